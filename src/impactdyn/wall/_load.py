"""The deposited momentum as nodal impulses: records → (node, weight) lists, sorted by arrival time.

Each deposition record (face element ``e = i + nx k`` of the case's grid, arrival time t,
impulse I, :class:`~impactdyn.wallgrid.WallDeposition`) becomes a velocity jump of the
front-face nodes under that element at the first solver time t^n ≥ t (never early; at most
one step late).  The spreads below act on the face cells of the mesh's load grid
(:attr:`~._mesh.WallMesh.load_grid`): the case's grid on a ``"report"`` mesh; on a ``"graded"``
one the solver grid itself, each case cell's impulse shared among the solver's face cells it
overlaps by area (a uniform areal impulse over the cell,
:func:`impactdyn.wallgrid.face_overlaps`) before the spread.  The impulse is shared among the nodes by weights w_a ≥ 0 with Σ_a w_a = 1,
so the impulse put on the wall is I exactly (to round-off):

* ``"corners"`` — I/4 on each of the element's four corner nodes (at in-plane refinement
  r_p of a report mesh, the corners of the parent element; the nodes between them get nothing).  At
  r_p = 1 this is DYNA3D/LS-DYNA's nodal split of an element load.
* ``"area"`` — each of the r_p × r_p sub-faces under the element takes the share of its
  area, split in quarters to its corners: the bilinear (tributary-area) weights of a
  uniform traction over the element.  Equal to ``"corners"`` at r_p = 1.
* ``"mass"`` — weights proportional to the lumped nodal masses of the (r_p + 1)² nodes
  under the element: every one of them takes the same velocity jump I/Σm, which is the
  spread that brings the least kinetic energy |I|²/(2Σm) for a given impulse.

``depth`` δ (cm) takes each of those front-face shares on through the thickness: the share
becomes a uniform body force over the depth δ below the front face, divided among the node
layers j by their tributary thickness inside [0, δ] (the lumped form of a uniform force per
unit volume; δ = 0, or below half the first layer, leaves it all on the front face).  By
default δ is half the first element layer of the case's grid (the parent mesh): the mass
DYNA3D's front-face nodes stand for at the report's mesh, so at refinement 1 the load is the
report's nodal load exactly, and a refined mesh takes it over the same material depth.  Why:
an impulse I on nodes at rest brings the energy |I|²/2m of the mass m it lands on.  On the
front-face nodes alone (δ = 0) m is half the first layer's mass, so the energy the load
brings grows with the refinement through the thickness and with it the damage under the
load (tests/wall/test_load.py; docs/vv/analytic.md, "Wall solver"); spread over a fixed
depth δ = n h it brings |I|²/(2ρAδ)·(1 − 1/(4n)) on a uniform column of cross-section A,
which converges as h → 0 (tests/wall/test_load.py).

A node's share goes to the node only in its free translations; the component along a
fixed translation (a support, or the symmetry plane's x) is taken by the support: it is
summed in the support impulse and does no work.  So
``impulse applied to the wall + impulse taken by the supports = Σ I`` exactly.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from impactdyn._errors import InputError
from impactdyn.wall._mesh import WallMesh
from impactdyn.wallgrid import WallDeposition, face_overlaps

SPREADS = ("corners", "area", "mass")


class NodalLoad(NamedTuple):
    """Deposition records on the mesh's nodes, sorted by arrival time.

    time (n,) µs; impulse (n, 3) g·cm/µs; the records of one face cell of the case's grid share
    its stencil: record r's nodes and weights are ``node[ptr[s]:ptr[s + 1]]``,
    ``weight[ptr[s]:ptr[s + 1]]`` with s = ``stencil[r]`` (weights sum to 1; a stencil per loaded
    cell, not per record: a cell of the case's grid covers up to ~100 nodes of a graded mesh's
    core through the load's depth, and a shot deposits ~10⁶ records on a few thousand cells);
    depth (cm) the depth δ below the front face the impulses are spread over (module docstring).
    A record type: the step loop takes it as it is (:mod:`._step`).
    """

    time: np.ndarray
    impulse: np.ndarray
    stencil: np.ndarray
    ptr: np.ndarray
    node: np.ndarray
    weight: np.ndarray
    depth: float = 0.0

    @property
    def total_impulse(self) -> np.ndarray:
        """Σ I of the records, (3,), g·cm/µs."""
        return self.impulse.sum(axis=0) if self.impulse.size else np.zeros(3)

    def entries(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(record, node, weight) of every node share of every record (for checks: one row per share)."""
        counts = np.diff(self.ptr)[self.stencil]
        record = np.repeat(np.arange(self.stencil.size), counts)
        first = np.repeat(self.ptr[self.stencil] - (np.cumsum(counts) - counts), counts)
        k = first + np.arange(record.size)
        return record, self.node[k], self.weight[k]


def _face_stencil(mesh: WallMesh, spread: str) -> tuple[np.ndarray, np.ndarray]:
    """Per face element of the load grid: the solver grid's front-face nodes (nf, m) and their weights (nf, m)."""
    nx, _, nz = mesh.load_grid.shape
    rp = mesh.shape[0] // nx            # in-plane refinement of the grid over the load grid (1 when graded)
    ni = mesh.grid.x.size
    k_f, i_f = np.divmod(np.arange(nx * nz), nx)
    if spread == "corners":
        di = np.array([0, rp, rp, 0])
        dk = np.array([0, 0, rp, rp])
        nodes = (i_f[:, None] * rp + di) + ni * (k_f[:, None] * rp + dk)
        return nodes, np.full(nodes.shape, 0.25)
    # every node under the element: local (a, b), a, b = 0..rp
    a, b = np.meshgrid(np.arange(rp + 1), np.arange(rp + 1), indexing="ij")
    a, b = a.ravel(), b.ravel()
    nodes = (i_f[:, None] * rp + a) + ni * (k_f[:, None] * rp + b)
    if spread == "mass":
        w = mesh.node_mass[nodes]
        return nodes, w / w.sum(axis=1, keepdims=True)
    # area: tributary weights of the sub-faces (rectilinear grid)
    x, z = mesh.grid.x, mesh.grid.z
    dx = np.diff(x)
    dz = np.diff(z)
    w = np.zeros(nodes.shape)
    for sa in range(rp):
        for sb in range(rp):
            ia = i_f * rp + sa
            kb = k_f * rp + sb
            area = dx[ia] * dz[kb] / 4.0
            for ca, cb in ((0, 0), (1, 0), (1, 1), (0, 1)):
                col = (sa + ca) * (rp + 1) + (sb + cb)
                w[:, col] += area
    return nodes, w / w.sum(axis=1, keepdims=True)


def default_depth(mesh: WallMesh) -> float:
    """Half the first element layer of the case's grid (``mesh.parent``), cm: the default δ.

    The case's grid on every kind of mesh, so that the energy the load brings does not change
    with the mesh (module docstring)."""
    return 0.5 * float(mesh.parent.y[1] - mesh.parent.y[0])


def check_deposition_depth(depth: float, thickness_cm: float) -> None:
    """InputError naming the key unless 0 ≤ ``depth`` ≤ the wall's thickness (a case checks it before any
    stage runs, the solver when it spreads the load)."""
    if not (math.isfinite(depth) and 0.0 <= depth <= thickness_cm):
        raise InputError(f"deposition_depth_cm: must be in [0, {thickness_cm:g}] (the wall's thickness), "
                         f"got {depth!r}")


def depth_weights(mesh: WallMesh, depth: float) -> np.ndarray:
    """Shares of the node layers j = 0, 1, … of a uniform body force over [0, ``depth``] below the
    front face: their tributary thicknesses inside it, normalised, shape (J,) (module docstring);
    ``depth`` 0 is the front face alone."""
    y = mesh.grid.y - mesh.grid.y[0]
    check_deposition_depth(depth, y[-1])
    if depth == 0.0:
        return np.ones(1)
    mid = 0.5 * (y[:-1] + y[1:])
    lo = np.concatenate([[0.0], mid])
    hi = np.concatenate([mid, [y[-1]]])
    inside = np.minimum(hi, depth) - lo
    inside[inside <= 1e-12 * depth] = 0.0       # a layer starting at δ up to round-off takes nothing
    inside = inside[:np.flatnonzero(inside)[-1] + 1]
    return inside / inside.sum()


def _cell_stencils(mesh: WallMesh, cells: np.ndarray, spread: str) -> list[tuple[np.ndarray, np.ndarray]]:
    """(front-face nodes, weights) of each of the case grid's face ``cells``: the ``spread`` on the load
    grid's face cells, and on a graded mesh the shares of those the case's cell overlaps (by area:
    products of 1-D overlaps) — a uniform areal impulse over the case's cell, summed per node."""
    face_nodes, face_weights = _face_stencil(mesh, spread)
    if mesh.load_grid is mesh.parent:
        return [(face_nodes[c], face_weights[c]) for c in cells]
    stencils = []
    for fine, share in face_overlaps(mesh.parent, mesh.load_grid, cells):
        node, at = np.unique(face_nodes[fine].ravel(), return_inverse=True)
        stencils.append((node, np.bincount(at, (share[:, None] * face_weights[fine]).ravel(), node.size)))
    return stencils


def nodal_load(mesh: WallMesh, deposition: WallDeposition, spread: str, depth: float | None = None) -> NodalLoad:
    """The deposition on ``mesh``'s nodes with the ``spread`` on the front face, carried to the
    ``depth`` below it (None: :func:`default_depth`; module docstring).

    ``deposition`` lies on the case's grid (``mesh.parent``), whatever the mesh: on a graded mesh
    each record's impulse is shared among the face cells its cell overlaps, by area, and so kept
    exactly (:func:`_cell_stencils`)."""
    if spread not in SPREADS:
        raise InputError(f"spread: {spread!r}, expected one of {SPREADS}")
    deposition.check_fits(mesh.parent)
    order = np.argsort(deposition.time, kind="stable")
    cells, stencil = np.unique(deposition.element[order], return_inverse=True)
    depth = default_depth(mesh) if depth is None else depth
    layer = depth_weights(mesh, depth)
    layer_stride = mesh.grid.x.size * mesh.grid.z.size     # node numbers: i fastest, then k, then j
    nodes, weights = [], []
    for node, weight in _cell_stencils(mesh, cells, spread):
        nodes.append((node[:, None] + layer_stride * np.arange(layer.size)).ravel())
        weights.append((weight[:, None] * layer).ravel())
    ptr = np.concatenate([[0], np.cumsum([n.size for n in nodes])]).astype(np.int64)
    return NodalLoad(time=np.ascontiguousarray(deposition.time[order], dtype=np.float64),
                     impulse=np.ascontiguousarray(deposition.impulse[order], dtype=np.float64),
                     stencil=np.ascontiguousarray(stencil, dtype=np.int64), ptr=ptr,
                     node=np.ascontiguousarray(np.concatenate(nodes) if nodes else np.zeros(0), dtype=np.int64),
                     weight=np.ascontiguousarray(np.concatenate(weights) if weights else np.zeros(0)),
                     depth=float(depth))
