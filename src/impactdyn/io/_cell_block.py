"""The block of CTH cells an avsout dump holds: the twelve fields that dc3din (records 2–7) and the
avsout header (its ``key = value`` lines) both give, declared once.

:class:`CellBlock` holds them as read; :class:`impactdyn.io.AvsLayout` is a checked one.  A dc3din
that does not propagate never reads its avsout, so its block is kept unchecked
(:class:`impactdyn.io.Dc3dInput` is a CellBlock).
"""

from __future__ import annotations

from dataclasses import dataclass, fields


@dataclass(frozen=True)
class CellBlock:
    """Where a block of CTH cells lies in the CTH mesh, as a file gives it.

    i1..i2, j1..j2, k1..k2: absolute CTH cell indices of the block (inclusive; CTH's first real
    cell is 2).  xlow, ylow, zlow: lower mesh bound (the lower node of cell 2), cm.  dx, dy, dz:
    cell size, cm.
    """

    i1: int
    i2: int
    j1: int
    j2: int
    k1: int
    k2: int
    xlow: float
    dx: float
    ylow: float
    dy: float
    zlow: float
    dz: float

    @property
    def shape(self) -> tuple[int, int, int]:
        """Cells in the block (nx, ny, nz)."""
        return (self.i2 - self.i1 + 1, self.j2 - self.j1 + 1, self.k2 - self.k1 + 1)


BLOCK_FIELDS = tuple(f.name for f in fields(CellBlock))
"""The twelve fields in file order."""
INDEX_FIELDS = tuple(f.name for f in fields(CellBlock) if f.type == "int")
"""i1 … k2, the cell indices (integers)."""
MESH_FIELDS = tuple(name for name in BLOCK_FIELDS if name not in INDEX_FIELDS)
"""xlow … dz, the mesh bounds and cell sizes (reals)."""
FIELD_PAIRS = tuple(zip(BLOCK_FIELDS[::2], BLOCK_FIELDS[1::2]))
"""(i1, i2), (j1, j2), (k1, k2), (xlow, dx), (ylow, dy), (zlow, dz): dc3din's records 2–7."""
INDEX_RANGES = tuple(zip(INDEX_FIELDS[::2], INDEX_FIELDS[1::2]))
"""(i1, i2), (j1, j2), (k1, k2): the block's first and last cell along each axis."""
