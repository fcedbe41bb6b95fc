"""The DC3D input file ``dc3din`` (Fahrenthold 1994, App. C; read by DC3D and DCPOST, App. G, F).

Fixed layout, read by position as the Fortran does: three header lines, then a
comment line before each record (the Fortran formats ``(///2i10)``, ``(/2i10)``,
``(/2e15.6)``, ``(/3e15.3)``, ``(/6i10)``, ``(/4e15.3)`` skip them; their text is
free).  Records, with the DC3D main program's names:

====  ===========================================  =====  ===============================================
rec   fields                                       Fmt    meaning, unit
====  ===========================================  =====  ===============================================
1     itype jtype                                  2i10   what to run (:class:`RunType`)
2     i1 i2                                        2i10   CTH cells dumped in avsout along x (absolute
3     j1 j2                                        2i10   indices, first real cell 2), y, z
4     k1 k2                                        2i10
5     xlow Δx                                      2e15   CTH mesh lower x bound and cell size, cm
6     ylow Δy                                      2e15   (node of cell i: xlow + (i − 2) Δx)
7     zlow Δz                                      2e15
8     tcut tmin dencut                             3e15   keep particles arriving at the wall in
                                                          [tmin, tcut] µs with bulk density ratio
                                                          (1 − φ) ρ / ρ_ref ≥ dencut
9     idmax jdmax kdmax idmaxn jdmaxn kdmaxn       6i10   wall grid nodes along x, y (thickness), z;
                                                          same for the new (remap) wall grid
10    xdmin xdmax xdminn xdmaxn                    4e15   wall x bounds (old grid, new grid), cm
11    ydmin ydmax ydminn ydmaxn                    4e15   wall y bounds; the wall plane is ydmin, cm
12    zdmin zdmax zdminn zdmaxn                    4e15   wall z bounds, cm
13    mu lambda rho_ref eta                        4e15   Lamé constants μ, λ (Mbar), reference
                                                          density (g/cm³), plastic viscosity η
14    zeta eps ymxref                              3e15   bulk viscosity ζ (Mbar·µs), integrator
                                                          tolerance and floor of its running maxima
15    factor                                       e15    DCPOST's momentum scale factor (DCPOST only)
====  ===========================================  =====  ===============================================

η: the model's η (paper eq. 10a) is a viscosity, Mbar·µs; the listing divides
V₀·2μ(E' − Eₚ) by it, so a listing η is per volume (Mbar·cm³·µs; docs/theory/debris.md, the
listing's errata).

The factor record: DCPOST reads it with ``(////e15.3)`` right after the ζ record,
i.e. on the next line, while App. C shows a comment line before it.  Both are
accepted: a line starting with ``*`` there is taken as its comment.

Values are read tolerantly (whitespace-separated, else the fixed columns above);
a missing or non-numeric record or inconsistent values raise :class:`InputError`
naming the file and line.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum
from pathlib import Path

from impactdyn._errors import InputError
from impactdyn.hydrogrid import check_cells
from impactdyn.wallgrid import WallGrid, check_nodes
from impactdyn.io._cell_block import BLOCK_FIELDS, FIELD_PAIRS, INDEX_FIELDS, INDEX_RANGES, CellBlock
from impactdyn.io._fortran import read_lines, read_record
from impactdyn.io._legacy_avs import AvsLayout

HEADER_LINES = 3

#: Records 2–7: the cell block's fields in pairs, the indices ``2i10``, the mesh's bounds and cell sizes ``2e15``.
_BLOCK_RECORDS = tuple((pair, "ii", 10) if pair[0] in INDEX_FIELDS else (pair, "ee", 15) for pair in FIELD_PAIRS)

#: (field names, kinds 'i'/'e', Fortran field width) of each record, in file order.
_RECORDS = (
    (("itype", "jtype"), "ii", 10),
    *_BLOCK_RECORDS,
    (("tcut", "tmin", "dencut"), "eee", 15),
    (("idmax", "jdmax", "kdmax", "idmaxn", "jdmaxn", "kdmaxn"), "iiiiii", 10),
    (("xdmin", "xdmax", "xdminn", "xdmaxn"), "eeee", 15),
    (("ydmin", "ydmax", "ydminn", "ydmaxn"), "eeee", 15),
    (("zdmin", "zdmax", "zdminn", "zdmaxn"), "eeee", 15),
    (("mu", "lam", "rho_ref", "eta"), "eeee", 15),
    (("zeta", "eps", "ymxref"), "eee", 15),
    (("factor",), "e", 15),
)


class RunType(Enum):
    """What DC3D does for (itype, jtype) (main program, App. G; DCPOST, App. F)."""

    #: 2/1: propagate the debris to the wall, write the DYNA3D wall deck (old wall
    #: grid) and the momentum deposited per wall element.
    PROPAGATE_TO_WALL = (2, 1)
    #: 2/2: write the wall deck on the old wall grid only; no propagation.
    WALL_DECK = (2, 2)
    #: 2/3: write the wall deck on the new wall grid only; DCPOST maps deposition
    #: computed on the old grid onto the new grid's elements.
    WALL_DECK_NEW_GRID = (2, 3)
    #: 1 (jtype 1): propagate, and write the particles as CTH rezone packages
    #: (CTHOUT: one ``insert pyramid`` per particle).
    CTH_REZONE = (1, 1)

    @property
    def propagates(self) -> bool:
        return self.value[1] == 1

    @property
    def writes_wall_deck(self) -> bool:
        return self.value[0] == 2

    @property
    def uses_new_wall_grid(self) -> bool:
        return self is RunType.WALL_DECK_NEW_GRID


@dataclass(frozen=True)
class Dc3dInput(CellBlock):
    """The contents of a dc3din file; fields and units as in the module table.

    Records 2–7 are the fields of the :class:`CellBlock` (first in the field order), as read: they
    are checked as an :class:`AvsLayout` only where the run reads the avsout (:attr:`avs_layout`).
    """

    itype: int
    jtype: int
    tcut: float
    tmin: float
    dencut: float
    idmax: int
    jdmax: int
    kdmax: int
    idmaxn: int
    jdmaxn: int
    kdmaxn: int
    xdmin: float
    xdmax: float
    xdminn: float
    xdmaxn: float
    ydmin: float
    ydmax: float
    ydminn: float
    ydmaxn: float
    zdmin: float
    zdmax: float
    zdminn: float
    zdmaxn: float
    mu: float
    lam: float
    rho_ref: float
    eta: float
    zeta: float
    eps: float
    ymxref: float
    factor: float
    lines: dict[str, int] = field(default_factory=dict, compare=False, repr=False)
    """The line of the file read that holds each field."""

    @property
    def run_type(self) -> RunType:
        return RunType((self.itype, self.jtype))

    @property
    def avs_layout(self) -> AvsLayout:
        """Where the avsout cells lie (records 2–7)."""
        return AvsLayout(*(getattr(self, name) for name in BLOCK_FIELDS))

    @property
    def wall_grid(self) -> WallGrid:
        """The (old) wall grid: idmax × jdmax × kdmax nodes over the xd/yd/zd bounds."""
        return WallGrid.uniform((self.xdmin, self.xdmax), (self.ydmin, self.ydmax), (self.zdmin, self.zdmax),
                                (self.idmax, self.jdmax, self.kdmax))

    @property
    def new_wall_grid(self) -> WallGrid:
        """The new wall grid (the ``n`` fields), used with jtype 3."""
        return WallGrid.uniform((self.xdminn, self.xdmaxn), (self.ydminn, self.ydmaxn),
                                (self.zdminn, self.zdmaxn), (self.idmaxn, self.jdmaxn, self.kdmaxn))

    @property
    def dyngen_wall(self) -> WallGrid:
        """The grid DYNGEN writes the deck on: the new grid for jtype 3, else the old one."""
        return self.new_wall_grid if self.run_type.uses_new_wall_grid else self.wall_grid


def read_dc3din(path: str | Path) -> Dc3dInput:
    """Read and check a dc3din file."""
    path = Path(path)
    lines = read_lines(path)
    values: dict[str, float | int] = {}
    line_of: dict[str, int] = {}
    pos = HEADER_LINES  # 0-based index of the next data line
    for r, (names, kinds, width) in enumerate(_RECORDS):
        if r > 0:
            optional_comment = names == ("factor",)
            pos += 1 if not optional_comment or (pos < len(lines) and _is_comment(lines[pos])) else 0
        what = " ".join(names)
        if pos >= len(lines):
            raise InputError(f"{path}:{len(lines)}: missing record '{what}' (the file ends at line {len(lines)}; "
                             "dc3din has a comment line before each record)")
        if _is_comment(lines[pos]):
            raise InputError(f"{path}:{pos + 1}: expected the record '{what}', found a comment line "
                             "(dc3din has exactly one comment line before each record)")
        for name, v in zip(names, read_record(lines[pos], kinds, width, f"{path}:{pos + 1}")):
            values[name], line_of[name] = v, pos + 1
        pos += 1
    _check(path, values, line_of)
    return Dc3dInput(**values, lines=line_of)


def _is_comment(line: str) -> bool:
    return line.lstrip().startswith("*")


def _check(path: Path, v: dict, line_of: dict[str, int]) -> None:
    def fail(name: str, msg: str) -> None:
        raise InputError(f"{path}:{line_of[name]}: {msg}")

    if (v["itype"], v["jtype"]) not in {t.value for t in RunType}:
        fail("itype", f"itype {v['itype']}, jtype {v['jtype']}: DC3D knows 2/1 (propagate, wall deck), "
                      "2/2 and 2/3 (wall deck only, old or new wall grid), 1/1 (propagate, CTH packages)")
    for a, b in INDEX_RANGES:
        if not 1 <= v[a] <= v[b]:
            fail(a, f"inconsistent grid indices: need 1 <= {a} <= {b}, got {a} = {v[a]}, {b} = {v[b]}")
    for name in ("dx", "dy", "dz", "rho_ref", "mu", "eta", "eps", "ymxref", "factor"):
        if not v[name] > 0:
            fail(name, f"{name} = {v[name]} must be > 0")
    for name in ("tmin", "dencut", "zeta"):
        if not v[name] >= 0:
            fail(name, f"{name} = {v[name]} must be >= 0")
    if not v["tcut"] > v["tmin"]:
        fail("tcut", f"tcut = {v['tcut']} must exceed tmin = {v['tmin']}")
    if not v["lam"] + 2.0 * v["mu"] / 3.0 > 0:
        fail("lam", f"lambda = {v['lam']} with mu = {v['mu']} gives a bulk modulus <= 0")
    grids = ("",) + (("n",) if v["jtype"] == 3 else ())  # the new grid is read only for jtype 3
    for s in grids:
        for axis in "ijk":
            name = f"{axis}dmax{s}"
            if not v[name] >= 2:
                fail(name, f"{name} = {v[name]}: the wall grid needs at least 2 nodes along each axis")
        for axis in "xyz":
            lo, hi = f"{axis}dmin{s}", f"{axis}dmax{s}"
            if not v[hi] > v[lo]:
                fail(lo, f"inconsistent wall bounds: {hi} = {v[hi]} must exceed {lo} = {v[lo]}")
    # sizes, before anything is allocated: the avsout cell block (read when the run propagates), the wall
    # grid, and the new wall grid where it is used (the deck's grid for 2/3, the remap face for 2/1)
    if v["jtype"] == 1:
        check_cells(f"{path}:{line_of['i1']}-{line_of['k1']}: records i1 i2, j1 j2, k1 k2 (the avsout cells)",
                    [v[b] - v[a] + 1 for a, b in INDEX_RANGES])
        # where its cells lie
        AvsLayout.from_values(v, f"{path}:{line_of['i1']}-{line_of['dz']}: records i1 i2 to zlow dz")
    at = f"{path}:{line_of['idmax']}"
    check_nodes(f"{at}: idmax jdmax kdmax", [v["idmax"], v["jdmax"], v["kdmax"]])
    if v["jtype"] == 3:
        check_nodes(f"{at}: idmaxn jdmaxn kdmaxn", [v["idmaxn"], v["jdmaxn"], v["kdmaxn"]])
    elif (v["itype"], v["jtype"]) == (2, 1):
        check_nodes(f"{at}: idmaxn, 2, kdmaxn (the remap face)", [v["idmaxn"], 2, v["kdmaxn"]])
