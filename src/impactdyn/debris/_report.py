"""Run folder of the debris stage: summary, DCPOST tables, HDF5, VTK, wall decks and plots.

Files (``case.output`` switches the optional ones):

``summary.json``                  headline numbers (:meth:`DebrisResult.summary`) and the file list
``config.resolved.toml``          every parameter used (the run's case, defaults included)
``areal_density.csv``             DCPOST: impulse and areal density per wall face element
``areal_density_remap.csv``       the same on ``wall.remap``'s grid, if given
``handoff_grid.h5``               the HydroGrid the particles were seeded from (readable as a case's grid.file)
``debris.h5``                     all arrays: particles, arrival states, deposition, wall
``particles_handoff.vtu``         particles as tetrahedra at hand-off (ParaView)
``particles_arrival.vtu``         the propagated particles at their arrival
``wall_deposition.vtu``           the wall's front face with impulse and areal density per element
``wall.k``                        LS-DYNA keyword deck, time-resolved loads (:mod:`impactdyn.io._lsdyna`)
``wall_dyna3d.inp``               the legacy DYNA3D deck with DCPOST's cards (summed per element, t = 0)
``plots/areal_density.png``       DCMPLT's contour map
``plots/cloud.png``               side and top views of the cloud at hand-off and at arrival

Times are µs after the hand-off; units cm, g, µs (momentum g·cm/µs = 10 N·s).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from impactdyn._config import dump_toml
from impactdyn._errors import InputError
from impactdyn._runfolder import FolderWriter, RunFolder, atomic_output
from impactdyn.debris._deposit import areal_density, element_records, face_areas, remap_impulse
from impactdyn.debris._particle import P_SLICE
from impactdyn.debris._propagate import DebrisResult
from impactdyn.debris._tets import signed_volume
from impactdyn.materials import AL_6061_T6_MAT13, Mat13Card
from impactdyn.wallgrid import WallDeposition, WallGrid

AREAL_HEADER = ["i", "k", "element", "x_cm", "z_cm", "px_g_cm_us", "py_g_cm_us", "pz_g_cm_us",
                "areal_density_g_cm_us"]


def areal_rows(impulse: np.ndarray, wall: WallGrid) -> list[list]:
    """DCPOST's table: one row per face element, i fastest (element i + nx k)."""
    areal = areal_density(impulse, wall)
    xc = 0.5 * (wall.x[:-1] + wall.x[1:])
    zc = 0.5 * (wall.z[:-1] + wall.z[1:])
    nx, _, nz = wall.shape
    return [[i, k, i + nx * k, xc[i], zc[k], *impulse[i, k], areal[i, k]] for k in range(nz) for i in range(nx)]


def write_debris_run(result: DebrisResult, case, outdir: str | Path, *, force: bool = False,
                     remap: WallGrid | None = None, dcpost_factor: float = 1.0,
                     extra_summary: dict | None = None) -> dict:
    """Write the run folder atomically; returns the summary written."""
    with RunFolder(outdir, force=force) as rf:
        return write_debris_files(rf, result, case, remap=remap, dcpost_factor=dcpost_factor,
                                  extra_summary=extra_summary)


def write_debris_files(folder: FolderWriter, result: DebrisResult, case, *, remap: WallGrid | None = None,
                       dcpost_factor: float = 1.0, extra_summary: dict | None = None,
                       wall_material: Mat13Card = AL_6061_T6_MAT13, decks: bool = True) -> dict:
    """Every file of the module docstring into ``folder``; returns the summary (also ``summary.json``).

    ``decks=False`` leaves the wall decks out (the Whipple pipeline writes them in a stage of their own).
    """
    o = case.output
    summary = result.summary() | (extra_summary or {})
    files = ["summary.json", "config.resolved.toml", "areal_density.csv"]
    folder.write_text("config.resolved.toml", dump_toml(case))
    folder.write_csv("areal_density.csv", AREAL_HEADER, areal_rows(result.impulse, result.wall))
    if remap is not None:
        moved = remap_impulse(result.impulse, result.wall, remap)
        folder.write_csv("areal_density_remap.csv", AREAL_HEADER, areal_rows(moved, remap))
        summary["remap"] = {"momentum_deposited": moved.reshape(-1, 3).sum(axis=0).tolist(),
                            "peak_areal_density_g_cm_us": float(areal_density(moved, remap).max())}
        files.append("areal_density_remap.csv")
    if o.hdf5:
        from impactdyn.io import write_grid

        write_grid(folder.file("handoff_grid.h5"), result.grid)
        write_hdf5(result, folder.file("debris.h5"))
        files += ["handoff_grid.h5", "debris.h5"]
    if o.vtk:
        files += write_vtk(result, folder.path, o.max_vtk_particles)
    if decks:
        files += write_decks(folder, result.wall, result.deposition, result.impulse, case, dcpost_factor,
                             wall_material)
    if o.plots:
        write_plots(result, folder.path / "plots")
        files += ["plots/areal_density.png", "plots/cloud.png"]
    summary["files"] = sorted(files)
    folder.write_json("summary.json", summary)
    return summary


def write_decks(folder: FolderWriter, wall: WallGrid, deposition: WallDeposition, impulse: np.ndarray, case,
                dcpost_factor: float = 1.0, material: Mat13Card = AL_6061_T6_MAT13) -> list[str]:
    """The wall decks ``case.output`` asks for: LS-DYNA (time-resolved loads) and DYNA3D (DCPOST's cards)."""
    o, written = case.output, []
    if o.lsdyna_deck:
        from impactdyn.io import write_lsdyna_deck

        end = o.end_time_us or (float(deposition.time.max()) + 10.0 if deposition.time.size else 10.0)
        write_lsdyna_deck(folder.file("wall.k"), wall, material, deposition, pulse_width=o.pulse_width_us,
                          end_time=end, clamped_edges=case.wall.clamped_edges,
                          title=case.title or "impactdyn rear wall under debris-cloud deposition")
        written.append("wall.k")
    if o.dyna3d_deck:
        from impactdyn.io import write_dyna3d_deck

        write_dyna3d_deck(folder.file("wall_dyna3d.inp"), wall, material, element_records(impulse, dcpost_factor),
                          clamped_edges=case.wall.clamped_edges)
        written.append("wall_dyna3d.inp")
    return written


def write_hdf5(result: DebrisResult, path: Path) -> None:
    """The run's arrays in one HDF5 file (groups particles, arrival, deposition, wall; the grid is
    ``handoff_grid.h5``)."""
    import h5py

    r, c = result, result.cloud
    with atomic_output(path) as tmp, h5py.File(tmp, "w") as f:
        f.attrs["units"] = "cm, g, us; momentum g*cm/us; times after hand-off"
        f.attrs["t_handoff_us"] = r.t_handoff
        p = f.create_group("particles")
        for name in ("vertices", "states", "J", "mass", "void_fraction", "density_ratio", "cell", "tet"):
            p.create_dataset(name, data=getattr(c, name), compression="gzip")
        p.create_dataset("t_arrival", data=r.t_arrival)
        a = f.create_group("arrival")
        a.create_dataset("index", data=r.propagated)
        a.create_dataset("states", data=r.states, compression="gzip")
        a.create_dataset("points", data=r.points, compression="gzip")
        a.create_dataset("on_wall", data=r.on_wall)
        for name in ("steps", "rejected", "code", "t_reached"):
            a.create_dataset(name, data=getattr(r.stats, name))
        d = f.create_group("deposition")
        for name in ("element", "time", "impulse"):
            d.create_dataset(name, data=getattr(r.deposition, name), compression="gzip")
        w = f.create_group("wall")
        for name in ("x", "y", "z"):
            w.create_dataset(name, data=getattr(r.wall, name))
        w.create_dataset("impulse", data=r.impulse)
        w.create_dataset("areal_density", data=r.areal)


def read_deposition(path: str | Path) -> tuple[WallGrid, WallDeposition, np.ndarray]:
    """The wall, its time-resolved deposition and the impulse per element ``(nx, nz, 3)`` of a ``debris.h5``."""
    from impactdyn.io import open_hdf5

    path = Path(path)
    with open_hdf5(path) as f:
        try:
            w, d = f["wall"], f["deposition"]
            wall = WallGrid(x=w["x"][()], y=w["y"][()], z=w["z"][()])
            dep = WallDeposition(element=d["element"][()], time=d["time"][()], impulse=d["impulse"][()])
            impulse = w["impulse"][()]
        except KeyError as err:
            raise InputError(f"{path}: not a debris.h5 file ({err})") from None
    return wall, dep, impulse


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
            "mass_g": [c.mass], "velocity_cm_us": [velocity], "speed_km_s": [10.0 * np.linalg.norm(velocity, axis=1)],
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


def write_plots(result: DebrisResult, folder: Path) -> None:
    """DCMPLT's contour map of the areal density, and the cloud at hand-off and arrival."""
    from impactdyn._plotting import pyplot, save_figure

    plt = pyplot()

    folder.mkdir(parents=True, exist_ok=True)
    w, r = result.wall, result
    xc = 0.5 * (w.x[:-1] + w.x[1:])
    zc = 0.5 * (w.z[:-1] + w.z[1:])
    fig, ax = plt.subplots(figsize=(6, 7), constrained_layout=True)
    areal = r.areal.T
    if np.any(areal > 0):
        levels = np.linspace(0.0, areal.max(), 16)
        cs = ax.contourf(xc, zc, areal, levels=levels, cmap="viridis")
        fig.colorbar(cs, ax=ax, label="areal momentum density |Σp|/(Δx Δz)  (g/(cm·µs))")
    else:
        ax.text(0.5, 0.5, "no momentum deposited", transform=ax.transAxes, ha="center")
    ax.set_xlim(w.x[0], w.x[-1])
    ax.set_ylim(w.z[0], w.z[-1])
    ax.set_aspect("equal")
    ax.set_xlabel("x (cm), symmetry plane at x = %.3g" % w.x[0])
    ax.set_ylabel("z (cm)")
    ax.set_title("Momentum deposited on the rear wall (DCPOST)")
    save_figure(fig, folder / "areal_density.png", dpi=120)

    c = r.cloud
    speed = 10.0 * np.linalg.norm(c.states[:, P_SLICE] / c.mass[:, None], axis=1)  # km/s
    fig, axes = plt.subplots(1, 2, figsize=(12, 5.5), constrained_layout=True)
    ax = axes[0]
    sc = ax.scatter(c.centroid[:, 1], c.centroid[:, 2], c=speed, s=2, cmap="plasma")
    fig.colorbar(sc, ax=ax, label="particle speed (km/s)")
    ax.set_xlabel("y (cm), toward the wall")
    ax.set_ylabel("z (cm)")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_title(f"cloud at hand-off, side view (t = {r.t_handoff:g} µs)")
    ax = axes[1]
    arrived = r.stats.code == 0
    if np.any(arrived):
        hit = r.points[arrived, 4]
        sc = ax.scatter(hit[:, 0], hit[:, 2], c=r.t_arrival[r.propagated][arrived], s=2, cmap="viridis")
        fig.colorbar(sc, ax=ax, label="arrival time after hand-off (µs)")
    ax.add_patch(plt.Rectangle((w.x[0], w.z[0]), w.x[-1] - w.x[0], w.z[-1] - w.z[0], fill=False, lw=1))
    ax.set_xlabel("x (cm)")
    ax.set_ylabel("z (cm)")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_title("centroids at arrival on the wall plane (wall outlined)")
    for ax in axes:
        ax.grid(alpha=0.3)
    save_figure(fig, folder / "cloud.png", dpi=120)
