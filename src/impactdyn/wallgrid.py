"""The rear wall: brick mesh, supports and the deposited momentum (data model, below every solver).

One numbering serves every deck writer — DYNGEN's (Fahrenthold 1994, App. G):
node (i, j, k) (i along x, j through the thickness y, k along z, 0-based) is
number ``1 + i + (nx+1) k + (nx+1)(nz+1) j``; element (i, j, k) is number
``1 + i + nx k + nx nz j``.  The debris hits the front face y = y[0]; its x–z
face elements are the deposition grid of DYNOUT/DCPOST, and face element
``e = i + nx k`` is solid element number e + 1 (front layer j = 0).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np

from impactdyn._errors import InputError
from impactdyn._limits import check_fits

#: Memory one wall node costs at least (:mod:`impactdyn._limits`): its coordinates (24 B),
#: its number (8 B) and its element's eight node numbers in the decks (64 B).
NODE_BYTES = 96


def check_nodes(what: str, nodes) -> int:
    """The number of nodes of a wall with ``nodes`` along each axis, if the machine can hold them;
    otherwise an :class:`InputError` that begins with ``what`` (the key or record that set them)."""
    total = 1
    for n in nodes:
        total *= int(n)
    return check_fits(f"{what} = {list(nodes)}", total, NODE_BYTES, "wall nodes")


@dataclass(frozen=True, eq=False)
class WallGrid:
    """Rectilinear brick mesh of the wall; x (nx+1,), y (ny+1,), z (nz+1,) node coordinates, cm.

    y is the thickness direction; the front (impacted) face is y = y[0].
    """

    x: np.ndarray
    y: np.ndarray
    z: np.ndarray

    def __post_init__(self) -> None:
        for name in ("x", "y", "z"):
            a = np.array(getattr(self, name), dtype=np.float64)
            if a.ndim != 1 or a.size < 2 or not np.all(np.isfinite(a)) or np.any(np.diff(a) <= 0):
                raise InputError(f"WallGrid.{name}: needs at least 2 finite, strictly increasing nodes")
            a.flags.writeable = False
            object.__setattr__(self, name, a)

    @classmethod
    def uniform(cls, x_range: tuple[float, float], y_range: tuple[float, float],
                z_range: tuple[float, float], nodes: tuple[int, int, int]) -> "WallGrid":
        """Equally spaced nodes, as DYNGEN: ``nodes = (idmax, jdmax, kdmax)`` over each range."""
        check_nodes("WallGrid.uniform: nodes", nodes)
        return cls(*(np.linspace(lo, hi, n) for (lo, hi), n in zip((x_range, y_range, z_range), nodes)))

    @property
    def shape(self) -> tuple[int, int, int]:
        """Number of elements (nx, ny, nz)."""
        return (self.x.size - 1, self.y.size - 1, self.z.size - 1)

    @property
    def thickness(self) -> float:
        """The wall's thickness y[-1] − y[0], cm."""
        return float(self.y[-1] - self.y[0])

    @property
    def n_nodes(self) -> int:
        return self.x.size * self.y.size * self.z.size

    @property
    def n_elements(self) -> int:
        nx, ny, nz = self.shape
        return nx * ny * nz

    @property
    def n_face_elements(self) -> int:
        """Elements of the x–z deposition grid, nx·nz."""
        return self.shape[0] * self.shape[2]

    def node_numbers(self) -> np.ndarray:
        """1-based node numbers, shape (nx+1, ny+1, nz+1), DYNGEN order (i fastest, then k, then j)."""
        ni, nj, nk = self.x.size, self.y.size, self.z.size
        i, j, k = np.meshgrid(np.arange(ni), np.arange(nj), np.arange(nk), indexing="ij")
        return 1 + i + ni * k + ni * nk * j

    def node_coordinates(self) -> np.ndarray:
        """Coordinates in node-number order, shape (n_nodes, 3), cm."""
        xyz = np.stack(np.meshgrid(self.x, self.y, self.z, indexing="ij"), axis=-1)
        return _in_number_order(xyz)

    def element_nodes(self) -> np.ndarray:
        """Node numbers of each element in element-number order, shape (n_elements, 8).

        DYNGEN's order: the back face (j+1) n5 n6 n7 n8, then the front face (j)
        n1 n2 n3 n4, where n1 = (i, j, k), n2 = (i+1, j, k), n3 = (i+1, j, k+1),
        n4 = (i, j, k+1) — a positive-volume hexahedron.
        """
        n = self.node_numbers()
        front = [n[:-1, :-1, :-1], n[1:, :-1, :-1], n[1:, :-1, 1:], n[:-1, :-1, 1:]]
        back = [n[:-1, 1:, :-1], n[1:, 1:, :-1], n[1:, 1:, 1:], n[:-1, 1:, 1:]]
        return _in_number_order(np.stack(back + front, axis=-1))

    def face_element_nodes(self, element: np.ndarray) -> np.ndarray:
        """Front-face node numbers (n1 n2 n3 n4) of face elements ``i + nx k``, shape (n, 4)."""
        k, i = np.divmod(np.asarray(element), self.shape[0])
        n = self.node_numbers()[:, 0, :]
        return np.stack([n[i, k], n[i + 1, k], n[i + 1, k + 1], n[i, k + 1]], axis=-1)

    def constrained_dofs(self, clamped: bool = False) -> np.ndarray:
        """Fixed translations (x, y, z) of each node in number order, shape (n_nodes, 3), bool.

        The plane x = x[0] is the symmetry plane of the half model (x fixed).  The
        other three edges, through the thickness, are supported as DYNGEN does:
        x = x[-1] fixes x and y, z = z[0] and z = z[-1] fix y and z (DYNA3D codes
        1, 4, 5, and 7 at the corners, where the edge conditions add up).  With
        ``clamped`` those three edges fix all translations instead.
        """
        ni, nj, nk = self.x.size, self.y.size, self.z.size
        fixed = np.zeros((ni, nj, nk, 3), dtype=bool)
        fixed[0, :, :, 0] = True
        fixed[-1, :, :, :] |= (True, True, clamped)
        fixed[:, :, 0, :] |= (clamped, True, True)
        fixed[:, :, -1, :] |= (clamped, True, True)
        return _in_number_order(fixed)


@dataclass(frozen=True, eq=False)
class WallDeposition:
    """Time-resolved momentum deposited on the wall's front face (DYNOUT records).

    element : (n,) int — face element ``i + nx k`` of the x–z deposition grid (0-based).
    time : (n,) — arrival time, µs.
    impulse : (n, 3) — deposited momentum, g·cm/µs.
    """

    element: np.ndarray
    time: np.ndarray
    impulse: np.ndarray

    def __post_init__(self) -> None:
        e = np.asarray(self.element)
        if e.ndim != 1 or (e.size and (not np.issubdtype(e.dtype, np.integer) or e.min() < 0)):
            raise InputError("WallDeposition.element: must be a 1-D array of non-negative integers")
        t = np.array(self.time, dtype=np.float64)
        p = np.array(self.impulse, dtype=np.float64)
        if t.shape != e.shape or p.shape != e.shape + (3,):
            raise InputError(f"WallDeposition: shapes element {e.shape}, time {t.shape}, impulse {p.shape}; "
                             "expected (n,), (n,), (n, 3)")
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(p))):
            raise InputError("WallDeposition: time and impulse must be finite")
        for name, a in (("element", e.astype(np.int64)), ("time", t), ("impulse", p)):
            a.flags.writeable = False
            object.__setattr__(self, name, a)

    def check_fits(self, wall: WallGrid) -> None:
        """InputError unless every element lies on ``wall``'s deposition grid."""
        if self.element.size and self.element.max() >= wall.n_face_elements:
            raise InputError(f"WallDeposition.element: {self.element.max()} is outside the wall's "
                             f"{wall.shape[0]} x {wall.shape[2]} face grid")


def face_overlaps(source: WallGrid, target: WallGrid, cells: np.ndarray) -> Iterator[tuple[np.ndarray, np.ndarray]]:
    """For each of ``source``'s face ``cells``: ``target``'s face cells it overlaps (in target element
    order) and the shares of its area they cover (rectilinear grids: products of 1-D overlaps; sum 1)."""
    share_x, share_z = _overlap_shares(source.x, target.x), _overlap_shares(source.z, target.z)
    nx_s, nx_t = source.shape[0], target.shape[0]
    for c in cells:
        k, i = divmod(int(c), nx_s)
        ix, iz = np.flatnonzero(share_x[i]), np.flatnonzero(share_z[k])
        yield (ix[None, :] + nx_t * iz[:, None]).ravel(), np.outer(share_z[k, iz], share_x[i, ix]).ravel()


def _overlap_shares(source: np.ndarray, target: np.ndarray) -> np.ndarray:
    """Share of each source interval's length that each target interval covers, (ns, nt), rows sum to 1."""
    overlap = np.clip(np.minimum(source[1:, None], target[None, 1:])
                      - np.maximum(source[:-1, None], target[None, :-1]), 0.0, None)
    return overlap / overlap.sum(axis=1, keepdims=True)


def sphere_deposition(wall: WallGrid, diameter_cm: float, speed_cm_us: float, density_g_cm3: float,
                      t0_us: float = 0.0, centre_xz: tuple[float, float] = (0.0, 0.0),
                      samples: int = 8) -> WallDeposition:
    """The momentum of a compact sphere striking the front face normally, as records on ``wall``'s face grid.

    A sphere of diameter d, density ρ and speed V along +y, its front touching the wall at
    ``t0_us`` over ``centre_xz``: the column over the face point at distance r from the centre
    has length L = 2 √(R² − r²) and arrives from t0 + (R − L/2)/V to t0 + (R + L/2)/V, carrying
    the momentum ρ L V per unit area at the constant rate ρ V² (a rod stopped at the wall).
    Each face cell takes the columns of ``samples`` × ``samples`` points in it, in time bins
    of h_min / V (h_min the smallest face cell).  Only the part of the sphere over the grid is
    deposited: on a half model (symmetry plane x = ``wall.x[0]`` = 0) with the centre on it,
    half the sphere.  The records' impulses sum to the sphere's (or the half's) momentum
    ρ π d³ V / 6 (/ 2) up to the sampling of its disc: to 0.2 % at four cells across d, 0.02 % at
    eight (the default 8 × 8 samples a cell).

    Returns records ``element`` (n,), ``time`` (n,) µs, ``impulse`` (n, 3) g·cm/µs.
    """
    for name, value in (("diameter_cm", diameter_cm), ("speed_cm_us", speed_cm_us),
                        ("density_g_cm3", density_g_cm3)):
        if not (np.isfinite(value) and value > 0):
            raise InputError(f"sphere_deposition: {name} must be > 0, got {value!r}")
    if not (isinstance(samples, int) and samples >= 1):
        raise InputError(f"sphere_deposition: samples must be an integer >= 1, got {samples!r}")
    radius = 0.5 * diameter_cm
    nx = wall.x.size - 1
    hx, hz = np.diff(wall.x), np.diff(wall.z)
    s = (np.arange(samples) + 0.5) / samples
    X, Z = np.meshgrid((wall.x[:-1, None] + hx[:, None] * s).ravel() - centre_xz[0],
                       (wall.z[:-1, None] + hz[:, None] * s).ravel() - centre_xz[1], indexing="ij")
    i, k = np.meshgrid(np.repeat(np.arange(nx), samples), np.repeat(np.arange(hz.size), samples), indexing="ij")
    inside = X**2 + Z**2 < radius**2
    i, k = i[inside], k[inside]
    length = 2.0 * np.sqrt(radius**2 - X[inside] ** 2 - Z[inside] ** 2)
    momentum = density_g_cm3 * length * (hx[i] * hz[k] / samples**2) * speed_cm_us
    t_first = t0_us + (radius - 0.5 * length) / speed_cm_us
    t_last = t0_us + (radius + 0.5 * length) / speed_cm_us
    bin_width = float(min(hx.min(), hz.min())) / speed_cm_us
    edges = t0_us + bin_width * np.arange(int(np.ceil(diameter_cm / speed_cm_us / bin_width)) + 2)
    overlap = np.clip(np.minimum(t_last[:, None], edges[None, 1:]) - np.maximum(t_first[:, None], edges[None, :-1]),
                      0.0, None) / (t_last - t_first)[:, None]
    table = np.zeros((wall.n_face_elements, edges.size - 1))
    np.add.at(table, i + nx * k, overlap * momentum[:, None])
    e, b = np.nonzero(table)
    impulse = np.zeros((e.size, 3))
    impulse[:, 1] = table[e, b]
    return WallDeposition(element=e.astype(np.int64), time=0.5 * (edges[b] + edges[b + 1]), impulse=impulse)


def _in_number_order(a: np.ndarray) -> np.ndarray:
    """(ni, nj, nk, ...) array -> (ni·nj·nk, ...) in DYNGEN order (i fastest, then k, then j)."""
    return a.transpose(1, 2, 0, *range(3, a.ndim)).reshape(-1, *a.shape[3:])
