"""The wall's finite-element mesh: brick mesh, lumped masses, supports, node→element map.

Two kinds of mesh (:data:`MESH_KINDS`), both a rectilinear :class:`~impactdyn.wallgrid.WallGrid`:

* ``"report"`` (:func:`build_mesh`) — the case's grid with every element cut into ``r_t``
  layers through the thickness (y) and ``r_p × r_p`` pieces in the plane (x, z), equal parts
  of the parent element; the deposition records stay on the parent's face cells.
* ``"graded"`` (:mod:`._grading`) — near-cubic elements where the debris load is
  concentrated, growing away from it; the records are re-binned onto its own face cells.

The solver grid keeps DYNGEN's numbering (:mod:`impactdyn.wallgrid`), 0-based here:

    node (i, j, k)    → i + NI k + NI NK j            (NI, NK: the grid's nodes along x, z)
    element (i, j, k) → i + nx k + nx nz j            (nx, nz: the grid's elements along x, z)

and the element's eight nodes in DYNGEN's order: the back face (j+1) n5 n6 n7 n8, then
the front face (j) n1 n2 n3 n4.  That order is the isoparametric order of the 8-node
brick with ξ along x, η along z and ζ along −y (local node a at (ξ, η, ζ) = (∓1, ∓1, −1)
for a = 0…3 and the same at ζ = +1 for a = 4…7), a right-handed, positive-volume
numbering, and also VTK's hexahedron order.  On the report mesh at refinement 1 the
numbers are DYNGEN's minus one.

Lumped mass: each element gives ρ₀V₀/8 to each of its nodes (the row sum of the
consistent mass matrix of a parallelepiped; Belytschko, Liu & Moran 2000, §6.3).

Supports (``supports``), by node, per translation:

* ``"dyngen"`` — :meth:`WallGrid.constrained_dofs` of the solver grid: the plane
  x = x[0] is the symmetry plane of the half model (x fixed); the edge x = x[-1]
  fixes x and y; the edges z = z[0] and z = z[-1] fix y and z (DYNA3D codes 1, 4, 5 and
  7 at the corners, as DYNGEN writes them).  Every node through the thickness of an
  edge is constrained.
* ``"clamped"`` — the symmetry plane as above and all translations fixed on the other
  three edges.
* ``"free"`` — nothing fixed (verification problems).
* ``"uniaxial"`` — x and z fixed at every node: one-dimensional strain through the
  thickness (flyer-plate and wave-speed problems).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from impactdyn._errors import InputError
from impactdyn.wall._hex import element_volumes
from impactdyn.wallgrid import WallGrid

SUPPORTS = ("dyngen", "clamped", "free", "uniaxial")
#: The kinds of solver mesh (module docstring); the first is the default of :func:`~._grading.solver_mesh`.
MESH_KINDS = ("graded", "report")


@dataclass(frozen=True, eq=False)
class WallMesh:
    """The brick mesh of a wall, ready for the solver (units cm, g).

    Attributes
    ----------
    parent : WallGrid
        The case's grid (the debris stage's deposition grid is its front face; the load's
        default depth is half its first layer, :func:`~._load.default_depth`).
    grid : WallGrid
        The solver grid; its node and element numbering is the mesh's.
    refinement : (int, int)
        (through the thickness, in the plane): every element of the case's grid (``"report"``) or of
        the graded grid (``"graded"``) cut into that many layers and pieces along each in-plane axis.
    coordinates : (n_nodes, 3)
        Initial node coordinates, cm.
    connectivity : (n_elements, 8) int64
        0-based node numbers of each element, DYNGEN / VTK order (module docstring).
    volume : (n_elements,)
        Initial element volumes V₀, cm³.
    element_mass : (n_elements,)
        ρ₀V₀, g.
    node_mass : (n_nodes,)
        Lumped nodal masses, g.
    fixed : (n_nodes, 3) bool
        Fixed translations (x, y, z).
    supports : str
        One of :data:`SUPPORTS`.
    node_element_ptr, node_element_entry : (n_nodes + 1,), (8 n_elements,) int64
        CSR map node → element corners: the entries ``8 e + a`` (element e, local node a)
        of node I are ``node_element_entry[node_element_ptr[I]:node_element_ptr[I + 1]]``.
    density : float
        ρ₀, g/cm³.
    kind : str
        One of :data:`MESH_KINDS`: on a ``"report"`` mesh the load's spread acts on the parent's
        face cells, on a ``"graded"`` one on the grid's own (:attr:`load_grid`).
    """

    parent: WallGrid
    grid: WallGrid
    refinement: tuple[int, int]
    coordinates: np.ndarray
    connectivity: np.ndarray
    volume: np.ndarray
    element_mass: np.ndarray
    node_mass: np.ndarray
    fixed: np.ndarray
    supports: str
    node_element_ptr: np.ndarray
    node_element_entry: np.ndarray
    density: float
    kind: str = "report"

    @property
    def load_grid(self) -> WallGrid:
        """The grid whose face cells the load's spread acts on: the parent (report) or the grid (graded)."""
        return self.parent if self.kind == "report" else self.grid

    @property
    def shape(self) -> tuple[int, int, int]:
        """Elements (nx, ny, nz) of the refined mesh."""
        return self.grid.shape

    @property
    def n_nodes(self) -> int:
        return self.coordinates.shape[0]

    @property
    def n_elements(self) -> int:
        return self.connectivity.shape[0]

    @property
    def thickness(self) -> float:
        """Wall thickness y[-1] − y[0], cm (the solver grid's, :attr:`WallGrid.thickness`)."""
        return self.grid.thickness

    def element_ijk(self) -> np.ndarray:
        """(i, j, k) of every element in number order, shape (n_elements, 3)."""
        nx, ny, nz = self.shape
        e = np.arange(self.n_elements)
        j, rest = np.divmod(e, nx * nz)
        k, i = np.divmod(rest, nx)
        return np.stack([i, j, k], axis=-1)

    def node_ijk(self) -> np.ndarray:
        """(i, j, k) of every node in number order, shape (n_nodes, 3)."""
        ni, nk = self.grid.x.size, self.grid.z.size
        n = np.arange(self.n_nodes)
        j, rest = np.divmod(n, ni * nk)
        k, i = np.divmod(rest, ni)
        return np.stack([i, j, k], axis=-1)

    def face_nodes(self, side: str) -> np.ndarray:
        """Node numbers of the front (y = y[0]) or rear (y = y[-1]) face, shape (NK, NI): [k, i]."""
        ni, nj, nk = self.grid.x.size, self.grid.y.size, self.grid.z.size
        j = {"front": 0, "rear": nj - 1}[side]
        return (np.arange(ni)[None, :] + ni * np.arange(nk)[:, None] + ni * nk * j).astype(np.int64)

    def layer_elements(self, j: int) -> np.ndarray:
        """Element numbers of layer j (0 = front), shape (nz, nx): [k, i]."""
        nx, _, nz = self.shape
        return (np.arange(nx)[None, :] + nx * np.arange(nz)[:, None] + nx * nz * j).astype(np.int64)

    def describe(self) -> dict:
        """The mesh in words and numbers, JSON-ready (the wall stage's record): kind, elements
        (nx, ny, nz), counts, the in-plane element sizes' range and the layer thicknesses' range, cm."""
        plane = np.concatenate([np.diff(self.grid.x), np.diff(self.grid.z)])
        layers = np.diff(self.grid.y)
        return {"kind": self.kind, "elements": list(self.shape), "n_elements": self.n_elements,
                "n_nodes": self.n_nodes,
                "refinement": list(self.refinement),
                "element_size_plane_cm": [float(plane.min()), float(plane.max())],
                "layer_thickness_cm": [float(layers.min()), float(layers.max())],
                "supports": self.supports}


def refine(a: np.ndarray, r: int) -> np.ndarray:
    """Node coordinates with every interval of ``a`` cut into ``r`` equal parts."""
    a = np.asarray(a, dtype=np.float64)
    inner = a[:-1, None] + (a[1:] - a[:-1])[:, None] * (np.arange(r) / r)[None, :]
    return np.concatenate([inner.ravel(), a[-1:]])


def check_density_supports(density: float, supports: str) -> None:
    """InputError naming the argument for a non-positive density or an unknown support condition."""
    if not (np.isfinite(density) and density > 0):
        raise InputError(f"density: must be > 0, got {density!r}")
    if supports not in SUPPORTS:
        raise InputError(f"supports: {supports!r}, expected one of {SUPPORTS}")


def check_refinements(refinement_thickness: int, refinement_plane: int) -> tuple[int, int]:
    """(r_t, r_p) as ints, or an InputError naming the argument that is not a positive integer."""
    for name, r in (("refinement_thickness", refinement_thickness), ("refinement_plane", refinement_plane)):
        if isinstance(r, bool) or not isinstance(r, (int, np.integer)) or r < 1:
            raise InputError(f"{name}: must be a positive integer, got {r!r}")
    return int(refinement_thickness), int(refinement_plane)


def build_mesh(wall: WallGrid, density: float, refinement_thickness: int = 1, refinement_plane: int = 1,
               supports: str = "dyngen") -> WallMesh:
    """The ``"report"`` solver mesh of ``wall`` (module docstring), ρ₀ = ``density`` g/cm³.

    Raises :class:`InputError` naming the argument for a non-positive or non-integer
    refinement, a non-positive density or an unknown support condition.
    """
    rt, rp = check_refinements(refinement_thickness, refinement_plane)
    check_density_supports(density, supports)
    return assemble_mesh(wall, refined(wall, rt, rp), density, supports, refinement=(rt, rp), kind="report")


def refined(grid: WallGrid, through: int, plane: int) -> WallGrid:
    """``grid`` with every element cut into ``through`` layers and ``plane`` × ``plane`` pieces in the plane."""
    return WallGrid(refine(grid.x, plane), refine(grid.y, through), refine(grid.z, plane))


def assemble_mesh(parent: WallGrid, grid: WallGrid, density: float, supports: str,
                  refinement: tuple[int, int], kind: str) -> WallMesh:
    """The :class:`WallMesh` of the solver grid ``grid`` (checked arguments): masses, supports, node map."""
    coords = np.ascontiguousarray(grid.node_coordinates(), dtype=np.float64)
    conn = np.ascontiguousarray(grid.element_nodes() - 1, dtype=np.int64)
    volume = element_volumes(coords, conn)
    if np.any(volume <= 0):
        raise InputError("WallGrid: an element has a non-positive volume")
    element_mass = density * volume
    node_mass = np.zeros(coords.shape[0])
    np.add.at(node_mass, conn.ravel(), np.repeat(element_mass / 8.0, 8))
    if supports in ("dyngen", "clamped"):
        fixed = grid.constrained_dofs(clamped=supports == "clamped")
    elif supports == "free":
        fixed = np.zeros(coords.shape, dtype=bool)
    else:  # uniaxial
        fixed = np.zeros(coords.shape, dtype=bool)
        fixed[:, 0] = fixed[:, 2] = True
    entries = conn.ravel()
    order = np.argsort(entries, kind="stable")
    ptr = np.zeros(coords.shape[0] + 1, dtype=np.int64)
    ptr[1:] = np.cumsum(np.bincount(entries, minlength=coords.shape[0]))
    for a in (coords, conn, volume):
        a.flags.writeable = False
    return WallMesh(parent=parent, grid=grid, refinement=refinement, coordinates=coords, connectivity=conn,
                    volume=volume, element_mass=element_mass, node_mass=node_mass,
                    fixed=np.ascontiguousarray(fixed, dtype=bool), supports=supports,
                    node_element_ptr=ptr, node_element_entry=order.astype(np.int64), density=float(density),
                    kind=kind)
