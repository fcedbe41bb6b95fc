"""LS-DYNA keyword deck of the rear wall, loaded by the time-resolved deposition.

Units cm, g, µs (LS-DYNA is unit-consistent): density g/cm³, stress Mbar, force
g·cm/µs² (= 1e7 N), impulse g·cm/µs.  Standard fixed-column cards (LS-DYNA
Keyword User's Manual): 10-column fields, except *NODE (NID i8, X Y Z 3×16, TC RC
i8), *ELEMENT_SOLID (EID PID N1–N8, 10×i8, the one-card form) and the
*DEFINE_CURVE points (A O, 2×20, in E20.12 form: 13 significant digits).  Other
reals take as many significant digits as their field holds after one leading blank.

Deck: *KEYWORD, *TITLE, *CONTROL_TERMINATION, *CONTROL_HOURGLASS and
*CONTROL_BULK_VISCOSITY (when given: the wall stage's settings, so the FE code runs the
same numerics), *DATABASE_BINARY_D3PLOT, *PART, *SECTION_SOLID (ELFORM 1), the material
(and its *EOS_GRUNEISEN), *NODE, *ELEMENT_SOLID (numbering of :class:`WallGrid`,
DYNGEN's), *BOUNDARY_SPC_NODE, the loads, *END.

Material: *MAT_ISOTROPIC_ELASTIC_FAILURE (MAT_013), the LS-DYNA descendant of the
report's DYNA3D type 13 and the model of :mod:`impactdyn.wall`'s ``mat13``, card for
card from a :class:`Mat13Card`: MID RO G SIGY ETAN BULK, then EPF PRF REM TREM with
ETAN the plastic hardening modulus E_h (not the bilinear slope), EPF the effective
plastic strain at failure (blank if 0: no failure), PRF the failure pressure written
explicitly (≤ 0; the report's −1.2e34 Mbar means none), REM = 1 (a failed element
is kept, carrying only compressive pressure, as in DYNA3D; 0 would erode it) and
TREM = 0.  The default is the report's wall, :data:`AL_6061_T6_MAT13`.

Or, given a library :class:`Material` with Johnson–Cook constants (the wall stage's
``johnson_cook`` model): *MAT_JOHNSON_COOK (MAT_015) — MID RO G; A B N C M TM TR EPSO;
CP PC SPALL IT D1–D4; D5 — with PC = −p_spall and SPALL = 3 (the element spalls when
the pressure falls below PC, the wall stage's criterion), the JC damage constants of
:attr:`~impactdyn.materials.Material.johnson_cook_damage` in Johnson & Cook's convention (σ* the
mean stress over the effective stress; LS-DYNA's D1–D5 are entered as in their paper),
EROD and EFMIN the wall stage's (failed elements keep compressive pressure, EROD 1, and the
fracture strain its floor, :mod:`impactdyn.wall._johnson_cook`); the wall stage's default
Tuler–Butcher spall law has no *MAT_015 form, so the deck's spall is the cut-off PC; and *EOS_GRUNEISEN
(MAT_015 needs an EOS): C = c₀, S1 = s, S2 = S3 = 0, GAMA0 = Γ₀, A = 0, E0 = 0, V0 = 1 —
the shield stage's Mie–Grüneisen form p = p_H(μ) + Γ₀ρ₀e referred to the Hugoniot.

Supports: :meth:`WallGrid.constrained_dofs` — x fixed on the symmetry plane
x = x[0], and by default (``clamped_edges=True``) all translations fixed on the
other three edges, through the thickness.

Loads — the choice: each deposition record (face cell, time t, impulse I) is a force
pulse, triangular over [t, t + ``pulse_width``] with ∫F dt = I (peak 2I/w at mid-pulse).
The pulses of one face cell add up into one *DEFINE_CURVE per direction, and
*LOAD_NODE_POINT cards (DOF 1, 2, 3) share that curve among the front-face nodes under
the cell with scale factors SF: its four corners, a quarter each, on the grid the records
are on; on a finer mesh of the wall stage (``deposition_grid`` the case's grid, ``wall``
the mesh, :func:`impactdyn.wall.solver_mesh`) each of the mesh's face cells the case's cell
overlaps takes the share of its area, in quarters to its corners — the load the wall
stage puts on the front face.  A curve per cell, not per node: a shot deposits ~10⁶
records on a few thousand cells, and a node's curve would repeat the pulses of every cell
around it (the 7a deck on the graded mesh: 833 MB per node, per cell a quarter of that).
The SFs are written to their 10-column field's 7 digits and the curve is divided by
their sum as written, so a cell's curves carry its impulse exactly (to the ordinates'
~13 digits).  A load history keeps the arrival times the debris propagation computed;
*INITIAL_VELOCITY_NODE would put all momentum in at t = 0 and into the nodal masses
only.  The abscissae are rounded to what their field can hold *before* the peaks are
computed.  Each curve starts and ends with a flat zero segment, so LS-DYNA's
extrapolation past its ends stays 0.  ``pulse_width`` should be of the order of a debris
particle's contact time (size / speed: 0.03 cm / 0.6 cm/µs ≈ 0.05 µs, the default).

:func:`read_lsdyna_deck` reads back what this module writes (nodes, solids,
SPCs, curves, point loads), for tests and checks.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from impactdyn._config import Positive, checked
from impactdyn._errors import InputError
from impactdyn.materials import AL_6061_T6_MAT13, Mat13Card, Material
from impactdyn.wallgrid import WallDeposition, WallGrid, face_overlaps
from impactdyn.io._fortran import parse_int, parse_real, read_lines
from impactdyn._runfolder import atomic_output


@dataclass(frozen=True, eq=False)
class LsDynaDeck:
    """What :func:`read_lsdyna_deck` finds.

    node_ids (n,), coordinates (n, 3); solid_ids (m,), solid_parts (m,),
    solid_nodes (m, 8); spc_nodes (s,), spc_dofs (s, 3) bool; curves: LCID ->
    (abscissae (p,), ordinates (p,)) with SFA/SFO/OFFA/OFFO applied;
    point_loads (q, 3) int (NID, DOF, LCID) with point_load_scale (q,); cards: the numeric
    cards of the other keywords (*CONTROL_*, *MAT_*, *EOS_*, *SECTION_SOLID) as
    keyword -> rows of eight 10-column reals (blank: 0).
    """

    node_ids: np.ndarray
    coordinates: np.ndarray
    solid_ids: np.ndarray
    solid_parts: np.ndarray
    solid_nodes: np.ndarray
    spc_nodes: np.ndarray
    spc_dofs: np.ndarray
    curves: dict[int, tuple[np.ndarray, np.ndarray]]
    point_loads: np.ndarray
    point_load_scale: np.ndarray
    cards: dict[str, list[list[float]]]


@checked
def write_lsdyna_deck(path: str | Path, wall: WallGrid, material: Mat13Card | Material = AL_6061_T6_MAT13,
                      deposition: WallDeposition | None = None, *, pulse_width: Positive = 0.05,
                      end_time: Positive = 30.0, clamped_edges: bool = True,
                      title: str = "impactdyn rear wall under debris-cloud deposition",
                      hourglass: tuple[int, float] | None = None,
                      bulk_viscosity: tuple[float, float] | None = None,
                      failure_strain_floor: float | None = None, erode_failed: bool = True,
                      deposition_grid: WallGrid | None = None) -> None:
    """Write the keyword deck (module docstring), atomically.  Times in µs.

    hourglass : (IHQ, QH) of *CONTROL_HOURGLASS; bulk_viscosity : (Q1, Q2) of
    *CONTROL_BULK_VISCOSITY (quadratic, linear); None leaves LS-DYNA's defaults.
    failure_strain_floor, erode_failed : *MAT_JOHNSON_COOK's EFMIN (None: LS-DYNA's 1e-6) and
    EROD (0: failed elements erode, 1: they keep compressive pressure), the wall stage's
    fracture-strain floor and erosion (a type-13 card ignores them).
    deposition_grid : the grid whose face cells the records are on (None: ``wall``'s own), spanning
    the same rectangle as ``wall``: the case's grid under a finer mesh of the wall stage.
    """
    if deposition is not None:
        deposition.check_fits(wall if deposition_grid is None else deposition_grid)
    lines = ["*KEYWORD", "*TITLE", title[:80],
             "$ units: cm, g, us; stress Mbar; force g*cm/us^2 = 1e7 N; impulse g*cm/us",
             "*CONTROL_TERMINATION", _row([end_time])]
    if hourglass is not None:
        lines += ["*CONTROL_HOURGLASS", "$      IHQ        QH", _row([int(hourglass[0]), float(hourglass[1])])]
    if bulk_viscosity is not None:
        lines += ["*CONTROL_BULK_VISCOSITY", "$       Q1        Q2", _row([float(q) for q in bulk_viscosity])]
    lines += ["*DATABASE_BINARY_D3PLOT", _row([end_time / 100.0])]
    lines += _material_cards(material, failure_strain_floor, erode_failed) + ["*NODE"]
    xyz = wall.node_coordinates()
    lines += [_field(n, 8) + "".join(_field(c, 16) for c in p) for n, p in enumerate(xyz, start=1)]
    lines.append("*ELEMENT_SOLID")
    lines += [_field(e, 8) + _field(1, 8) + "".join(_field(n, 8) for n in c)
              for e, c in enumerate(wall.element_nodes(), start=1)]
    fixed = wall.constrained_dofs(clamped_edges)
    lines.append("*BOUNDARY_SPC_NODE")
    lines += [_row([n + 1, 0, *f.astype(int), 0, 0, 0]) for n, f in enumerate(fixed) if f.any()]
    if deposition is not None and deposition.element.size:
        lines += _load_cards(wall, deposition, pulse_width, wall if deposition_grid is None else deposition_grid)
    lines.append("*END")
    with atomic_output(path) as tmp:
        tmp.write_text("\n".join(lines) + "\n", encoding="ascii")


def _material_cards(m: Mat13Card | Material, efmin: float | None = None, erode: bool = True) -> list[str]:
    """*PART, *SECTION_SOLID and the material (module docstring): MAT_013 for a type-13 card,
    MAT_015 with *EOS_GRUNEISEN for a Johnson–Cook library material."""
    cards = ["*SECTION_SOLID", _row([1, 1])]
    if isinstance(m, Mat13Card):
        return ["*PART", "wall", _row([1, 1, 1])] + cards + [
            "*MAT_ISOTROPIC_ELASTIC_FAILURE",
            "$      MID        RO         G      SIGY      ETAN      BULK",
            _row([1, m.density, m.shear_modulus, m.yield_stress, m.hardening_modulus, m.bulk_modulus]),
            "$      EPF       PRF       REM      TREM",
            _row([m.failure_strain if m.failure_strain > 0 else None, m.failure_pressure, 1.0, 0.0])]
    jc = m.johnson_cook
    if jc is None:
        raise InputError(f"material {m.name!r}: no Johnson-Cook constants for *MAT_JOHNSON_COOK")
    d = m.johnson_cook_damage
    damage = [d.D1, d.D2, d.D3, d.D4] if d is not None else [None] * 4
    pc = -m.spall_strength if m.spall_strength is not None else None
    return ["*PART", "wall", _row([1, 1, 1, 1])] + cards + [
        "*MAT_JOHNSON_COOK",
        "$      MID        RO         G         E        PR",
        _row([1, m.rho0, m.shear_modulus]),
        "$        A         B         N         C         M        TM        TR      EPSO",
        _row([jc.A, jc.B, jc.n, jc.C, jc.m, jc.t_melt, jc.t_room, jc.reference_strain_rate]),
        "$       CP        PC     SPALL        IT        D1        D2        D3        D4",
        _row([m.specific_heat, pc, 3.0 if pc is not None else None, 0.0, *damage]),
        "$       D5      C2/P      EROD     EFMIN",
        _row([d.D5 if d is not None else None, None, 0.0 if erode else 1.0, efmin]),
        "*EOS_GRUNEISEN",
        "$    EOSID         C        S1        S2        S3     GAMA0         A        E0",
        _row([1, m.c0, m.s, 0.0, 0.0, m.gamma0, 0.0, 0.0]),
        "$       V0",
        _row([1.0])]


def _load_cards(wall: WallGrid, dep: WallDeposition, width: float, source: WallGrid) -> list[str]:
    """*DEFINE_CURVE per loaded cell of ``source`` and direction, and the *LOAD_NODE_POINT cards that
    share it among ``wall``'s front-face nodes (``width`` > 0, µs; module docstring)."""
    a = _as_written(dep.time)
    b = _as_written(dep.time + width)
    mid = _as_written(0.5 * (a + b))
    if not np.all((a < mid) & (mid < b)):
        raise InputError(f"pulse_width = {width} µs is below the resolution of the arrival times as written")
    order = np.argsort(dep.element, kind="stable")
    cells, starts = np.unique(dep.element[order], return_index=True)
    curves, loads, lcid = [], [], 0
    for recs, (fine, share) in zip(np.split(order, starts[1:]), face_overlaps(source, wall, cells)):
        t, force = _pulse_sum(a[recs], mid[recs], b[recs], dep.impulse[recs])
        t_all = np.concatenate([[t[0] - width], t, [t[-1] + width]])  # flat zero ends
        nodes, at = np.unique(wall.face_element_nodes(fine).ravel(), return_inverse=True)
        weight = np.bincount(at, np.repeat(0.25 * share, 4), nodes.size)
        written = np.array([float(_field(w, 10)) for w in weight])
        for dof in range(3):
            if not force[:, dof].any():
                continue
            lcid += 1
            # the node shares as their 10-column fields hold them: the curve carries 1/Σ of them,
            # so the cell's impulse is kept to the ordinates' digits, not the shares'
            f_all = np.concatenate([[0.0], force[:, dof], [0.0]]) / written.sum()
            curves += ["*DEFINE_CURVE", _row([lcid, 0, 1.0, 1.0, 0.0, 0.0])]
            curves += _points(t_all, f_all)
            loads += [_row([int(n), dof + 1, lcid, float(w)]) for n, w in zip(nodes, written)]
    return curves + ["*LOAD_NODE_POINT"] + loads


def _pulse_sum(a: np.ndarray, mid: np.ndarray, b: np.ndarray, impulse: np.ndarray
               ) -> tuple[np.ndarray, np.ndarray]:
    """Sum of triangular pulses, pulse r over [a_r, b_r] peaking at mid_r with area impulse_r ``(R, 3)``.

    Returns the breakpoints t ``(P,)`` (every a, mid, b, sorted, unique) and the
    sum at them ``(P, 3)`` (exact between them: the sum is piecewise linear).  The
    slope changes at each breakpoint are accumulated, O(R log R); where no pulse
    is active the sum is set to exactly 0, so round-off never leaves a tail.
    """
    height = impulse * (2.0 / (b - a))[:, None]
    up, down = height / (mid - a)[:, None], height / (b - mid)[:, None]
    t, where = np.unique(np.concatenate([a, mid, b]), return_inverse=True)
    kink = np.zeros((t.size, 3))
    np.add.at(kink, where, np.concatenate([up, -up - down, down]))
    slope = np.cumsum(kink, axis=0)[:-1]
    force = np.concatenate([np.zeros((1, 3)), np.cumsum(slope * np.diff(t)[:, None], axis=0)])
    active = np.searchsorted(np.sort(a), t, "left") - np.searchsorted(np.sort(b), t, "right")
    force[active == 0] = 0.0
    return t, force


def read_lsdyna_deck(path: str | Path) -> LsDynaDeck:
    """Read the nodes, solids, SPCs, curves and point loads of a keyword deck (fixed or comma format)."""
    path = Path(path)
    blocks: list[tuple[str, list[tuple[int, str]]]] = []
    for n, line in enumerate(read_lines(path), start=1):
        if line.startswith("*"):
            blocks.append((line.strip().upper(), []))
        elif blocks and not line.startswith("$") and line.strip():
            blocks[-1][1].append((n, line))
    nodes, solids, spcs, loads, curves, cards = [], [], [], [], {}, {}
    for key, rows in blocks:
        if key == "*NODE":
            nodes += [_parse(path, n, line, "ieee", (8, 16, 16, 16)) for n, line in rows]
        elif key == "*ELEMENT_SOLID":
            solids += [_parse(path, n, line, "i" * 10, (8,) * 10) for n, line in rows]
        elif key == "*BOUNDARY_SPC_NODE":
            spcs += [_parse(path, n, line, "i" * 5, (10,) * 5) for n, line in rows]
        elif key == "*LOAD_NODE_POINT":
            loads += [_parse(path, n, line, "iiie", (10,) * 4) for n, line in rows]
        elif key == "*DEFINE_CURVE":
            if not rows:
                raise InputError(f"{path}: *DEFINE_CURVE without cards")
            lcid, _, sfa, sfo, offa, offo = _parse(path, *rows[0], "iieeee", (10,) * 6)
            pts = np.array([_parse(path, n, line, "ee", (20, 20)) for n, line in rows[1:]]).reshape(-1, 2)
            curves[lcid] = ((sfa or 1.0) * (pts[:, 0] + offa), (sfo or 1.0) * (pts[:, 1] + offo))
        elif key.startswith(("*CONTROL_", "*MAT_", "*EOS_", "*SECTION_")):
            cards[key] = [_parse(path, n, line, "e" * 8, (10,) * 8) for n, line in rows]
    nodes_a = np.array(nodes, dtype=float).reshape(-1, 4)
    solids_a = np.array(solids, dtype=np.int64).reshape(-1, 10)
    spcs_a = np.array(spcs, dtype=np.int64).reshape(-1, 5)
    loads_a = np.array(loads, dtype=float).reshape(-1, 4)
    return LsDynaDeck(
        node_ids=nodes_a[:, 0].astype(np.int64), coordinates=nodes_a[:, 1:],
        solid_ids=solids_a[:, 0], solid_parts=solids_a[:, 1], solid_nodes=solids_a[:, 2:],
        spc_nodes=spcs_a[:, 0], spc_dofs=spcs_a[:, 2:5].astype(bool),
        curves=curves, point_loads=loads_a[:, :3].astype(np.int64), point_load_scale=loads_a[:, 3], cards=cards)


def _parse(path: Path, n: int, line: str, kinds: str, widths: Sequence[int]) -> list:
    """The leading fields of a card (comma-separated or fixed columns); blank fields read as 0."""
    if "," in line:
        fields = line.split(",")
    else:
        edges = list(itertools.accumulate(widths, initial=0))
        fields = [line[lo:hi] for lo, hi in zip(edges[:-1], edges[1:])]
    fields = (fields + [""] * len(kinds))[:len(kinds)]
    try:
        return [(parse_int if k == "i" else parse_real)(f.strip() or "0") for k, f in zip(kinds, fields)]
    except ValueError as err:
        raise InputError(f"{path}:{n}: {err}") from None


def _row(values: Sequence) -> str:
    """A card of 10-column fields (None: blank)."""
    return "".join(" " * 10 if v is None else _field(v, 10) for v in values)


def _field(v, width: int) -> str:
    """An integer, or a real with as many significant digits as ``width`` − 1 columns hold.

    Reals keep a leading blank, so that neighbouring fields never touch.
    """
    if isinstance(v, (int, np.integer)):
        s = str(int(v))
    else:
        s = _fit(float(v), width - 1)
    if s is None or len(s) > width:
        raise ValueError(f"{v} does not fit a {width}-column field")
    return s.rjust(width)


def _fit(x: float, room: int) -> str | None:
    """``x`` in %g form with the most significant digits (≤ 17) that fit in ``room`` characters."""
    most = min(room - 1, 17)
    p, s = most, f"{x:.{most}g}"
    while len(s) > room and p > 1:  # one digit fewer per character over, then back up while it fits
        p = max(1, p - (len(s) - room))
        s = f"{x:.{p}g}"
    while p < most and len(wider := f"{x:.{p + 1}g}") <= room:
        p, s = p + 1, wider
    return s if len(s) <= room else None


def _point(t: float, f: float) -> str:
    """A *DEFINE_CURVE point card: two E20.12 fields (a wider exponent falls back to :func:`_field`)."""
    card = f"{t:20.12e}{f:20.12e}"
    if card[0] == " " and card[20] == " " and len(card) == 40:
        return card
    return _field(t, 20) + _field(f, 20)


def _points(t: np.ndarray, f: np.ndarray) -> list[str]:
    """The :func:`_point` cards of the pairs (t_i, f_i), t and f (n,): the same strings, formatted in
    one pass (the load curves of a shot's deck hold millions of points)."""
    t = np.asarray(t, dtype=float)
    f = np.asarray(f, dtype=float)
    if t.size == 0:
        return []
    pairs = np.column_stack([t, f]).ravel().tolist()
    cards = (("%20.12e%20.12e\n" * t.size) % tuple(pairs)).splitlines()
    for i in np.flatnonzero(~(_two_digit_exponent(t) & _two_digit_exponent(f))):
        cards[i] = _point(float(t[i]), float(f[i]))
    return cards


def _two_digit_exponent(x: np.ndarray) -> np.ndarray:
    """Where %.12e surely writes x with a two-digit exponent (0, or 1e-98 ≤ |x| < 1e99; not NaN/inf)."""
    a = np.abs(x)
    return (a == 0.0) | ((a >= 1e-98) & (a < 1e99))


def _as_written(values: np.ndarray) -> np.ndarray:
    """Curve abscissae rounded as :func:`_point` writes them."""
    values = np.asarray(values, dtype=float).ravel()
    return np.array([float(card[:20]) for card in _points(values, np.zeros(values.size))])
