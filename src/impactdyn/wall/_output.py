"""Files of a wall run: ParaView time series, surface maps, history plot, measures (all written atomically).

:func:`write_wall_outputs` writes, into ``folder``:

* ``wall.pvd`` + ``wall_series/wall_NNNN.vtu`` — the ParaView time series: the deformed mesh
  (hexahedra) with point data ``displacement`` (cm) and ``velocity`` (cm/µs) and cell data
  ``plastic_strain``, ``damage``, ``failed``, ``eroded``, ``failure_cause`` (0 intact, else 1 +
  the index of the criterion in :data:`impactdyn.wall.FAILURE_CAUSES`), ``pressure`` (Mbar) and
  ``von_mises`` (Mbar); eroded elements stay in the mesh, flagged (threshold on ``eroded`` to
  hide them).  ``series`` says how much of it: ``"all"`` every frame of the run
  (``output_interval_us``, 2 µs by default: ~270 MB on the graded 7a wall), ``"lean"`` the
  frames :func:`lean_frames` picks (one per :data:`LEAN_FRAME_INTERVAL_US`, and the last),
  written as :data:`LEAN_FIELDS` (no ``velocity``: at that spacing the series shows how the
  crater and bulge grew, not the waves that a velocity field shows) with float32 points and
  int32 connectivity, LZMA-compressed (VTK's ``vtkLZMADataCompressor``, read by ParaView 5.5 and
  later and by meshio): on 7a 10 frames, ~3.2 MB each against 6.1 MB (zlib, float64 points and
  velocity) and 4.3 MB with zlib, writing ~1.3 s more per frame; ``"none"`` no series;
* ``wall.json`` — verdict, evidence, measures, energy and momentum balance, model constants,
  the mesh (:meth:`WallMesh.describe`: kind, elements, counts, element-size ranges) and options;

and into ``plots`` (default ``folder/plots``):

* ``wall_front.png`` and ``wall_rear.png`` — maps of the front (impacted) and rear surfaces
  at the end of the run, in the manner of the report's surface figures (Figures 6–7, 11,
  14, 17, 20): effective plastic strain of the surface elements, failed and eroded elements,
  and the normal displacement u_y of the surface (positive into the wall at the front, out of
  it at the rear); the half model is mirrored about its symmetry plane x = 0;
* ``wall_history.png`` — energies against time (work of the load, kinetic, internal,
  plastic, hourglass, bulk viscous, eroded) and the rear bulge and front dent.
"""

from __future__ import annotations

import json
import os
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

from impactdyn.io import atomic_output, write_mesh
from impactdyn.units import KM_S_PER_CM_US
from impactdyn.wall._result import WallFrame, WallResult

#: Unit of the energies in the history plot: 1 g·cm²/µs² = 10⁵ J; the plot shows J.
_J_PER_ENERGY = 1.0e5


#: Time between the frames of a lean ParaView series (µs): ~10 frames of a 100-µs wall run.
LEAN_FRAME_INTERVAL_US = 10.0

#: The fields of a lean series' frames (point data, cell data); the full series adds ``velocity``.
LEAN_FIELDS = (("displacement",), ("plastic_strain", "damage", "failed", "eroded", "failure_cause", "pressure",
                                   "von_mises"))

SERIES = ("all", "lean", "none")


def write_wall_outputs(result: WallResult, folder: str | os.PathLike, plots: str | os.PathLike | None = None,
                       series: str = "all", figures: bool = True) -> dict[str, Path]:
    """Write the files of the module docstring; returns them by kind (pvd, json, front, rear, history).

    ``series``: the ParaView series' frames, "all", "lean" or "none" (module docstring); ``figures``: whether
    to draw the three figures into ``plots`` (default ``folder/plots``)."""
    if series not in SERIES:
        raise ValueError(f"series = {series!r}: choose one of {', '.join(SERIES)}")
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    files: dict[str, Path] = {}
    if series != "none":
        files["pvd"] = write_time_series(result, folder, lean=series == "lean")
    files["json"] = write_measures(result, folder / "wall.json")
    if figures:
        plots = Path(plots) if plots is not None else folder / "plots"
        plots.mkdir(parents=True, exist_ok=True)
        files["front"] = plot_surface(result, "front", plots / "wall_front.png")
        files["rear"] = plot_surface(result, "rear", plots / "wall_rear.png")
        files["history"] = plot_history(result, plots / "wall_history.png")
    return files


def _vtu_mesh(result: WallResult, frame: WallFrame, lean: bool = False):
    import meshio

    m = result.mesh
    points = m.coordinates + frame.displacement.astype(np.float64)
    cell_data = {
        "plastic_strain": [frame.plastic_strain], "damage": [frame.damage],
        "failed": [frame.failed.astype(np.uint8)], "eroded": [frame.eroded.astype(np.uint8)],
        "failure_cause": [frame.failure_cause.astype(np.uint8)],
        "pressure": [frame.pressure], "von_mises": [frame.von_mises],
    }
    point_data = {"displacement": frame.displacement, "velocity": frame.velocity}
    connectivity = m.connectivity
    if lean:  # float32 points: 1e-7 of a 10-cm wall, far below any displacement the series shows
        points, connectivity = points.astype(np.float32), connectivity.astype(np.int32)
        point_data = {key: point_data[key] for key in LEAN_FIELDS[0]}
        cell_data = {key: cell_data[key] for key in LEAN_FIELDS[1]}
    return meshio.Mesh(points, [("hexahedron", connectivity)], point_data=point_data, cell_data=cell_data)


def lean_frames(times: np.ndarray, interval: float = LEAN_FRAME_INTERVAL_US) -> np.ndarray:
    """Indices of the frames a lean series keeps: the first, the first frame at or after each further
    multiple of ``interval`` past the first frame's time, and the last (times ascending)."""
    times = np.asarray(times, dtype=float)
    slot = np.floor((times - times[0]) / interval + 1e-9)
    keep = np.flatnonzero(np.diff(slot, prepend=-1.0) > 0)
    return np.union1d(keep, [times.size - 1])


def write_time_series(result: WallResult, folder: str | os.PathLike, name: str = "wall", lean: bool = False) -> Path:
    """``name.pvd`` and one ``name_series/name_NNNN.vtu`` per frame (``lean``: the frames of
    :func:`lean_frames`, lighter: module docstring); returns the .pvd path."""
    folder = Path(folder)
    series = folder / f"{name}_series"
    series.mkdir(parents=True, exist_ok=True)
    root = ET.Element("VTKFile", type="Collection", version="0.1", byte_order="LittleEndian")
    coll = ET.SubElement(root, "Collection")
    frames = result.frames
    if lean:
        frames = [frames[i] for i in lean_frames(np.array([f.time for f in frames]))]
    for k, frame in enumerate(frames):
        path = series / f"{name}_{k:04d}.vtu"
        write_mesh(path, _vtu_mesh(result, frame, lean), **({"compression": "lzma"} if lean else {}))
        ET.SubElement(coll, "DataSet", timestep=repr(float(frame.time)), group="", part="0",
                      file=f"{series.name}/{path.name}")
    pvd = folder / f"{name}.pvd"
    with atomic_output(pvd) as tmp:
        ET.ElementTree(root).write(tmp, encoding="utf-8", xml_declaration=True)
    return pvd


def _json_default(obj):
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, np.generic):
        return obj.item()
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")


def write_measures(result: WallResult, path: str | os.PathLike) -> Path:
    """Verdict, measures, model and options as JSON."""
    path = Path(path)
    doc = {**result.summary(), "options": result.options.model_dump(),
           "units": {"length": "cm", "time": "us", "mass": "g", "velocity": "cm/us (km/s where named)",
                     "energy": "g cm^2/us^2 = 1e5 J", "impulse": "g cm/us", "pressure": "Mbar"}}
    with atomic_output(path) as tmp:
        tmp.write_text(json.dumps(doc, indent=2, default=_json_default) + "\n")
    return path


def _mirrored(xs: np.ndarray, values: np.ndarray, axis: int) -> tuple[np.ndarray, np.ndarray]:
    """Mirror a half-model field about x = xs[0] (x along ``axis`` of values)."""
    x2 = np.concatenate([2 * xs[0] - xs[:0:-1], xs])
    flipped = np.flip(values, axis=axis)
    if values.shape[axis] == xs.size:  # nodal: do not repeat the plane's nodes
        flipped = np.take(flipped, np.arange(values.shape[axis] - 1), axis=axis)
    return x2, np.concatenate([flipped, values], axis=axis)


def plot_surface(result: WallResult, side: str, path: str | os.PathLike) -> Path:
    """Map of the front or rear surface at the end of the run (module docstring)."""
    from matplotlib.colors import ListedColormap

    from impactdyn._plotting import pyplot, save_figure

    plt = pyplot()
    m, f = result.mesh, result.final
    layer = m.layer_elements(0 if side == "front" else m.shape[1] - 1)  # [k, i]
    nodes = m.face_nodes(side)                                          # [k, i]
    x, z = m.grid.x, m.grid.z
    eps = f.plastic_strain[layer].astype(float)
    state = np.where(f.eroded[layer], 2, np.where(f.failed[layer], 1, 0)).astype(float)
    uy = f.displacement[nodes, 1].astype(float)
    mirror = m.supports in ("dyngen", "clamped")
    if mirror:
        xe, eps = _mirrored(x, eps, axis=1)
        _, state = _mirrored(x, state, axis=1)
        _, uy = _mirrored(x, uy, axis=1)
    else:
        xe = x
    fig, axes = plt.subplots(1, 3, figsize=(14, 5.2), sharey=True, constrained_layout=True)
    im = axes[0].pcolormesh(xe, z, eps, cmap="viridis", shading="flat")
    fig.colorbar(im, ax=axes[0], shrink=0.8, label="effective plastic strain")
    axes[0].set_title("plastic strain")
    cmap = ListedColormap(["#dddddd", "#d62728", "#000000"])
    axes[1].pcolormesh(xe, z, state, cmap=cmap, vmin=-0.5, vmax=2.5, shading="flat")
    axes[1].set_title("failed (red) and eroded (black) elements")
    lim = float(np.abs(uy).max()) or 1.0
    im = axes[2].pcolormesh(xe, z, uy, cmap="RdBu_r", vmin=-lim, vmax=lim, shading="gouraud")
    fig.colorbar(im, ax=axes[2], shrink=0.8, label="u_y (cm; +: along y, front → rear)")
    axes[2].set_title("normal displacement")
    for ax in axes:
        ax.set_aspect("equal")
        ax.set_xlabel("x (cm)")
        if mirror:
            ax.axvline(x[0], color="k", lw=0.5, ls=":")
    axes[0].set_ylabel("z (cm)")
    fig.suptitle(f"Wall {side} surface at t = {f.time:.2f} µs: {result.verdict} "
                 f"(crater depth / t = {result.measures['crater_depth_ratio']:.2f}, "
                 f"rear bulge {result.measures['rear_bulge_cm']:.3f} cm)")
    return save_figure(fig, path)


def plot_history(result: WallResult, path: str | os.PathLike) -> Path:
    """Energies and the rear bulge against time."""
    from impactdyn._plotting import pyplot, save_figure

    plt = pyplot()
    h = result.history
    t = h["time"]
    fig, (ax, bx) = plt.subplots(2, 1, figsize=(8, 7.5), sharex=True, constrained_layout=True)
    for key, label in (("load_work", "work of the load"), ("kinetic", "kinetic"), ("internal", "internal"),
                       ("plastic", "plastic"), ("hourglass", "hourglass"), ("bulk_viscous", "bulk viscous"),
                       ("eroded", "eroded")):
        ax.plot(t, h[key] * _J_PER_ENERGY, label=label)
    ax.set_ylabel("energy (J)")
    ax.legend(fontsize=8, ncol=2)
    ax.set_title(f"Wall energy balance (error at the end {result.measures['energy']['balance_error']:.2e})")
    bx.plot(t, h["rear_bulge"], label="rear bulge")
    bx.plot(t, h["front_dent"], label="front dent")
    bx.set_ylabel("displacement (cm)")
    bx.set_xlabel("t (µs)")
    cx = bx.twinx()
    cx.plot(t, h["rear_velocity"] * KM_S_PER_CM_US, color="0.5", lw=0.8, label="largest rear-face v_y")
    cx.set_ylabel("rear-face velocity (km/s)")
    lines = bx.get_lines() + cx.get_lines()
    bx.legend(lines, [ln.get_label() for ln in lines], fontsize=8)
    return save_figure(fig, path)
