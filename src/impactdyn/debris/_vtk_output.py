"""The VTK files of a debris run (ParaView): particles at hand-off and at arrival, the wall's deposition."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from impactdyn import units
from impactdyn.debris._deposit import face_areas
from impactdyn.debris._propagate import DebrisResult
from impactdyn.debris._tets import signed_volume


def _tet_mesh(vertices: np.ndarray):
    """Points ``(4N, 3)`` and right-handed tetra connectivity ``(N, 4)`` of tetrahedra ``(N, 4, 3)``."""
    cells = np.arange(4 * len(vertices)).reshape(-1, 4)
    flip = signed_volume(vertices) < 0  # the listing's tetrahedra 4 and 5 are left-handed
    cells[flip] = cells[flip][:, [0, 2, 1, 3]]
    return vertices.reshape(-1, 3), cells


def write_vtk(result: DebrisResult, folder: Path, max_particles: int) -> list[str]:
    """Particles at hand-off and at arrival, and the wall's deposition, as VTK unstructured grids."""
    import meshio

    from impactdyn.io import write_mesh

    r, c = result, result.cloud
    written = []
    if 0 < len(c) <= max_particles:
        pts, cells = _tet_mesh(c.vertices)
        velocity = c.momentum / c.mass[:, None]
        write_mesh(folder / "particles_handoff.vtu", meshio.Mesh(pts, [("tetra", cells)], cell_data={
            "mass_g": [c.mass], "velocity_cm_us": [velocity],
            "speed_km_s": [units.cm_us_to_km_s(np.linalg.norm(velocity, axis=1))],
            "t_arrival_us": [np.where(np.isfinite(r.t_arrival), r.t_arrival, -1.0)],
            "density_ratio": [c.density_ratio], "void_fraction": [c.void_fraction]}))
        written.append("particles_handoff.vtu")
    if 0 < len(r.propagated) <= max_particles:
        pts, cells = _tet_mesh(r.points[:, :4])
        sel = r.propagated
        write_mesh(folder / "particles_arrival.vtu", meshio.Mesh(pts, [("tetra", cells)], cell_data={
            "mass_g": [c.mass[sel]], "velocity_cm_us": [c.momentum[sel] / c.mass[sel, None]],
            "t_arrival_us": [r.t_arrival[sel]], "failure_code": [r.stats.code.astype(np.int32)],
            "steps": [r.stats.steps.astype(np.int64)]}))
        written.append("particles_arrival.vtu")
    w = r.wall
    nx, _, nz = w.shape
    X, Z = np.meshgrid(w.x, w.z, indexing="ij")
    pts = np.stack([X.ravel(), np.full(X.size, w.y[0]), Z.ravel()], axis=-1)  # node (i, k) = i (nz+1) + k
    i, k = np.meshgrid(np.arange(nx), np.arange(nz), indexing="ij")
    n0 = (i * (nz + 1) + k).ravel()
    quads = np.stack([n0, n0 + nz + 1, n0 + nz + 2, n0 + 1], axis=-1)
    write_mesh(folder / "wall_deposition.vtu", meshio.Mesh(pts, [("quad", quads)], cell_data={
        "impulse_g_cm_us": [r.impulse.reshape(-1, 3)], "areal_density_g_cm_us": [r.areal.ravel()],
        "area_cm2": [face_areas(w).ravel()]}))
    return written + ["wall_deposition.vtu"]
