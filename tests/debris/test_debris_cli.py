"""`impactdyn debris run` and `debris legacy`: run folders, outputs read back, bad input (issue 3)."""

import json
import tomllib
from pathlib import Path

import h5py
import meshio
import numpy as np
import pytest
import tomli_w

from impactdyn.cli import main
from impactdyn.debris import WallGrid, signed_volume
from impactdyn.io import read_cth_packages, read_grid, read_lsdyna_deck, write_avsout, AvsLayout

EXAMPLE = Path(__file__).parents[2] / "examples" / "debris" / "shell_cloud.toml"


def small_case(tmp_path, **changes) -> Path:
    """The shipped example on a coarse grid (a few hundred particles)."""
    data = tomllib.loads(EXAMPLE.read_text())
    data["grid"]["shell"]["cell_size_cm"] = 0.25
    data["wall"]["nodes"] = [17, 3, 33]
    for key, value in changes.items():
        node = data
        *parents, last = key.split(".")
        for p in parents:
            node = node.setdefault(p, {})
        node[last] = value
    path = tmp_path / "case.toml"
    path.write_text(tomli_w.dumps(data))
    return path


@pytest.fixture(scope="module")
def run_folder(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("debris")
    out = tmp / "run"
    assert main(["debris", "run", str(small_case(tmp)), "-o", str(out)]) == 0
    return out


def test_run_folder_summary_and_conservation(run_folder):
    s = json.loads((run_folder / "summary.json").read_text())
    for key in ("n_cells", "n_particles", "n_arrived", "momentum_in", "momentum_deposited", "integrator",
                "wall_time_s"):
        assert key in s
    assert s["n_arrived"] == s["n_particles"] > 100
    # the whole cloud lands on the wall: the deposited impulse is the momentum that came in
    np.testing.assert_allclose(s["momentum_deposited"], s["momentum_in"], rtol=1e-12)
    assert all((run_folder / f).is_file() for f in s["files"])


def test_resolved_config_reproduces_the_run(run_folder, tmp_path):
    again = tmp_path / "again"
    assert main(["debris", "run", str(run_folder / "config.resolved.toml"), "-o", str(again)]) == 0
    a = json.loads((run_folder / "summary.json").read_text())
    b = json.loads((again / "summary.json").read_text())
    assert a["momentum_deposited"] == b["momentum_deposited"] and a["integrator"] == b["integrator"]


def test_exports_read_back(run_folder):
    s = json.loads((run_folder / "summary.json").read_text())
    grid = read_grid(run_folder / "handoff_grid.h5")
    assert grid.shape == tuple(int(n) for n in np.array(grid.shape))
    with h5py.File(run_folder / "debris.h5") as f:
        impulse = f["wall/impulse"][...]
        dep = f["deposition/impulse"][...]
        mass = f["particles/mass"][...]
    np.testing.assert_allclose(dep.sum(axis=0), s["momentum_deposited"], rtol=1e-13)
    np.testing.assert_allclose(impulse.reshape(-1, 3).sum(axis=0), s["momentum_deposited"], rtol=1e-12)
    np.testing.assert_allclose(mass.sum(), s["mass_seeded_g"], rtol=1e-13)
    # VTK particles: right-handed tetrahedra whose volumes are the cells' (the listing's 4 and 5 flipped)
    m = meshio.read(run_folder / "particles_handoff.vtu")
    tets = m.points[m.cells_dict["tetra"]]
    vol = signed_volume(tets)
    assert np.all(vol > 0) and len(vol) == s["n_particles"]
    np.testing.assert_allclose(m.cell_data["mass_g"][0].sum(), s["mass_seeded_g"], rtol=1e-12)
    wall = meshio.read(run_folder / "wall_deposition.vtu")
    np.testing.assert_allclose(wall.cell_data["impulse_g_cm_us"][0].sum(axis=0), s["momentum_deposited"],
                               rtol=1e-12)
    # the keyword deck carries the deposition: its load curves integrate to the deposited impulse
    deck = read_lsdyna_deck(run_folder / "wall.k")
    total = np.zeros(3)
    for (nid, dof, lcid), sf in zip(deck.point_loads, deck.point_load_scale):
        t, f = deck.curves[lcid]
        total[dof - 1] += sf * np.trapezoid(f, t)
    np.testing.assert_allclose(total, s["momentum_deposited"], rtol=1e-9)
    csv = np.loadtxt(run_folder / "areal_density.csv", delimiter=",", skiprows=1)
    np.testing.assert_allclose(csv[:, 5:8].sum(axis=0), s["momentum_deposited"], rtol=1e-9)


def test_existing_folder_needs_force(run_folder, tmp_path, capsys):
    case = small_case(tmp_path)
    assert main(["debris", "run", str(case), "-o", str(run_folder)]) == 2
    assert "--force" in capsys.readouterr().err


@pytest.mark.parametrize("change, words", [
    ({"material.mu_Mbar": -1.0}, "material.mu_Mbar"),
    ({"wall.x_cm": [8.0, 0.0]}, "wall.x_cm"),
    ({"integrator.method": "euler"}, "integrator"),
    ({"grid.shell.void_fraction": 1.0}, "grid.shell.void_fraction"),
    ({"filter.t_cut_us": 0.0}, "filter.t_cut_us"),
    ({"compute.scheduler": "mpi"}, "compute.scheduler"),
    ({"bogus": 1}, "bogus: unknown key"),
    ({"grid.file": "nowhere.h5"}, "grid"),
    ({"wall.y_cm": [-9.0, -8.7]}, "lies behind or inside the debris"),
])
def test_bad_input_exit_2_and_nothing_written(tmp_path, capsys, change, words):
    out = tmp_path / "out"
    assert main(["debris", "run", str(small_case(tmp_path, **change)), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert words in err and "Traceback" not in err
    assert not out.exists() and [p.name for p in tmp_path.iterdir()] == ["case.toml"]


def test_missing_grid_file_is_named(tmp_path, capsys):
    case = small_case(tmp_path)
    data = tomllib.loads(case.read_text())
    del data["grid"]["shell"]
    data["grid"]["file"] = "missing.h5"
    case.write_text(tomli_w.dumps(data))
    assert main(["debris", "run", str(case), "-o", str(tmp_path / "o")]) == 2
    assert "missing.h5: no such file" in capsys.readouterr().err


#: A dc3din of an 8 x 6 x 8 cell dump, its run type to fill in (``.format(itype=, jtype=)``).
DC3DIN = (Path(__file__).parents[1] / "data" / "small_dc3din.txt").read_text()


def legacy_inputs(tmp_path, itype=2, jtype=1):
    """A dc3din and an avsout of a block of aluminium flying at the wall at 5 km/s (CTH units, cgs)."""
    layout = AvsLayout(2, 9, 2, 7, 2, 9, 0.0, 0.1, -1.0, 0.1, 0.0, 0.1)
    x, y, z = layout.nodes()
    shape = layout.shape
    ones = np.ones(shape)
    from impactdyn.hydrogrid import HydroGrid

    grid = HydroGrid(x, y, z, density=2.7 * ones, void_fraction=0.0 * ones, mass=2.7e-3 * ones,
                     pressure=0 * ones, temperature=300 * ones, specific_energy=0 * ones, sound_speed=0.5 * ones,
                     velocity=np.broadcast_to([0.0, 0.5, 0.0], shape + (3,)), staggered=True)
    write_avsout(tmp_path / "avsout", grid, layout)
    (tmp_path / "dc3din").write_text(DC3DIN.format(itype=itype, jtype=jtype))
    return tmp_path / "dc3din", tmp_path / "avsout"


def test_legacy_propagate_and_decks(tmp_path):
    dc3din, avsout = legacy_inputs(tmp_path)
    out = tmp_path / "legacy"
    assert main(["debris", "legacy", str(dc3din), str(avsout), "-o", str(out)]) == 0
    s = json.loads((out / "summary.json").read_text())
    # interior cells 2..n-1 of the 8 x 6 x 8 dump
    assert s["n_particles"] == 5 * 6 * 4 * 6 and s["n_arrived"] == s["n_particles"]
    np.testing.assert_allclose(s["momentum_deposited"], s["momentum_in"], rtol=1e-12)
    # the new wall grid differs: DCPOST's remap keeps the impulse
    np.testing.assert_allclose(s["remap"]["momentum_deposited"], s["momentum_deposited"], rtol=1e-12)
    deck = (out / "wall_dyna3d.inp").read_text().splitlines()
    assert deck[1].split()[1:3] == ["251", "129"]  # 9 x 3 x 9 + 8 nodes, 8 x 2 x 8 + 1 elements
    # the resolved config is a case of its own, next to the hand-off grid it names
    resolved = tomllib.loads((out / "config.resolved.toml").read_text())
    assert resolved["grid"]["file"] == "handoff_grid.h5" and resolved["legacy"]["eta_per_volume"]
    assert main(["debris", "run", str(out / "config.resolved.toml"), "-o", str(tmp_path / "rerun")]) == 0


def test_legacy_deck_only_and_rezone(tmp_path):
    dc3din, avsout = legacy_inputs(tmp_path, 2, 3)
    assert main(["debris", "legacy", str(dc3din), "-o", str(tmp_path / "deck")]) == 0
    s = json.loads((tmp_path / "deck" / "summary.json").read_text())
    assert (s["wall_nodes"], s["wall_elements"]) == (5 * 3 * 5, 4 * 2 * 4)  # the new grid
    dc3din, avsout = legacy_inputs(tmp_path, 1, 1)
    out = tmp_path / "rezone"
    assert main(["debris", "legacy", str(dc3din), str(avsout), "-o", str(out)]) == 0
    pk = read_cth_packages(out / "cth_packages.txt")
    assert len(pk["density"]) == 5 * 6 * 4 * 6
    np.testing.assert_allclose(pk["velocity"][:, 1], 0.5e6, rtol=1e-6)  # cm/s
    # each pyramid holds its particle's mass at the written density (solid cells: volume / 5 shares)
    vol = np.abs(signed_volume(pk["corners"]))
    np.testing.assert_allclose((vol * pk["density"]).reshape(-1, 5).sum(axis=1), 2.7e-3, rtol=1e-5)
    assert main(["debris", "legacy", str(dc3din), "-o", str(tmp_path / "x")]) == 2  # avsout needed


@pytest.mark.parametrize("line, text, message", [
    (30, "            0.0            5.0         1.0e-6", "dc3din:30: integrator.eps: must be less than 1"),
    (20, "         9         3         9         1         3         5", "dc3din:20: wall.remap.nodes[0]: must be "
                                                                            "greater than or equal to 2"),
    (28, "          1.0e4          0.503          2.703         1.0e-2", "dc3din:28: material: (lambda_Mbar + 2 "
                                                                            "mu_Mbar) / rho_ref_g_cm3 gives"),
    (14, "            0.0            0.1", "dc3din:24: ydmin = 0: the wall's front face lies behind or inside the "
                                          "debris of"),  # ylow: the dump's cells moved into the wall
])
def test_legacy_values_the_case_refuses_name_the_dc3din_line(tmp_path, capsys, line, text, message):
    """The dc3din's records become a debris case: its bounds and the seeding's checks name the record's line."""
    dc3din, avsout = legacy_inputs(tmp_path)
    lines = dc3din.read_text().splitlines()
    lines[line - 1] = text
    dc3din.write_text("\n".join(lines) + "\n")
    assert main(["debris", "legacy", str(dc3din), str(avsout), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert f"{tmp_path / message}" in err and "Traceback" not in err, err


def test_usage_errors_exit_2(capsys):
    assert main(["debris", "run"]) == 2


def test_legacy_truncated_avsout_names_the_file(tmp_path, capsys):
    dc3din, avsout = legacy_inputs(tmp_path)
    lines = avsout.read_text().splitlines()
    avsout.write_text("\n".join(lines[:-7]) + "\n")
    assert main(["debris", "legacy", str(dc3din), str(avsout), "-o", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert str(avsout) in err and "Traceback" not in err and not (tmp_path / "o").exists()


def test_the_areal_momentum_map_is_drawn_in_the_reports_unit():
    """The map's colour bar is in N·s/cm² (units.AREAL_MOMENTUM_UNIT, the report's tables' unit and the docs'),
    its values too: 10 × the g/(cm·µs) the deposition holds."""
    from impactdyn._plotting import pyplot
    from impactdyn.debris._plots import areal_momentum_figure
    from impactdyn.units import AREAL_MOMENTUM_UNIT

    areal = np.zeros((4, 6))
    areal[1, 2] = 0.0123                      # g/(cm·µs): 0.123 N·s/cm², the 7a example's peak
    fig = areal_momentum_figure(np.linspace(0, 4, 5), np.linspace(-2, 4, 7), areal)
    bar = fig.axes[1]
    assert bar.get_ylabel().endswith(f"({AREAL_MOMENTUM_UNIT})") and AREAL_MOMENTUM_UNIT == "N·s/cm²"
    assert bar.get_ylim()[1] == pytest.approx(0.123)
    pyplot().close(fig)
