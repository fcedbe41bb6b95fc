"""The files of a wall run: ParaView series, surface maps, history plot and measures."""

import json
import xml.etree.ElementTree as ET

import meshio
import numpy as np
import pytest

from impactdyn import wall
from impactdyn.wallgrid import WallDeposition, WallGrid


@pytest.fixture(scope="module")
def result():
    grid = WallGrid.uniform((0.0, 0.8), (0.0, 0.3175), (-0.4, 0.4), (6, 3, 6))
    dep = WallDeposition(element=np.array([0, 1, 5, 6]), time=np.array([0.0, 0.0, 0.2, 0.3]),
                         impulse=np.array([[0.0, 5e-4, 0.0]] * 4))
    return wall.run_wall(grid, dep, "al6061-t6", wall.WallOptions(end_time_us=3.0, output_interval_us=1.0))


def test_result_shape(result):
    assert [round(f.time, 6) for f in result.frames][0] == 0.0
    assert len(result.frames) >= 4 and result.frames[-1].time >= 3.0
    n = len(result.history["time"])
    assert all(len(v) == n for v in result.history.values())
    assert result.final.displacement.shape == (result.mesh.n_nodes, 3)
    assert result.measures["rear_bulge_cm"] > 0.0


def test_files(result, tmp_path):
    files = wall.write_wall_outputs(result, tmp_path / "wall", plots=tmp_path / "plots")
    assert set(files) == {"pvd", "json", "front", "rear", "history"}
    for key in ("front", "rear", "history"):
        assert files[key].stat().st_size > 10_000 and files[key].suffix == ".png"
    root = ET.parse(files["pvd"]).getroot()
    datasets = root.findall("./Collection/DataSet")
    assert len(datasets) == len(result.frames)
    last = meshio.read(files["pvd"].parent / datasets[-1].get("file"))
    assert last.cells[0].type == "hexahedron" and len(last.cells[0].data) == result.mesh.n_elements
    for name in ("displacement", "velocity"):
        assert last.point_data[name].shape == (result.mesh.n_nodes, 3)
    for name in ("plastic_strain", "damage", "failed", "eroded", "pressure", "von_mises"):
        assert last.cell_data[name][0].shape == (result.mesh.n_elements,)
    np.testing.assert_allclose(last.points, result.mesh.coordinates + result.final.displacement, rtol=1e-6)
    doc = json.loads(files["json"].read_text())
    assert doc["verdict"] == result.verdict and doc["options"]["material_model"] == wall.WallOptions().material_model
    assert doc["measures"]["energy"]["load_work"] > 0
    # nothing half-written left behind
    assert not list(tmp_path.rglob(".*tmp*"))


def test_series_none_skips_the_series(result, tmp_path):
    files = wall.write_wall_outputs(result, tmp_path, series="none")
    assert "pvd" not in files and not (tmp_path / "wall.pvd").exists()
    assert (tmp_path / "plots" / "wall_front.png").exists() and (tmp_path / "wall.json").exists()


def test_a_lean_series_keeps_fewer_lighter_frames_paraview_can_open(result, tmp_path):
    files = wall.write_wall_outputs(result, tmp_path, series="lean")
    frames = [d.get("file") for d in ET.parse(files["pvd"]).getroot().iter("DataSet")]
    times = [float(d.get("timestep")) for d in ET.parse(files["pvd"]).getroot().iter("DataSet")]
    assert sorted((tmp_path / "wall_series").iterdir()) == [tmp_path / f for f in frames]
    assert times[-1] == result.final.time and len(frames) <= len(result.frames)
    last = meshio.read(tmp_path / frames[-1])
    assert last.points.dtype == np.float32 and "velocity" not in last.point_data
    np.testing.assert_allclose(last.point_data["displacement"], result.final.displacement)
    np.testing.assert_array_equal(last.cell_data["failed"][0], result.final.failed)
    with pytest.raises(ValueError, match="series"):
        wall.write_wall_outputs(result, tmp_path, series="some")


def test_lean_frames_are_one_per_interval_and_the_last():
    from impactdyn.wall._output import lean_frames

    times = 12.5 + 2.0 * np.arange(44)                 # a 7a run's frames: 12.5 ... 98.5 µs
    picked = lean_frames(np.append(times, 100.0))
    np.testing.assert_array_equal(picked, [0, 5, 10, 15, 20, 25, 30, 35, 40, 44])
    np.testing.assert_array_equal(lean_frames(np.array([3.0])), [0])
