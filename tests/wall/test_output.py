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


def test_lean_skips_the_series(result, tmp_path):
    files = wall.write_wall_outputs(result, tmp_path, lean=True)
    assert "pvd" not in files and not (tmp_path / "wall.pvd").exists()
    assert (tmp_path / "plots" / "wall_front.png").exists() and (tmp_path / "wall.json").exists()
