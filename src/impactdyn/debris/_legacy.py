"""``impactdyn debris legacy``: the 1994 workflow from ``dc3din`` (+ ``avsout``).

The dc3din records become a :class:`DebrisCase` (written as ``config.resolved.toml``
next to ``handoff_grid.h5``, so the run can be repeated with ``debris run``):

* material μ, λ, ρ_ref, η, ζ (records 13–14).  The listing's η is per unit volume
  (``legacy.eta_per_volume``, docs/theory/debris.md, the listing's errata), so that flag is set: the number in dc3din
  means what DC3D made of it.
* filters tcut, tmin, dencut (record 8); the wall grid (records 9–12); the new
  wall grid as ``wall.remap`` when it differs from the old one; integrator eps and
  ymxref (record 14); DCPOST's factor scales the DYNA3D deck's cards.
* ``listing=True`` also switches on every other listing deviation and the
  listing's integrator (RK4 step doubling).

Run types (:class:`impactdyn.io.RunType`): 2/1 propagates, deposits and writes
both decks; 2/2 and 2/3 write the wall decks only (old or new wall grid); 1/1
propagates the particles in the arrival window for 0.2 µs (the listing's delt)
and writes CTH rezone packages (``cth_packages.txt``).
"""

from __future__ import annotations

import re
import time
from pathlib import Path

import numpy as np

from impactdyn import units
from impactdyn._config import set_dotted, validate
from impactdyn._errors import InputError
from impactdyn._runfolder import RunFolder, check_target
from impactdyn.debris._deposit import arrival_points
from impactdyn.debris._particle import F_SLICE, P_SLICE
from impactdyn.io import RunType, read_avsout, read_dc3din

#: Propagation time of itype 1 (CTH rezone), µs (DCELEM: delt = 0.2).
REZONE_TIME_US = 0.2


FROM_RECORDS: dict[str, tuple[str, ...]] = {
    "material.mu_Mbar": ("mu",), "material.lambda_Mbar": ("lam",), "material.rho_ref_g_cm3": ("rho_ref",),
    "material.eta_Mbar_us": ("eta",), "material.zeta_Mbar_us": ("zeta",),
    "filter.dencut": ("dencut",), "filter.t_min_us": ("tmin",), "filter.t_cut_us": ("tcut",),
    "wall.x_cm": ("xdmin", "xdmax"), "wall.y_cm": ("ydmin", "ydmax"), "wall.z_cm": ("zdmin", "zdmax"),
    "wall.nodes": ("idmax", "jdmax", "kdmax"),
    "integrator.eps": ("eps",), "integrator.ymxref": ("ymxref",),
}
"""The keys of the DebrisCase a dc3din becomes, and the dc3din fields that give each (a list where
there are several)."""

REMAP_FROM_RECORDS: dict[str, tuple[str, ...]] = {
    "wall.remap.x_cm": ("xdminn", "xdmaxn"), "wall.remap.z_cm": ("zdminn", "zdmaxn"),
    "wall.remap.nodes": ("idmaxn", "kdmaxn"),
}
"""The same for the new wall grid, a 2/1 run's remap face where it differs from the old grid."""


def case_from_dc3din(d, listing: bool = False) -> dict:
    """The DebrisCase dict equivalent to a :class:`Dc3dInput` (grid.file = handoff_grid.h5)."""
    case = {
        "title": f"dc3din itype {d.itype} jtype {d.jtype}",
        "grid": {"file": "handoff_grid.h5"},
        "wall": {"clamped_edges": False},
        "integrator": {"method": "legacy"} if listing else {},
        "legacy": {"eta_per_volume": True} | (
            {k: True for k in ("nddata_swap", "fdot_scaling", "inertia_transform", "abs_arrival",
                               "vertex_scaling")} if listing else {}),
    }
    new = ((d.xdminn, d.xdmaxn), (d.zdminn, d.zdmaxn), (d.idmaxn, d.kdmaxn))
    remap = d.run_type is RunType.PROPAGATE_TO_WALL and new != ((d.xdmin, d.xdmax), (d.zdmin, d.zdmax),
                                                                (d.idmax, d.kdmax))
    for key, names in (FROM_RECORDS | (REMAP_FROM_RECORDS if remap else {})).items():
        values = [getattr(d, name) for name in names]
        case = set_dotted(case, key, values if len(values) > 1 else values[0])
    return case


def _record_line(d, key: str) -> int | None:
    """The dc3din line that holds the value of the case's ``key`` (of a table's first key, for a rule of
    the table's); None for a key no record gives."""
    base = re.sub(r"\[\d+\]$", "", key)
    table = FROM_RECORDS | REMAP_FROM_RECORDS
    keys = [k for k in table if k == base or k.startswith(base + ".")]
    return d.lines.get(table[keys[0]][0]) if keys else None


def run_legacy(dc3din: Path, avsout: Path | None, out: Path, *, force: bool = False, listing: bool = False,
               progress_factory=None, echo=print, report=None) -> dict:
    """Run the workflow of ``dc3din``'s run type; returns the summary written."""
    from impactdyn.debris._case import DebrisCase, build, check_seeding, remap_grid
    from impactdyn.debris._propagate import run_debris
    from impactdyn.debris._outputs import write_debris_run

    check_target(out, force)
    start = time.perf_counter()
    d = read_dc3din(dc3din)
    kind = d.run_type
    case = validate(DebrisCase, case_from_dc3din(d, listing), source=str(dc3din),
                    line_of=lambda key: _record_line(d, key))
    if not kind.propagates:
        return _decks_only(d, case, out, force, echo)
    if avsout is None:
        raise InputError(f"{dc3din}: run type {d.itype}/{d.jtype} propagates the debris: give the avsout file")
    grid = read_avsout(avsout, d.avs_layout)
    check_seeding(case, grid, f"{dc3din}:{d.lines['i1']}-{d.lines['k1']}: records i1 i2, j1 j2, k1 k2 (the avsout "
                  "cells)", f"{dc3din}:{d.lines['ydmin']}: ydmin", f"{avsout} (placed by records ylow dy, line "
                  f"{d.lines['ylow']})")
    args = build(case, str(dc3din), grid=grid)
    bar, update = progress_factory() if progress_factory else (None, None)
    if kind is RunType.CTH_REZONE:
        return _rezone(args, case, out, force, start, echo)
    if bar is not None:
        with bar:
            result = run_debris(**args, progress=update)
    else:
        result = run_debris(**args)
    summary = write_debris_run(result, case, out, force=force, remap=remap_grid(case), dcpost_factor=d.factor,
                               extra_summary={"title": case.title, "run_type": f"{d.itype}/{d.jtype}",
                                              "wall_time_s": time.perf_counter() - start})
    if report:
        report(summary, out)
    return summary


def _decks_only(d, case, out: Path, force: bool, echo) -> dict:
    """Run types 2/2 and 2/3: DYNGEN's wall deck (and the keyword deck) on the old or new wall grid."""
    from impactdyn._config import dump_toml
    from impactdyn.materials import AL_6061_T6_MAT13
    from impactdyn.io import write_dyna3d_deck, write_lsdyna_deck

    wall = d.dyngen_wall
    with RunFolder(out, force=force) as rf:
        rf.write_text("config.resolved.toml", dump_toml(case))
        write_dyna3d_deck(rf.file("wall_dyna3d.inp"), wall, AL_6061_T6_MAT13)
        write_lsdyna_deck(rf.file("wall.k"), wall, AL_6061_T6_MAT13, clamped_edges=False)
        summary = {"title": case.title, "run_type": f"{d.itype}/{d.jtype}", "wall_nodes": wall.n_nodes,
                   "wall_elements": wall.n_elements,
                   "files": ["config.resolved.toml", "summary.json", "wall.k", "wall_dyna3d.inp"]}
        rf.write_json("summary.json", summary)
    echo(f"wall deck only ({d.itype}/{d.jtype}): {wall.n_nodes + 8} nodes, {wall.n_elements + 1} elements "
         f"(DYNA3D, with the backing element); results in {out}")
    return summary


def cth_packages(cloud, states: np.ndarray, rho_ref: float) -> dict[str, np.ndarray]:
    """The rezone packages of CTHOUT (itype = 1) for particles ``cloud`` in ``states (N, 33)``.

    ρ_out = ρ_ref / det F, velocity p/m in cm/s, and the corners c + s F (x_k⁰ − c⁰) with
    s = ((1 − φ) ρ/ρ_ref)^{1/3}, which shrinks the tetrahedron so that ρ_out times its volume
    is the particle's mass (the listing's c3).  (The listing skips the ``+ c`` with a ``go to
    301`` whose label is commented out in the OCR; a pyramid about the origin is meaningless,
    so the centroid is added.)  Keyword arguments of :func:`impactdyn.io.write_cth_packages`.
    """
    detF = np.linalg.det(states[:, F_SLICE].reshape(-1, 3, 3))
    return {"index": np.column_stack([cloud.cell + 1, cloud.tet + 1]),
            "density": rho_ref / detF,
            "velocity_cm_s": units.cm_us_to_cm_s(states[:, P_SLICE] / cloud.mass[:, None]),
            "corners": arrival_points(states, cloud.vertices,
                                      np.cbrt((1.0 - cloud.void_fraction) * cloud.density_ratio))[:, :4]}


def _rezone(args: dict, case, out: Path, force: bool, start: float, echo) -> dict:
    """Run type 1/1: particles in the arrival window, propagated for 0.2 µs, as CTH rezone packages."""
    from impactdyn._config import dump_toml
    from impactdyn.debris._propagate import propagate_chunked, seed_and_select
    from impactdyn.io import write_cth_packages, write_grid

    cloud, _, selected = seed_and_select(args["grid"], args["wall"], args["material"], args["seed_filter"],
                                         args["seed_options"], args["window"])
    moving = cloud.subset(selected)
    states, stats = propagate_chunked(moving, np.full(len(moving), REZONE_TIME_US), args["material"],
                                      args["integrator"], args["compute"])
    with RunFolder(out, force=force) as rf:
        rf.write_text("config.resolved.toml", dump_toml(case))
        write_grid(rf.file("handoff_grid.h5"), args["grid"])
        write_cth_packages(rf.file("cth_packages.txt"), **cth_packages(moving, states, args["material"].rho_ref))
        summary = {"title": case.title, "run_type": "1/1", "n_particles": len(cloud), "n_packages": len(moving),
                   "rezone_time_us": REZONE_TIME_US, "n_failed": stats.n_failed,
                   "failures": stats.failure_counts(), "wall_time_s": time.perf_counter() - start,
                   "files": ["config.resolved.toml", "cth_packages.txt", "handoff_grid.h5", "summary.json"]}
        rf.write_json("summary.json", summary)
    echo(f"{len(moving)} CTH rezone packages ({REZONE_TIME_US} µs of propagation); results in {out}")
    return summary
