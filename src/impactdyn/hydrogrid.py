"""HydroGrid: the hydrocode state on a rectilinear grid, input of the debris stage.

Units are the impact stages' (cm, g, µs; see :mod:`impactdyn.units`).  Cell
``(i, j, k)`` spans ``[x[i], x[i+1]] × [y[j], y[j+1]] × [z[k], z[k+1]]``; its lower
corner is node ``(i, j, k)`` (docs/theory/debris.md, seeding: the listing's NDDATA convention).

Two velocity conventions (``staggered``):

* ``False``: cell-centred velocities (our SPH stage, VTK input).
* ``True``: the legacy CTH dump read by RDAVS (Fahrenthold 1994, App. G), whose
  velocity component d of cell (i, j, k) belongs to the cell's *lower* face
  normal to axis d (x: the face at ``x[i]``).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from impactdyn._errors import InputError
from impactdyn._limits import check_fits

#: Units of every array of a HydroGrid, as written into HDF5/VTK attributes.
UNITS = {
    "x": "cm",
    "y": "cm",
    "z": "cm",
    "density": "g/cm^3",
    "void_fraction": "1",
    "mass": "g",
    "pressure": "Mbar",
    "temperature": "K",
    "specific_energy": "cm^2/us^2",
    "sound_speed": "cm/us",
    "velocity": "cm/us",
    "time": "us",
}

#: Cell fields of shape (nx, ny, nz); ``velocity`` is (nx, ny, nz, 3).
SCALAR_FIELDS = (
    "density",
    "void_fraction",
    "mass",
    "pressure",
    "temperature",
    "specific_energy",
    "sound_speed",
)
CELL_FIELDS = SCALAR_FIELDS + ("velocity",)

#: The report's DC3D cell edge, cm: the default cell of the grids the library builds
#: (``shield.bin_to_hydrogrid``, ``debris.shell_cloud_grid``).
DC3D_CELL_CM = 0.03175
_NONNEGATIVE = ("density", "mass", "temperature", "sound_speed")

#: Memory one cell costs at least (:mod:`impactdyn._limits`): its ten float64 values, once.
CELL_BYTES = 8 * (len(SCALAR_FIELDS) + 3)


def check_cells(what: str, shape) -> int:
    """The number of cells of an (nx, ny, nz) grid, if the machine can hold them; otherwise an
    :class:`InputError` that begins with ``what`` (the key or record that set the shape).
    ``shape`` may hold floats (a length over a cell size), rounded up."""
    total = 1.0
    for n in shape:
        total *= math.ceil(n) if math.isfinite(n) else n
    return check_fits(what, total, CELL_BYTES, "grid cells")


@dataclass(frozen=True, eq=False)
class HydroGrid:
    """Hydrocode state on a rectilinear grid (arrays are stored read-only, float64).

    Attributes
    ----------
    x, y, z : (nx+1,), (ny+1,), (nz+1,)
        Node coordinates, cm, strictly increasing.
    density : (nx, ny, nz)
        Material density ρ, g/cm³ (of the material, not the cell's bulk density).
    void_fraction : (nx, ny, nz)
        φ in [0, 1]; the cell's bulk density is (1 − φ) ρ.
    mass : (nx, ny, nz)
        Cell mass, g.
    pressure : (nx, ny, nz)
        Mbar (may be negative: tension).
    temperature : (nx, ny, nz)
        K.
    specific_energy : (nx, ny, nz)
        Specific internal energy, cm²/µs² (may be negative: relative to a reference state).
    sound_speed : (nx, ny, nz)
        cm/µs.
    velocity : (nx, ny, nz, 3)
        cm/µs; face-centred if ``staggered`` (see the module docstring), else cell-centred.
    staggered : bool
    time : float
        µs.
    """

    x: np.ndarray
    y: np.ndarray
    z: np.ndarray
    density: np.ndarray
    void_fraction: np.ndarray
    mass: np.ndarray
    pressure: np.ndarray
    temperature: np.ndarray
    specific_energy: np.ndarray
    sound_speed: np.ndarray
    velocity: np.ndarray
    staggered: bool = False
    time: float = 0.0

    def __post_init__(self) -> None:
        for name in ("x", "y", "z"):
            a = _frozen_array(self, name)
            if a.ndim != 1 or a.size < 2:
                raise InputError(f"HydroGrid.{name}: must be 1-D with at least 2 nodes, got shape {a.shape}")
            _check_finite(name, a)
            if np.any(np.diff(a) <= 0):
                n = int(np.argmax(np.diff(a) <= 0))
                raise InputError(f"HydroGrid.{name}: nodes must increase strictly ({name}[{n}] = {a[n]}, "
                                 f"{name}[{n + 1}] = {a[n + 1]})")
        shape = self.shape
        for name in CELL_FIELDS:
            a = _frozen_array(self, name)
            want = shape + (3,) if name == "velocity" else shape
            if a.shape != want:
                raise InputError(f"HydroGrid.{name}: shape {a.shape}, expected {want} for {shape} cells")
            _check_finite(name, a)
        for name in _NONNEGATIVE:
            _check_where(name, getattr(self, name) < 0, "negative value")
        phi = self.void_fraction
        _check_where("void_fraction", (phi < 0) | (phi > 1), "outside [0, 1]")
        if not isinstance(self.staggered, (bool, np.bool_)):
            raise InputError(f"HydroGrid.staggered: must be a bool, got {self.staggered!r}")
        object.__setattr__(self, "staggered", bool(self.staggered))
        try:
            t = float(self.time)
        except (TypeError, ValueError):
            t = np.nan
        if not np.isfinite(t):
            raise InputError(f"HydroGrid.time: must be finite, got {self.time!r}")
        object.__setattr__(self, "time", t)

    @property
    def shape(self) -> tuple[int, int, int]:
        """Number of cells (nx, ny, nz)."""
        return (self.x.size - 1, self.y.size - 1, self.z.size - 1)

    def cell_volumes(self) -> np.ndarray:
        """Cell volumes Δx_i Δy_j Δz_k, cm³, shape (nx, ny, nz)."""
        return np.diff(self.x)[:, None, None] * np.diff(self.y)[None, :, None] * np.diff(self.z)[None, None, :]

    def total_mass(self) -> float:
        """Σ cell mass, g."""
        return float(self.mass.sum())

    def total_momentum(self) -> np.ndarray:
        """Σ m v over cells, g·cm/µs, shape (3,) (each cell's velocity record, either convention)."""
        return np.einsum("ijk,ijkd->d", self.mass, self.velocity)

    def nodal_velocities(self) -> np.ndarray:
        """Node velocities, cm/µs, shape (nx+1, ny+1, nz+1, 3): mass-weighted means of cell values.

        Cells outside the grid carry no weight; a node whose stencil holds no mass
        gets zero (RDAVS: "empty weights → zero").

        Staggered data (RDAVS, Fahrenthold 1994 App. G; docs/theory/binning.md): component d at
        node (a, b, c) averages the cells whose lower d-face contains the node —
        the four cells sharing the node's face plane for that component::

            v_x(a, b, c) = Σ m v_x / Σ m  over cells (a,     b-1..b, c-1..c)
            v_y(a, b, c) = Σ m v_y / Σ m  over cells (a-1..a, b,     c-1..c)
            v_z(a, b, c) = Σ m v_z / Σ m  over cells (a-1..a, b-1..b, c    )

        (the listing's 1-based loops over nodes 2..n read the same with the same
        indices).  Consequently nodes on the upper boundary plane of axis d
        (a = nx for x) have no cell in their d-stencil and get v_d = 0; DC3D never
        uses them (it makes particles of cells 2..n−1 only).

        Cell-centred data: every component averages the eight cells around the
        node, ``(a-1..a, b-1..b, c-1..c)``.
        """
        m = self.mass
        mv = m[..., None] * self.velocity
        if not self.staggered:
            return _weighted_mean(_node_sum(mv, (0, 1, 2)), _node_sum(m, (0, 1, 2))[..., None])
        pairs = [tuple(ax for ax in range(3) if ax != d) for d in range(3)]
        return np.stack([_weighted_mean(_node_sum(mv[..., d], p), _node_sum(m, p)) for d, p in enumerate(pairs)],
                        axis=-1)

    def __repr__(self) -> str:
        return (f"HydroGrid(shape={self.shape}, staggered={self.staggered}, time={self.time} us, "
                f"mass={self.total_mass():.6g} g)")


def _node_sum(a: np.ndarray, pair_axes: tuple[int, ...]) -> np.ndarray:
    """Σ of cell values (nx, ny, nz, ...) over each node's stencil, shape (nx+1, ny+1, nz+1, ...).

    Along a pair axis node n collects cells n−1 and n; along the other axes only
    cell n (the cell whose lower face holds the node).  Missing cells count as 0.
    """
    (nx, ny, nz), rest = a.shape[:3], a.shape[3:]
    p = np.zeros((nx + 2, ny + 2, nz + 2) + rest)
    p[1:-1, 1:-1, 1:-1] = a  # p index n+1 is cell n; p[0] and p[-1] are empty cells
    offsets = [(0, 1) if ax in pair_axes else (1,) for ax in range(3)]
    out = np.zeros((nx + 1, ny + 1, nz + 1) + rest)
    for o in itertools.product(*offsets):
        out += p[o[0] : o[0] + nx + 1, o[1] : o[1] + ny + 1, o[2] : o[2] + nz + 1]
    return out


def _weighted_mean(total: np.ndarray, weight: np.ndarray) -> np.ndarray:
    """total / weight where weight > 0, else 0 (RDAVS: empty weights give zero)."""
    return np.divide(total, weight, out=np.zeros(np.broadcast_shapes(total.shape, weight.shape)), where=weight > 0)


def _frozen_array(grid: HydroGrid, name: str) -> np.ndarray:
    try:
        a = np.array(getattr(grid, name), dtype=np.float64)  # a private copy
    except (TypeError, ValueError):
        raise InputError(f"HydroGrid.{name}: not an array of numbers") from None
    a.flags.writeable = False
    object.__setattr__(grid, name, a)
    return a


def _check_finite(name: str, a: np.ndarray) -> None:
    _check_where(name, ~np.isfinite(a), "not finite")


def _check_where(name: str, bad: np.ndarray, what: str) -> None:
    if np.any(bad):
        idx = tuple(int(i) for i in np.argwhere(bad)[0])
        raise InputError(f"HydroGrid.{name}: {what} at index {idx} ({int(bad.sum())} entries)")

