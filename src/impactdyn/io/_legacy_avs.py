"""The legacy CTH dump ``avsout``, as DC3D's RDAVS reads it (Fahrenthold 1994, App. G).

Layout (RDAVS):

* 27 header lines, skipped (``read(2,901) chdum`` 27 times);
* then two records per cell, Fortran ``7e11.3``::

      vx  vy  vz  p  T  rho  e        (cm/s, cm/s, cm/s, dyn/cm², K, g/cm³, erg/g)
      mass  phi  c                    (g, void fraction, cm/s)

  cells in the order ``do k / do j / do i`` — k outermost, i innermost — over the
  (i2−i1+1) × (j2−j1+1) × (k2−k1+1) cells given by dc3din.

The dump does not say where its cells are: dc3din does (records ``i1 i2``,
``j1 j2``, ``k1 k2``, ``xlow Δx``, ...; :class:`AvsLayout`).  Absolute CTH cell i
has its lower node at ``x_i = xlow + (i − 2) Δx`` (CTH's first real cell is i = 2).
The velocities are face-centred (RDAVS's nodal averaging, see
:meth:`HydroGrid.nodal_velocities`), so the grid read is ``staggered``.

Units are converted on reading, through :mod:`impactdyn.units`: velocities and
sound speed ÷ 1e6 (cm/µs), pressure ÷ 1e12 (Mbar), specific energy ÷ 1e12
(cm²/µs²).  RDAVS converted only velocities and pressure; it did not use the
others.  Temperature is kept as written (kelvin: the CTH plot input of App. A
selects ``units cgsk``).

The writer produces the same layout, with 3 significant digits per value
(``e11.3``).  Its header lines carry the layout and the time as ``key = value``
lines, which RDAVS skips, so ``read_avsout(path)`` needs no dc3din for such a
file; for a CTH dump pass the layout from dc3din (:attr:`Dc3dInput.avs_layout`).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from impactdyn import units
from impactdyn._config import MAX_REACH
from impactdyn._errors import InputError
from impactdyn.hydrogrid import HydroGrid, check_cells
from impactdyn.io._cell_block import BLOCK_FIELDS, INDEX_FIELDS, INDEX_RANGES, MESH_FIELDS, CellBlock
from impactdyn.io._fortran import format_e, parse_real, read_lines, record_fields
from impactdyn._runfolder import atomic_output
from impactdyn.io._registry import register_format

HEADER_LINES = 27
FIELD_WIDTH = 11
_RECORD1 = ("vx", "vy", "vz", "p", "T", "rho", "e")
_RECORD2 = ("mass", "phi", "c")
_PER_CELL = len(_RECORD1) + len(_RECORD2)
_KEY_LINE = re.compile(r"^\s*([A-Za-z_]\w*)\s*=\s*(\S+)\s*$")
_RECORD2_FIELDS = ("mass", "void_fraction", "sound_speed")  # the HydroGrid fields of the second record
_CELL_ERROR = re.compile(r"HydroGrid\.(\w+): .* at index \((\d+), (\d+), (\d+)")


@dataclass(frozen=True)
class AvsLayout(CellBlock):
    """Where the dump's cells lie in the CTH mesh (dc3din records 2–7): a :class:`CellBlock`
    (its fields), checked on construction (an :class:`InputError` for a block that cannot be a dump).
    """

    def __post_init__(self) -> None:
        for a, b in INDEX_RANGES:
            lo, hi = getattr(self, a), getattr(self, b)
            if not (1 <= lo <= hi):
                raise InputError(f"avsout layout: need 1 <= {a} <= {b}, got {a} = {lo}, {b} = {hi}")
        for name in MESH_FIELDS:
            v = getattr(self, name)
            if not np.isfinite(v) or (name.startswith("d") and v <= 0):
                raise InputError(f"avsout layout: {name} = {v} must be finite" + (" and > 0" if name[0] == "d" else ""))
        check_cells(f"avsout layout: {self.i1}..{self.i2} x {self.j1}..{self.j2} x {self.k1}..{self.k2}",
                    self.shape)
        for axis, nodes, d in zip("xyz", self.nodes(), (self.dx, self.dy, self.dz)):
            if not np.abs(nodes[[0, -1]]).max() <= MAX_REACH * d:
                raise InputError(f"avsout layout: the {axis} nodes reach {nodes[0]:g} .. {nodes[-1]:g}, more than "
                                 f"{MAX_REACH} cells of d{axis} = {d:g} from the origin (they would not be distinct)")

    def nodes(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Node coordinates x (nx+1,), y, z: ``x_l = xlow + (i1 + l − 2) Δx`` (RDAVS), cm."""
        return tuple(low + (first + np.arange(n + 1) - 2) * d
                     for low, first, n, d in zip((self.xlow, self.ylow, self.zlow), (self.i1, self.j1, self.k1),
                                                 self.shape, (self.dx, self.dy, self.dz)))

    @classmethod
    def from_values(cls, values: dict[str, float | int], where: str) -> "AvsLayout":
        """The layout of the twelve ``values`` read from a file, by field name; an :class:`InputError`
        begins with ``where``, the file and lines that gave them."""
        try:
            return cls(**{name: values[name] for name in BLOCK_FIELDS})
        except InputError as err:
            raise InputError(f"{where}: {err}") from None

    @classmethod
    def of_grid(cls, grid: HydroGrid) -> "AvsLayout":
        """The layout of a uniform grid, numbered from CTH's first real cell (i1 = j1 = k1 = 2)."""
        (nx, ny, nz), (x, y, z) = grid.shape, (grid.x, grid.y, grid.z)
        layout = cls(2, nx + 1, 2, ny + 1, 2, nz + 1, x[0], (x[-1] - x[0]) / nx,
                     y[0], (y[-1] - y[0]) / ny, z[0], (z[-1] - z[0]) / nz)
        layout.check_grid(grid)
        return layout

    def check_grid(self, grid: HydroGrid) -> None:
        """InputError unless ``grid`` has this layout's cells and (uniform) nodes."""
        if grid.shape != self.shape:
            raise InputError(f"avsout layout: {self.shape} cells, grid has {grid.shape}")
        for name, want, have, d in zip("xyz", self.nodes(), (grid.x, grid.y, grid.z), (self.dx, self.dy, self.dz)):
            if np.max(np.abs(want - have)) > 1e-9 * d:
                raise InputError(f"avsout layout: the grid's {name} nodes are not xlow + (i - 2) * d{name} "
                                 "(avsout holds uniform grids only)")


def read_avsout(path: str | Path, layout: AvsLayout | None = None, time: float | None = None) -> HydroGrid:
    """Read an avsout dump into a staggered HydroGrid (internal units).

    ``layout``: the grid from dc3din; None reads it from the header (files written
    by :func:`write_avsout`).  ``time`` (µs): None takes the header's ``time_us``,
    else 0.
    """
    path = Path(path)
    lines = read_lines(path)
    if len(lines) < HEADER_LINES:
        raise InputError(f"{path}:{len(lines)}: truncated: the header has {HEADER_LINES} lines, "
                         f"the file ends after {len(lines)}")
    header = _header_values(lines[:HEADER_LINES])
    if layout is None:
        layout = _layout_from_header(path, header)
    if time is None:
        time = header.get("time_us", (0.0, 0))[0]
    nx, ny, nz = layout.shape
    values, records = _read_values(path, lines, nx * ny * nz, layout)
    cells = values.reshape(nz, ny, nx, _PER_CELL).transpose(2, 1, 0, 3)  # k outer, i inner -> (i, j, k)
    x, y, z = layout.nodes()
    try:
        return HydroGrid(
            x=x, y=y, z=z,
            velocity=units.cm_s_to_cm_us(cells[..., 0:3]),
            pressure=units.dyn_cm2_to_mbar(cells[..., 3]),
            temperature=cells[..., 4],
            density=cells[..., 5],
            specific_energy=units.erg_g_to_cm2_us2(cells[..., 6]),
            mass=cells[..., 7],
            void_fraction=cells[..., 8],
            sound_speed=units.cm_s_to_cm_us(cells[..., 9]),
            staggered=True,
            time=time,
        )
    except InputError as err:  # a cell's value out of range: the line of its record
        m = _CELL_ERROR.match(str(err))
        if m is None:
            raise InputError(f"{path}: {err}") from None
        i, j, k = map(int, m.group(2, 3, 4))
        record = 2 * (i + nx * (j + ny * k)) + (m.group(1) in _RECORD2_FIELDS)
        raise InputError(f"{path}:{records[record]}: {err}") from None


def write_avsout(path: str | Path, grid: HydroGrid, layout: AvsLayout | None = None) -> None:
    """Write a staggered, uniform HydroGrid as avsout (cgs, ``7e11.3``, 3 significant digits), atomically.

    ``layout`` places the block in a CTH mesh (default: cells numbered from 2).
    """
    with atomic_output(path) as tmp:
        _write(tmp, grid, layout)


def _write(path: Path, grid: HydroGrid, layout: AvsLayout | None = None) -> None:
    if not grid.staggered:
        raise InputError("avsout holds face-centred (staggered) velocities; this grid is cell-centred")
    if layout is None:
        layout = AvsLayout.of_grid(grid)
    else:
        layout.check_grid(grid)
    cells = np.concatenate([
        units.cm_us_to_cm_s(grid.velocity),
        units.mbar_to_dyn_cm2(grid.pressure)[..., None],
        grid.temperature[..., None],
        grid.density[..., None],
        units.cm2_us2_to_erg_g(grid.specific_energy)[..., None],
        grid.mass[..., None],
        grid.void_fraction[..., None],
        units.cm_us_to_cm_s(grid.sound_speed)[..., None],
    ], axis=-1).transpose(2, 1, 0, 3)  # (i, j, k) -> k outer, i inner
    text = format_e(cells.ravel(), FIELD_WIDTH, 3)
    w1, w = len(_RECORD1) * FIELD_WIDTH, _PER_CELL * FIELD_WIDTH
    body = [line for c in range(0, len(text), w) for line in (text[c:c + w1], text[c + w1:c + w])]
    with open(path, "w", encoding="ascii") as fh:
        fh.write("\n".join(_header_lines(layout, grid.time) + body) + "\n")


def _header_lines(layout: AvsLayout, time: float) -> list[str]:
    lines = [
        "impactdyn avsout: CTH cell dump in the layout DC3D's RDAVS reads (Fahrenthold 1994, App. G)",
        "27 header lines, then per cell two 7e11.3 records, cgs units:",
        "  vx vy vz p T rho e  /  mass phi c      (cells: k outer, j, i inner)",
        "the key = value lines give the grid (as dc3din does) and the time:",
    ]
    lines += [f"{k} = {getattr(layout, k)}" for k in INDEX_FIELDS]
    lines += [f"{k} = {float(getattr(layout, k))!r}" for k in MESH_FIELDS]
    lines.append(f"time_us = {float(time)!r}")
    return lines + ["*"] * (HEADER_LINES - len(lines))


def _header_values(header: list[str]) -> dict[str, tuple[float, int]]:
    """The ``key = number`` lines of the header: each key's value and line."""
    out = {}
    for no, line in enumerate(header, start=1):
        m = _KEY_LINE.match(line)
        if m:
            try:
                out[m.group(1)] = (parse_real(m.group(2)), no)
            except ValueError:
                continue  # free text that happens to contain '='
    return out


def _layout_from_header(path: Path, header: dict[str, tuple[float, int]]) -> AvsLayout:
    missing = [k for k in BLOCK_FIELDS if k not in header]
    if missing:
        raise InputError(f"{path}:{HEADER_LINES}: the header (lines 1-{HEADER_LINES}) does not give the grid layout "
                         f"({', '.join(missing)} missing); a CTH dump needs the layout from dc3din: "
                         "read_avsout(path, Dc3dInput.avs_layout)")
    for k in INDEX_FIELDS:
        value, no = header[k]
        if not value.is_integer():
            raise InputError(f"{path}:{no}: {k} = {value!r} must be an integer")
    where = sorted(header[k][1] for k in BLOCK_FIELDS)
    return AvsLayout.from_values({k: int(header[k][0]) if k in INDEX_FIELDS else header[k][0] for k in BLOCK_FIELDS},
                          f"{path}:{where[0]}-{where[-1]}")


def _read_values(path: Path, lines: list[str], n_cells: int, layout: AvsLayout) -> tuple[np.ndarray, list[int]]:
    """The 10 values of each cell in file order, shape (n_cells * 10,), and the line of each record."""
    data = [(n, line) for n, line in enumerate(lines[HEADER_LINES:], start=HEADER_LINES + 1) if line.strip()]
    need = 2 * n_cells
    grid = (f"the {layout.i1}..{layout.i2} x {layout.j1}..{layout.j2} x {layout.k1}..{layout.k2} cell block "
            f"of dc3din needs {need} records")
    if len(data) < need:
        raise InputError(f"{path}:{len(lines)}: truncated: {len(data)} data records, {grid}")
    if len(data) > need:
        raise InputError(f"{path}:{data[need][0]}: wrong record count: {len(data)} data records, {grid}")
    tokens: list[str] = []
    for r, (n, line) in enumerate(data):
        count = len(_RECORD2) if r % 2 else len(_RECORD1)
        fields = line.split()
        if len(fields) != count:
            try:
                fields = record_fields(line, count, FIELD_WIDTH)
            except ValueError as err:
                names = " ".join(_RECORD2 if r % 2 else _RECORD1)
                raise InputError(f"{path}:{n}: {err} (record '{names}' of cell {r // 2 + 1})") from None
        tokens.extend(fields)
    try:
        values = np.array(tokens, dtype=np.float64)
    except ValueError:  # Fortran exponents (D, or no letter) or a non-numeric field
        values = np.empty(len(tokens))
        for m, tok in enumerate(tokens):
            try:
                values[m] = parse_real(tok)
            except ValueError as err:
                raise InputError(f"{path}:{_line_of(data, m)}: {err}") from None
    bad = ~np.isfinite(values)
    if bad.any():
        m = int(np.argmax(bad))
        raise InputError(f"{path}:{_line_of(data, m)}: not a finite number: {tokens[m]!r}")
    return values, [n for n, _ in data]


def _line_of(data: list[tuple[int, str]], value_index: int) -> int:
    cell, r = divmod(value_index, _PER_CELL)
    return data[2 * cell + (r >= len(_RECORD1))][0]


register_format("avsout", ("avsout", ".avsout"), reader=read_avsout, writer=_write)
