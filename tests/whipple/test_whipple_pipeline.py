"""`impactdyn whipple run`: the end-to-end pipeline on a coarse shot, restarts, reports and bad input (issue 4)."""

import html
import csv
import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from impactdyn.ble import perforates
from impactdyn.cli import main
from impactdyn.debris import compact_arrival_us, half_model_share, read_arrivals, read_deposition
from impactdyn.io import read_grid, read_lsdyna_deck
from impactdyn.materials import Mat13Card
from impactdyn.shield import read_fragments
from impactdyn.shield._io import read_particles
from impactdyn._config import parse_assignment
from impactdyn._errors import InputError
from impactdyn.whipple import ble_verdict, load_whipple_case, rerun_wall, shield_problem, wall_ending
from impactdyn.wall import ENDINGS, LSDYNA_HOURGLASS_TYPE
from impactdyn.whipple._case import ble_shield, projectile_mass
from impactdyn.whipple._pipeline import deck_options, run_whipple

EXAMPLES = Path(__file__).parents[2] / "examples" / "whipple"


def case_fragments(particles, case):
    """The debris fragments the shield stage finds in ``particles`` for ``case``."""
    from impactdyn.shield import debris_fragments
    from impactdyn.units import km_s_to_cm_us

    return debris_fragments(particles, shield_problem(case)[0], case.fragment_options,
                            km_s_to_cm_us(case.projectile.velocity_km_s))


@pytest.fixture(scope="module")
def run(tmp_path_factory, make_case):
    tmp = tmp_path_factory.mktemp("whipple")
    case = make_case(tmp, wall_solver__mesh="graded")     # the default wall mesh, end to end
    out = tmp / "run"
    assert main(["whipple", "run", str(case), "-o", str(out), "--keep", "all"]) == 0
    return case, out, json.loads((out / "summary.json").read_text())


#: The files a lean run (the default) leaves out and ``--keep all`` writes.
HEAVY = ("debris/handoff_grid.h5", "debris/particles_handoff.vtu", "debris/particles_arrival.vtu",
         "decks/wall.k", "decks/wall_dyna3d.inp")


def test_run_folder_holds_every_stage(run):
    _, out, s = run
    for path in ("case.toml", "report.html", "summary.json", "shield/particles.h5", "shield/particles.vtu",
                 "binning/handoff_grid.h5", "debris/debris.h5", "debris/areal_density.csv",
                 "debris/plots/areal_density.png", "decks/wall.k", "decks/wall_dyna3d.inp",
                 "plots/cloud_handoff.png", "plots/ballistic_limit.png", "plots/conservation.png",
                 "shield/fragments.csv", "shield/fragments.h5", "wall/stage.json", "wall/wall.json", "wall/wall.pvd", "wall/plots/wall_front.png",
                 "wall/plots/wall_rear.png", "wall/plots/wall_history.png"):
        assert (out / path).is_file(), path
    for path in HEAVY:
        assert (out / path).is_file(), path
    # the fragments' plot is drawn where the debris holds solid fragments; without, the report says so
    assert (out / "plots/fragments.png").is_file() == bool(s["stages"]["shield"]["fragments"]["n_fragments"])
    assert s["keep"] == "all"
    assert set(s["timings_s"]) == {"shield", "binning", "debris", "wall", "draws", "decks"}
    assert s["wall_time_s"] == pytest.approx(sum(s["timings_s"].values()))
    assert not list(out.parent.glob(".run.*"))  # no staging folder left


def test_shield_stage_conserves_momentum_and_energy(run):
    _, out, s = run
    shield = s["stages"]["shield"]
    assert shield["momentum_error_rel"] < 1e-10
    assert shield["energy_error_rel"] < 0.01
    particles, history = read_particles(out / "shield" / "particles.h5")
    assert particles.time == pytest.approx(1.0)
    assert particles.total_mass() == pytest.approx(history.mass[0], rel=1e-13)


def test_binned_grid_holds_the_particle_mass_behind_the_bumper(run):
    case, out, s = run
    grid = read_grid(out / "binning" / "handoff_grid.h5")
    particles, _ = read_particles(out / "shield" / "particles.h5")
    t_b = load_whipple_case(case).bumper.thickness_cm
    behind = particles.position[:, 1] >= t_b
    assert grid.y[0] == pytest.approx(t_b) and grid.x[0] == 0.0
    assert grid.mass.sum() == pytest.approx(particles.mass[behind].sum(), rel=1e-12)
    assert s["stages"]["binning"]["mass_error_rel"] < 1e-12


def test_wall_receives_the_momentum_of_the_arrived_debris(run):
    _, out, s = run
    d = s["stages"]["debris"]
    arrived, deposited = np.array(d["momentum_arrived"]), np.array(d["momentum_deposited"])
    off_wall = np.array(d["momentum_off_wall"])
    np.testing.assert_allclose(deposited + off_wall, arrived, rtol=1e-12, atol=1e-14)
    assert d["n_arrived"] > 0 and deposited[1] > 0
    # the LS-DYNA deck's load curves carry the deposited impulse
    deck = read_lsdyna_deck(out / "decks" / "wall.k")
    total = np.zeros(3)
    for (nid, dof, lcid), sf in zip(deck.point_loads, deck.point_load_scale):
        t, f = deck.curves[lcid]
        total[dof - 1] += sf * np.trapezoid(f, t)
    np.testing.assert_allclose(total, deposited, rtol=1e-9)
    _, _, impulse = read_deposition(out / "debris" / "debris.h5")
    assert s["deposition"]["impulse_on_wall_normal_N_s_full_model"] == pytest.approx(20.0 * impulse[..., 1].sum())
    # the arriving particles put their on-grid share of momentum on the wall, nothing else
    mass, momentum, share = read_arrivals(out / "debris" / "debris.h5")
    assert mass.size == d["n_arrived"] and np.all(mass > 0) and np.all((share >= 0) & (share <= 1))
    np.testing.assert_allclose((share[:, None] * momentum).sum(axis=0), impulse.sum(axis=(0, 1)), rtol=1e-9)


def test_the_debris_momentum_is_accounted_for_in_full(run):
    """What the debris carried at hand-off (cloud and compact fragments) = on the wall + outside the arrival
    window + off the face grid + never reaching the wall + failed flights, to round-off; the report says it
    and the peak areal momentum on the wall mesh's own face cells."""
    _, out, s = run
    ledger = {k: np.array(v) for k, v in s["deposition"]["momentum_ledger_g_cm_us"].items()}
    parts = sum(ledger[k] for k in ("deposited", "outside_window", "off_wall", "not_reaching", "failed"))
    np.testing.assert_allclose(parts, ledger["in"], rtol=1e-12, atol=1e-15)
    np.testing.assert_array_equal(ledger["added_at_wall"], 0.0)       # the default gives the wall what arrives
    np.testing.assert_array_equal(ledger["deposited"], s["stages"]["debris"]["momentum_deposited"])
    assert ledger["deposited"][1] > 0
    mesh_peak = s["stages"]["debris"]["peak_areal_density_mesh"]
    assert mesh_peak["peak_g_cm_us"] > 0 and 0 < mesh_peak["cell_cm"] <= 0.16
    text = html.unescape((out / "report.html").read_text())
    assert "outside the arrival window" in text and "on the wall mesh's face cells" in text


def test_the_crater_ejecta_add_to_the_walls_momentum_and_the_ledger_says_how_much(run, tmp_path, make_case):
    """``wall.momentum_transfer = "cratering"`` (a restart from the debris stage): each arrival's normal
    momentum times β(V_n) > 1; in + added at the wall = deposited + the rest, to round-off; the report says it."""
    _, out, base = run
    copy = tmp_path / "run"
    shutil.copytree(out, copy)
    case = make_case(tmp_path, "cratering.toml", wall_solver__mesh="graded", wall__momentum_transfer="cratering")
    assert main(["whipple", "run", str(case), "-o", str(copy), "--from", "debris"]) == 0
    s = json.loads((copy / "summary.json").read_text())
    ledger = {k: np.array(v) for k, v in s["deposition"]["momentum_ledger_g_cm_us"].items()}
    parts = sum(ledger[k] for k in ("deposited", "outside_window", "off_wall", "not_reaching", "failed"))
    np.testing.assert_allclose(parts, ledger["in"] + ledger["added_at_wall"], rtol=1e-12, atol=1e-15)
    default = np.array(base["deposition"]["momentum_ledger_g_cm_us"]["deposited"])
    assert ledger["added_at_wall"][1] > 0
    assert ledger["deposited"][1] == pytest.approx(default[1] + ledger["added_at_wall"][1], rel=1e-12)
    np.testing.assert_allclose(ledger["deposited"][[0, 2]], default[[0, 2]], rtol=1e-12, atol=1e-15)
    assert "more from the crater ejecta" in html.unescape((copy / "report.html").read_text())


def test_decks_carry_the_wall_stages_model(run, tmp_path, make_case):
    """The LS-DYNA deck runs what the wall stage ran: its hourglass type and bulk viscosity, and
    MAT_015 with its EOS for "johnson_cook" (the default) or MAT_013 for "mat13"."""
    case, out, _ = run
    c = load_whipple_case(case)
    cards = read_lsdyna_deck(out / "decks" / "wall.k").cards
    o = c.wall_options
    assert cards["*CONTROL_HOURGLASS"][0][:2] == [LSDYNA_HOURGLASS_TYPE[o.hourglass], pytest.approx(
        o.lsdyna_hourglass[1])]
    assert cards["*CONTROL_BULK_VISCOSITY"][0][:2] == [o.q1, o.q2]
    assert o.material_model == "johnson_cook"
    assert "*MAT_JOHNSON_COOK" in cards and "*MAT_ISOTROPIC_ELASTIC_FAILURE" not in cards
    m13 = deck_options(load_whipple_case(make_case(tmp_path, wall_solver__material_model="mat13",
                                                   wall_solver__hourglass="viscous")))
    assert isinstance(m13.material, Mat13Card) and m13.hourglass == (2, o.hourglass_coefficient)


def test_summary_has_the_verdict_and_the_cloud_figures(run):
    case, out, s = run
    c = load_whipple_case(case)
    p = c.projectile
    assert s["ble"]["verdict"] == ("perforation" if perforates(
        ble_shield(c), p.diameter_cm, p.velocity_km_s, p.obliquity_deg, 2.703) else "no perforation")
    cloud = s["cloud"]
    assert 0 < cloud["centre_of_mass_speed_km_s"] < cloud["leading_edge_velocity_km_s"] <= p.velocity_km_s
    assert 0 < cloud["cone_half_angle_deg"] < 90
    html = (out / "report.html").read_text()
    # cloud, BLE, load, conservation, 3 of the wall, and the fragments' where there are fragments
    assert html.count("data:image/png;base64,") == 7 + bool(s["stages"]["shield"]["fragments"]["n_fragments"])
    assert s["ble"]["verdict"] in html


PHASES = ("solid_mass_fraction", "liquid_mass_fraction", "vapour_mass_fraction")


def check_debris_state(state: dict, projectile_mass_g: float) -> None:
    """The shield stage's ``debris_state``: solid, liquid and vapour shares in [0, 1] summing to 1 for the
    debris, its projectile and its bumper particles, whose masses add up; the largest intact projectile
    piece no heavier than the projectile (or none at all)."""
    for part in (state, state["projectile"], state["bumper"]):
        assert set(PHASES) <= set(part) and part["mass_g"] >= 0
        if part["mass_g"] > 0:
            assert all(0.0 <= part[k] <= 1.0 for k in PHASES)
            assert sum(part[k] for k in PHASES) == pytest.approx(1.0, abs=1e-12)
    assert state["projectile"]["mass_g"] + state["bumper"]["mass_g"] == pytest.approx(state["mass_g"], rel=1e-12)
    piece = state["largest_projectile_piece_g"]
    keys = ("largest_projectile_piece_over_projectile", "largest_projectile_piece_diameter_cm",
            "largest_projectile_piece_particles")
    if piece is None:
        assert all(state[k] is None for k in keys)
    else:
        assert 0 < piece <= projectile_mass_g * (1 + 1e-12)
        assert state["largest_projectile_piece_over_projectile"] == pytest.approx(piece / projectile_mass_g)
        assert state["largest_projectile_piece_diameter_cm"] > 0 and state["largest_projectile_piece_particles"] >= 1


def test_summary_and_report_show_the_debris_state_at_hand_off(run):
    """Issue 38: every run says how much of its debris is solid, liquid and vapour (released to zero
    pressure), of the projectile's material alone too, and its largest intact projectile piece."""
    from impactdyn.shield import released_phase
    from impactdyn.whipple._cloud import debris_mask

    case, out, s = run
    c = load_whipple_case(case)
    state = s["stages"]["shield"]["debris_state"]
    check_debris_state(state, projectile_mass(c))
    assert state["mass_g"] == pytest.approx(s["cloud"]["debris_mass_g"], rel=1e-12) and state["mass_g"] > 0
    assert state["projectile"]["mass_g"] > 0 and state["bumper"]["mass_g"] > 0
    particles, _ = read_particles(out / "shield" / "particles.h5")
    debris = debris_mask(particles, c.bumper.thickness_cm)
    m = particles.mass[debris]
    assert state["solid_mass_fraction"] == pytest.approx(
        1.0 - m @ released_phase(particles).melted[debris] / m.sum(), rel=1e-12, abs=1e-15)
    text = (out / "report.html").read_text()
    assert "debris state at hand-off" in text and "largest intact projectile piece" in text
    assert "projectile&#x27;s debris, solid / liquid / vapour" in text


def test_restart_from_a_stage_reuses_the_earlier_ones(run, tmp_path, make_case):
    case, out, s = run
    copy = tmp_path / "run"
    shutil.copytree(out, copy)
    before = (copy / "shield" / "particles.h5").read_bytes()
    assert main(["whipple", "run", str(case), "-o", str(copy), "--from", "debris"]) == 0
    assert (copy / "shield" / "particles.h5").read_bytes() == before
    _, _, a = read_deposition(out / "debris" / "debris.h5")
    _, _, b = read_deposition(copy / "debris" / "debris.h5")
    np.testing.assert_array_equal(a, b)  # the same grid gives the same deposition
    # a changed binning is fine from the binning stage on, not from a later one
    rebinned = make_case(tmp_path, "rebinned.toml", binning__cell_size_cm=0.12)
    assert main(["whipple", "run", str(rebinned), "-o", str(copy), "--from", "debris"]) == 2
    assert main(["whipple", "run", str(rebinned), "-o", str(copy), "--from", "binning"]) == 0
    assert read_grid(copy / "binning" / "handoff_grid.h5").x[1] == pytest.approx(0.12)


def test_a_restart_of_a_folder_without_the_shield_stages_fragments_is_refused(run, tmp_path, capsys):
    """The later stages read the fragments the shield stage found; a folder of an earlier version has none."""
    case, out, _ = run
    copy = tmp_path / "run"
    shutil.copytree(out, copy)
    (copy / "shield" / "fragments.h5").unlink()
    assert main(["whipple", "run", str(case), "-o", str(copy), "--from", "binning"]) == 2
    err = capsys.readouterr().err
    assert "shield/fragments.h5" in err and "--from shield" in err and "Traceback" not in err
    assert not (copy / "shield" / "fragments.h5").exists() and (copy / "summary.json").is_file()


def test_debris_beyond_memory_is_refused_before_seeding_naming_the_binning_key(run, tmp_path, capsys, monkeypatch):
    from impactdyn import _limits
    from impactdyn.debris._seed import PARTICLE_BYTES

    case, out, s = run
    copy = tmp_path / "run"
    shutil.copytree(out, copy)
    particles = json.loads((out / "debris" / "stage.json").read_text())["n_particles"]
    monkeypatch.setattr(_limits, "physical_memory", lambda: particles * PARTICLE_BYTES // 2)
    assert main(["whipple", "run", str(case), "-o", str(copy), "--from", "debris"]) == 2
    err = capsys.readouterr().err
    assert "error: binning.cell_size_cm = 0.1, seed filters of [filter]: the hand-off grid" in err
    assert "debris particles need at least" in err

def test_a_lean_run_keeps_what_the_report_paraview_and_restarts_need(run, tmp_path, make_case, capsys):
    from impactdyn.debris import read_arrivals

    case, full, s_full = run
    out = tmp_path / "lean"
    assert main(["whipple", "run", str(case), "-o", str(out)]) == 0     # lean: the default
    s = json.loads((out / "summary.json").read_text())
    assert s["keep"] == "lean"
    assert s["wall"]["verdict"] == s_full["wall"]["verdict"]  # what is kept changes no number
    assert s["wall"]["rear_bulge_cm"] == pytest.approx(s_full["wall"]["rear_bulge_cm"], rel=1e-9)
    for path in HEAVY:
        assert not (out / path).exists(), path
    assert json.loads((out / "decks" / "stage.json").read_text())["files"] == []
    for path in ("report.html", "shield/particles.h5", "shield/particles.vtu", "binning/handoff_grid.h5",
                 "debris/debris.h5", "debris/wall_deposition.vtu", "wall/wall.pvd", "wall/plots/wall_front.png"):
        assert (out / path).is_file(), path
    assert "lean run" in (out / "report.html").read_text()
    # the ParaView series: fewer frames, every one the .pvd names is there, the last the run's end
    frames = sorted((out / "wall" / "wall_series").iterdir())
    assert 0 < len(frames) <= len(list((full / "wall" / "wall_series").iterdir()))
    assert all(f"wall_series/{f.name}" in (out / "wall" / "wall.pvd").read_text() for f in frames)
    # the lean debris.h5 holds the deposition, not the particles; it says so when asked for them
    np.testing.assert_allclose(read_deposition(out / "debris" / "debris.h5")[2],
                               read_deposition(full / "debris" / "debris.h5")[2], rtol=1e-12, atol=1e-15)
    with pytest.raises(Exception, match="lean debris.h5 holds no particle states"):
        read_arrivals(out / "debris" / "debris.h5")
    # restarts from a lean folder: the wall stage from its debris.h5, the debris stage from binning/
    assert main(["whipple", "run", str(case), "-o", str(out), "--from", "wall"]) == 0
    assert json.loads((out / "summary.json").read_text())["wall"]["verdict"] == s_full["wall"]["verdict"]
    assert main(["whipple", "run", str(case), "-o", str(out), "--from", "debris"]) == 0
    assert not (out / "debris" / "particles_arrival.vtu").exists()
    # the decks on request, into the lean folder
    assert main(["whipple", "run", str(case), "-o", str(out), "--from", "decks", "--keep", "all"]) == 0
    assert (out / "decks" / "wall.k").is_file() and (out / "decks" / "wall_dyna3d.inp").is_file()
    assert len(read_lsdyna_deck(out / "decks" / "wall.k").curves) == len(read_lsdyna_deck(full / "decks" / "wall.k").curves)
    capsys.readouterr()
    assert main(["whipple", "run", str(case), "-o", str(tmp_path / "x"), "--keep", "some"]) == 2
    assert "--keep 'some': choose lean or all" in capsys.readouterr().err
    assert not (tmp_path / "x").exists()


def test_restart_needs_a_run_folder(tmp_path, capsys, make_case):
    case = make_case(tmp_path)
    assert main(["whipple", "run", str(case), "-o", str(tmp_path / "none"), "--from", "decks"]) == 2
    assert "no run folder to restart from" in capsys.readouterr().err
    assert main(["whipple", "run", str(case), "-o", str(tmp_path / "x"), "--from", "nowhere"]) == 2
    assert not (tmp_path / "x").exists()


@pytest.mark.parametrize("change, message", [
    (dict(projectile__obliquity_deg=90.0), "projectile.obliquity_deg: must be less than 90"),
    (dict(projectile__diameter_cm=0.0), "projectile.diameter_cm: must be greater than 0"),
    (dict(projectile__material="unobtainium"), "projectile.material: unknown material 'unobtainium'"),
    (dict(wall__material="balsa"), "wall.material: unknown material 'balsa'"),
    (dict(wall__spacing_cm=-0.05), "wall.spacing_cm: -0.05: the wall's front face would lie inside the bumper"),
    (dict(wall__spacing_cm=0.5), "wall.spacing_cm = 0.5 cannot hold the hand-off grid"),
    (dict(shield__spacing_cm=0.2), "shield.spacing_cm = 0.2 is too coarse"),
    (dict(wall__momentum_transfer="bounce"), "wall.momentum_transfer: "),
    (dict(binning__cell_size_cm=4.0), "binning.cell_size_cm = 4.0 does not fit"),
    (dict(wall__nodes=[16, 1, 31]), "wall.nodes[1]: must be greater than or equal to 2"),
    (dict(shield__handoff_us="4"), "shield.handoff_us: must be a valid number"),
    (dict(shield__failure_model="brittle"), "shield.failure_model: "),
    (dict(shield__viscosity_switch="cullen"), "shield.viscosity_switch: "),
    (dict(shield__fragment_seed=-1), "shield.fragment_seed: must be greater than or equal to 0"),
    (dict(shield__fragment_link_spacings=-1.5), "shield.fragment_link_spacings: must be greater than 0"),
    (dict(shield__fragment_damage_threshold=0.0), "shield.fragment_damage_threshold: must be greater than 0"),
    (dict(shield__fragment_damage_threshold=1.5), "shield.fragment_damage_threshold: must be less than or equal to 1"),
    (dict(shield__failure_model="fragmentation", projectile__material="cu-ofhc"),
     "needs the Weibull flaws (the shield's fragmentation model) constants of material 'cu-ofhc'"),
    (dict(wall_solver__max_time_us=1.0), "wall_solver.max_time_us = 1 us is before the last arrival on the wall"),
    (dict(shield__failed_fragments="dust"), "shield.failed_fragments: "),
    (dict(shield__fragment_rate="kernel"), "shield.fragment_rate: "),
    (dict(shield__failed_fragments="grady"), "failed_fragments = \"grady\" needs failure_model = \"fragmentation\""),
    (dict(shield__failed_fragments="grady", shield__failure_model="fragmentation", projectile__material="cu-ofhc"),
     "no fracture toughness for projectile.material = 'cu-ofhc'"),
])
def test_bad_input_exits_2_and_writes_nothing(tmp_path, capsys, make_case, change, message):
    case = make_case(tmp_path, **change)
    out = tmp_path / "out"
    assert main(["whipple", "run", str(case), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err
    assert not out.exists() and not list(tmp_path.glob(".out*"))


def test_existing_run_folder_needs_force(run, capsys):
    case, out, _ = run
    stamp = (out / "summary.json").stat().st_mtime_ns
    assert main(["whipple", "run", str(case), "-o", str(out)]) == 2
    assert "pass --force" in capsys.readouterr().err
    assert (out / "summary.json").stat().st_mtime_ns == stamp


def test_rerun_wall_repeats_the_wall_stage_and_writes_nothing(run):
    """The wall stage of a finished run again: without changes the run's wall (its verdict and mesh; its
    measures to the time stepping, the rerun keeping no frames), the changes applied with them (options
    and material model), and the run folder left as it was."""
    _, out, _ = run
    files = {p: p.stat().st_mtime_ns for p in out.rglob("*")}
    wall = json.loads((out / "wall" / "stage.json").read_text())
    same = rerun_wall(out)
    assert same.verdict == wall["verdict"] and same.mesh.describe() == wall["mesh"]
    assert same.measures["rear_bulge_cm"] == pytest.approx(wall["measures"]["rear_bulge_cm"], rel=1e-3)
    changed = rerun_wall(out, {"damage": None}, refinement_thickness=2 * same.mesh.refinement[0])
    assert changed.mesh.shape[1] == 2 * same.mesh.shape[1]
    assert "ductile_damage" not in changed.model["failure_criteria"]
    assert {p: p.stat().st_mtime_ns for p in out.rglob("*")} == files


def test_key_value_options_read_their_values_as_json():
    """The command-line form of rerun_wall's changes (the V&V scripts' --model-option, --wall-option)."""
    assert parse_assignment("damage=null") == ("damage", None)
    assert parse_assignment("max_time_us=300") == ("max_time_us", 300)
    assert parse_assignment("material_model=mat13") == ("material_model", "mat13")
    for text in ("damage", "=1"):
        with pytest.raises(InputError, match=f"expected KEY=VALUE, got {text!r}"):
            parse_assignment(text)


@pytest.mark.parametrize("name, verdict", [("7a", "perforation"), ("7b", "no perforation"),
                                           ("10a", "perforation"), ("10b", "no perforation")])
def test_table2_examples_load_and_get_the_jsc_verdicts(name, verdict):
    case = load_whipple_case(EXAMPLES / f"table2_{name}.toml")
    assert case.wall.spacing_cm == 10.16 and case.projectile.obliquity_deg == 25.0
    assert ble_verdict(case)["verdict"] == verdict


def test_the_fragments_example_is_shot_7a_with_the_fragments_on():
    """The example of the fragments option differs from table2_7a.toml only by its title and the two
    [shield] keys that turn the fragments on (so it cannot drift from the shot it shows)."""
    plain, fragments = (load_whipple_case(EXAMPLES / f"table2_7a{tail}.toml") for tail in ("", "_fragments"))
    assert fragments.shield.failure_model == "fragmentation" and fragments.shield.failed_fragments == "grady"
    a, b = plain.model_dump(), fragments.model_dump()
    for case in (a, b):
        case.pop("title")
        case["shield"].pop("failure_model")
        case["shield"].pop("failed_fragments")
    assert a == b


def test_wall_stage_takes_the_deposited_impulse_and_gives_a_verdict(run):
    _, out, s = run
    wall = json.loads((out / "wall" / "stage.json").read_text())
    assert s["wall"]["verdict"] == wall["verdict"] in ("perforation", "detached spall", "no perforation")
    m = wall["measures"]
    deposited = np.array(m["impulse_deposited"])
    taken = np.array(m["impulse_applied"]) + np.array(m["impulse_supports"])
    assert np.abs(taken - deposited).max() <= 1e-12 * np.abs(deposited).max()
    # the deposition the wall took is the debris stage's, to round-off
    np.testing.assert_allclose(deposited, s["stages"]["debris"]["momentum_deposited"], rtol=1e-12, atol=0)
    assert abs(m["energy"]["balance_error"]) < 1e-6 * m["energy"]["load_work"]
    assert s["wall"]["agrees_with_equation"] == ((wall["verdict"] != "no perforation")
                                                 == (s["ble"]["verdict"] == "perforation"))
    # the damaged mass is split by the criterion that failed it, in the summary too
    by_cause = m["failed_mass_by_cause_g"]
    assert sum(by_cause.values()) == pytest.approx(m["damaged_mass_g"], rel=1e-12, abs=1e-15)
    assert s["wall"]["failed_mass_by_cause_g"] == by_cause
    assert "failed mass by criterion" in (out / "report.html").read_text()
    # and the criteria that could fail it (the case's Johnson–Cook 6061-T6 wall: damage and spall)
    assert s["wall"]["failure_criteria"] == wall["model"]["failure_criteria"] == [
        "ductile_damage", "ductile_damage_at_floor", "spall_damage"]
    assert "failure criteria of the wall model" in (out / "report.html").read_text()
    # the coarse case's 0.45-cm projectile lies below the validated sizes: the summary and report say so
    assert s["wall"]["caution"].startswith("on the validation shots the wall stage called every tested perforation safe")
    report = (out / "report.html").read_text()
    assert html.escape(s["wall"]["caution"]) in report
    # the caution at the top, before the title; a banner above it where the two verdicts differ
    assert report.index('class="caution"') < report.index("<h1>")
    assert ('class="banner"' in report) == (not s["wall"]["agrees_with_equation"])
    # how the run ended, and the bulge's peak, in the summary and the report
    assert s["wall"]["ended_by"] == m["ended_by"] in ENDINGS
    assert s["wall"]["peak_rear_bulge_cm"] >= m["rear_bulge_end_cm"]
    assert f"run ended by</th><td>{html.escape(wall_ending(s['wall']))}" in (out / "report.html").read_text()


@pytest.mark.parametrize("diameter, velocity, outside", [
    (0.575, 7.0, None), (0.3175, 3.0, None), (0.674, 7.57, None), (0.674, 8.0, "V = 8 km/s is outside"),
    (0.2, 7.0, "d = 0.2 cm is outside"),
    (0.7, 7.0, "d = 0.7 cm is outside"), (0.6, 10.0, "V = 10 km/s is outside")])
def test_wall_caution_names_what_the_validation_shots_say_and_what_lies_outside_them(diameter, velocity, outside):
    from impactdyn.whipple._report import WALL_VALIDATION, wall_caution

    case = load_whipple_case(EXAMPLES / "table2_7a.toml")
    caution = wall_caution(case, diameter, velocity)
    assert caution.startswith(WALL_VALIDATION) and caution.endswith("beside it")
    assert ("outside" in caution) == (outside is not None) and (outside is None or outside in caution)
    # with the fragments of failed material the wall's load is not the cloud's alone: the caution says
    # what stands behind that verdict instead
    with_fragments = wall_caution(load_whipple_case(EXAMPLES / "table2_7a_fragments.toml"), diameter, velocity)
    assert "fragments of failed material" in with_fragments and WALL_VALIDATION not in with_fragments
    assert with_fragments.endswith("beside it") and ("outside" in with_fragments) == (outside is not None)


def test_a_test_shots_report_sets_the_tests_outcome_beside_the_verdicts(run, tmp_path, make_case):
    """A case with a [test_shot] table (``whipple shot`` writes it) reports the test's outcome, the shot, its line
    and its source in the verdict table and the summary; a case without one has no such row."""
    from impactdyn.whipple import database_shot

    case, out, s = run
    assert s["test_shot"] is None and "<th>test shot " not in (out / "report.html").read_text()
    copy = tmp_path / "run"
    shutil.copytree(out, copy)
    shot = database_shot("B31")
    tested = make_case(tmp_path, "tested.toml", wall_solver__mesh="graded", test_shot=shot.record.model_dump())
    assert main(["whipple", "run", str(tested), "-o", str(copy), "--from", "report"]) == 0
    summary = json.loads((copy / "summary.json").read_text())
    assert summary["test_shot"]["outcome"] == shot.outcome and summary["test_shot"]["line"] == 292
    agrees = (s["wall"]["verdict"] in ("perforation", "detached spall")) == shot.perforated
    row = (f"<th>test shot TP-2003-210788 B31 (line 292 of database_whipple_pyBLOSSUM.csv)</th><td>{shot.outcome}: "
           f"the simulated verdict {'agrees' if agrees else 'disagrees'}, the equation's ")
    report = html.unescape((copy / "report.html").read_text())
    assert row in report
    # in the verdict table, after the equation's verdict
    assert report.index("equation's verdict") < report.index(row) < report.index("<h2>Stages")


@pytest.mark.parametrize("perforated, simulated, equation, words", [
    (True, "detached spall", "perforation", "the simulated verdict agrees, the equation's agrees"),
    (True, "no perforation", "perforation", "the simulated verdict disagrees, the equation's agrees"),
    (False, "perforation", "no perforation", "the simulated verdict disagrees, the equation's agrees"),
    (False, "no perforation", "perforation", "the simulated verdict agrees, the equation's disagrees")])
def test_the_tests_outcome_is_weighed_against_each_verdict(perforated, simulated, equation, words):
    from impactdyn.whipple._case import TEST_OUTCOMES
    from impactdyn.whipple._report import outcome_statement

    test = {"perforated": perforated, "outcome": TEST_OUTCOMES[perforated]}
    assert outcome_statement(test, simulated, equation) == f"{TEST_OUTCOMES[perforated]}: {words}"


def test_a_wall_run_cut_off_at_the_ceiling_is_said_to_be_not_at_rest():
    record = {"ended_by": "ceiling", "end_time_us": 100.01, "kinetic_left_fraction": 0.215}
    assert wall_ending(record).startswith("the max_time_us ceiling at 100 µs, 22% of its peak kinetic energy left")
    assert "not at rest" in wall_ending(record)
    assert "not at rest" not in wall_ending(record | {"ended_by": "decay"})


def test_a_perforation_that_ended_the_run_before_late_records_says_how_much_it_left_out():
    record = {"ended_by": "perforated", "end_time_us": 35.82, "kinetic_left_fraction": 0.05, "perforated_at_us": 15.71,
              "unapplied_records": 3, "impulse_unapplied": [0.0, 3e-4, 4e-4], "impulse_deposited": [0.0, 0.06, 0.08]}
    assert wall_ending(record).endswith("; 3 records arriving later (0.50% of the deposited momentum) not applied")
    assert "not applied" not in wall_ending(record | {"unapplied_records": 0})


def test_a_settled_wall_reports_its_permanent_bulge_and_progress(run, tmp_path, make_case, capsys):
    """``settle = true`` from the wall stage on: the settling shows as a stage of its own in the
    progress, and the permanent bulge reaches summary.json and the report."""
    _, out, _ = run
    copy = tmp_path / "run"
    shutil.copytree(out, copy)
    case = load_whipple_case(make_case(tmp_path, "settled.toml", wall_solver__settle=True))
    assert case.wall_solver.options(clamped_edges=True).settle
    calls = []
    s = run_whipple(case, copy, start="wall", progress=lambda stage, done, total: calls.append((stage, done, total)))
    settling = [c for c in calls if c[0] == "settle"]
    assert settling[0] == ("settle", 0.0, 1.0) and settling[-1] == ("settle", 1.0, 1.0)
    assert s["wall"]["settled"] and 0.0 <= s["wall"]["permanent_rear_bulge_cm"] <= s["wall"]["peak_rear_bulge_cm"]
    assert "rear-face permanent bulge" in (copy / "report.html").read_text()
    capsys.readouterr()
    assert main(["whipple", "run", str(tmp_path / "settled.toml"), "-o", str(copy), "--from", "wall"]) == 0
    assert "rear-face permanent bulge (the wall brought to rest): " in capsys.readouterr().out


def test_the_debris_case_carries_the_wall_material(tmp_path, make_case):
    """Rerunning debris/config.resolved.toml with `impactdyn debris run` writes the decks of the same wall."""
    from impactdyn.debris import DeckOptions
    from impactdyn.materials import CU_OFHC, mat13_card
    from impactdyn.whipple import load_whipple_case
    from impactdyn.whipple._case import debris_case

    case = load_whipple_case(make_case(tmp_path, wall__material="Cu-OFHC"))
    debris = debris_case(case, "handoff_grid.h5")
    assert debris.wall.material == CU_OFHC.name
    card = DeckOptions.of(debris).material
    assert card == mat13_card(CU_OFHC.name) == DeckOptions.of(case).material
    assert card.density == CU_OFHC.rho0


@pytest.mark.parametrize("changes, message", [
    (dict(wall_solver__refinement_thickness=0), "case.toml: wall_solver.refinement_thickness: must be greater than or equal to 1"),
    (dict(wall_solver__material_model="bogus"), "material_model"),
    (dict(wall_solver__max_time_us=-1.0), "max_time_us"),
    (dict(wall_solver__settle_tolerance=0.0), "settle_tolerance"),
    (dict(wall__thickness_cm=0.0), "wall.thickness_cm"),
    (dict(wall_solver__deposition_depth_cm=-1.0), "deposition_depth_cm"),
    (dict(wall_solver__deposition_depth_cm=5.0),
     "wall_solver.deposition_depth_cm: must be in [0, "),
    (dict(wall_solver__mesh="fine"), "wall_solver.mesh: must be 'graded' or 'report'"),
    (dict(wall_solver__grading_ratio=1.0), "wall_solver.grading_ratio: must be greater than 1"),
    (dict(wall_solver__grading_ratio=2.0), "wall_solver.grading_ratio: must be less than or equal to 1.5"),
    (dict(wall_solver__element_size_cm=0.0), "wall_solver.element_size_cm: must be greater than 0"),
    (dict(wall_solver__element_size_cm=50.0), "wall_solver.element_size_cm: must be in (0, "),
    (dict(wall_solver__max_element_size_cm=50.0), "wall_solver.max_element_size_cm: must be in (0, "),
    (dict(wall_solver__spall_law="instant"), "wall_solver.spall_law: unknown wall failure law 'instant'; choose one of tuler_butcher, cutoff"),
    (dict(wall_solver__fracture_strain_floor="none"), "wall_solver.fracture_strain_floor: must be"),
])
def test_bad_wall_solver_settings_exit_2_before_any_work(tmp_path, capsys, make_case, changes, message):
    case = make_case(tmp_path, **changes)
    out = tmp_path / "run"
    assert main(["whipple", "run", str(case), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err
    assert not out.exists()


@pytest.mark.parametrize("failed", ["spray", "grady"])
def test_a_fragmenting_shot_reports_its_solid_fragments(tmp_path, make_case, failed):
    """At 2 km/s the fragmentation model leaves the projectile in pieces the SPH resolves: the shield stage
    lists them (largest first, their mass within the debris's), and the report draws and names them.
    With ``failed_fragments = "grady"`` the failed solid material adds fragments of its own, and the
    split into the two populations still conserves mass and momentum exactly."""
    # 3 µs: the projectile's remains have passed behind the bumper; the wall's response is not asked here
    case = make_case(tmp_path, shield__failure_model="fragmentation", shield__spacing_cm=0.05,
                     shield__handoff_us=3.0, projectile__velocity_km_s=2.0, wall_solver__max_time_us=30.0,
                     shield__failed_fragments=failed, filter__t_cut_us=12.0)
    out = tmp_path / "run"
    assert main(["whipple", "run", str(case), "-o", str(out)]) == 0
    figures = json.loads((out / "summary.json").read_text())["stages"]["shield"]["fragments"]
    rows = list(csv.DictReader((out / "shield" / "fragments.csv").open()))
    assert figures["n_fragments"] == len(rows) > 0
    masses = [float(r["mass_g"]) for r in rows]
    assert masses == sorted(masses, reverse=True) and masses[0] == pytest.approx(figures["largest_g"])
    assert 0 < figures["largest_over_projectile"] < 1
    assert all(float(r["vy_cm_per_us"]) > 0 for r in rows)
    origins = {r["origin"] for r in rows}
    assert origins == ({"intact", "failed"} if failed == "grady" else {"intact"})
    assert "Solid fragments of the debris" in (out / "report.html").read_text()
    # found once by the shield stage, read back exactly by the later ones
    kept = read_fragments(out / "shield" / "fragments.h5")
    loaded = load_whipple_case(case)
    found = case_fragments(read_particles(out / "shield" / "particles.h5")[0], loaded)
    for name in ("mass", "position", "velocity", "spin", "diameter_cm", "axes_cm", "count", "ptr", "members",
                 "from_failed"):
        np.testing.assert_array_equal(getattr(kept, name), getattr(found, name))
    # the projectile breaks into solid pieces: the largest of them, no heavier than the largest fragment
    state = json.loads((out / "summary.json").read_text())["stages"]["shield"]["debris_state"]
    check_debris_state(state, projectile_mass(load_whipple_case(case)))
    assert 0 < state["largest_projectile_piece_g"] <= figures["largest_g"]

    # two populations: the compact fragments are not binned, and fly to the wall on their own;
    # mass and momentum are conserved exactly across the split
    stages = json.loads((out / "summary.json").read_text())["stages"]
    compact = stages["debris"]["compact_fragments"]
    assert compact["n_fragments"] >= 1 and stages["binning"]["n_particles_in_compact_fragments"] > 0
    particles, _ = read_particles(out / "shield" / "particles.h5")
    from impactdyn.shield import compact_particles
    from impactdyn.whipple._cloud import compact_fragments
    fragments = compact_fragments(case_fragments(particles, loaded), loaded)
    taken = compact_particles(fragments, len(particles))
    behind = particles.position[:, 1] >= loaded.bumper.thickness_cm
    grid = read_grid(out / "binning" / "handoff_grid.h5")
    assert grid.total_mass() == pytest.approx(particles.mass[behind & ~taken].sum(), rel=1e-12)
    assert compact["mass_g"] == pytest.approx(particles.mass[taken].sum(), rel=1e-12)
    # y and z: the half model's x momentum is exchanged with the mirror half, not conserved
    assert np.array(compact["momentum"])[1:] == pytest.approx(
        (particles.mass[taken] @ particles.velocity[taken])[1:], rel=1e-12)
    # a fragment lands whenever it passes into the wall during the wall run, also after the cloud's arrival
    # window ([filter] t_cut_us); one passing after the run lays down nothing and is stated; the rest
    # deposit their momentum exactly
    wall_y = loaded.bumper.thickness_cm + loaded.wall.spacing_cm
    arrival = compact_arrival_us(wall_y, fragments.diameter_cm, fragments.position, fragments.velocity)
    passed = arrival + fragments.diameter_cm / fragments.velocity[:, 1]          # its rear at the face
    inside = (arrival >= loaded.filter.t_min_us) & (passed <= loaded.wall_solver.max_time_us)
    assert np.any(inside & (arrival > loaded.filter.t_cut_us))          # lands after the cloud's window
    mass = half_model_share(fragments.position, fragments.diameter_cm) * fragments.mass
    assert compact["mass_outside_window_g"] == pytest.approx(mass[~inside].sum(), rel=1e-12, abs=1e-15)
    assert np.array(compact["momentum_deposited"])[1:] == pytest.approx(
        (mass[inside] @ fragments.velocity[inside])[1:], rel=1e-9)


def test_draws_run_the_sph_once_and_each_draw_as_a_run_with_its_seed(tmp_path, make_case, monkeypatch):
    """``fragment_draws = 3``: the run's own wall is the first draw, and each further draw, the fragments drawn
    again from the same SPH state, is the run a case with that seed would make (its deposition and wall,
    bit for bit); the record counts the perforations and states P with its Wilson interval.  The run folder
    is given as a relative path, as ``-o runs/name`` gives it."""
    from impactdyn.ble import wilson_interval
    from impactdyn.whipple._stages import FAILED_VERDICTS

    keys = dict(shield__failure_model="fragmentation", shield__spacing_cm=0.05, shield__handoff_us=3.0,
                projectile__velocity_km_s=2.0, wall_solver__max_time_us=30.0, shield__failed_fragments="grady",
                filter__t_cut_us=12.0)
    case = make_case(tmp_path, **keys)
    monkeypatch.chdir(tmp_path)
    assert main(["whipple", "run", str(case), "-o", "runs/run", "--draws", "3"]) == 0
    out = tmp_path / "runs" / "run"
    summary = json.loads((out / "summary.json").read_text())
    draws = summary["draws"]
    assert [d["seed"] for d in draws["draws"]] == [1, 2, 3] and draws["n_draws"] == 3
    assert draws["draws"][0]["verdict"] == summary["wall"]["verdict"]
    k = sum(d["verdict"] in FAILED_VERDICTS for d in draws["draws"])
    assert draws["perforated"] == k and draws["probability"] == k / 3
    assert draws["wilson_95"] == pytest.approx(list(wilson_interval(k, 3)), abs=0)
    assert f"perforation in {k} of 3 draws" in (out / "report.html").read_text()
    assert (out / "plots" / "draws.png").stat().st_size > 10_000 and 'alt="draws.png"' in (out / "report.html").read_text()
    # the third draw is the run of a case with seed 3: its wall's record, bit for bit
    alone = tmp_path / "seed3"
    assert main(["whipple", "run", str(make_case(tmp_path, name="seed3.toml", shield__fragment_seed=3, **keys)),
                 "-o", str(alone)]) == 0
    drawn = json.loads((out / "draws" / "seed3" / "wall" / "stage.json").read_text())
    single = json.loads((alone / "wall" / "stage.json").read_text())
    for key in ("verdict", "evidence", "measures", "mesh"):
        assert drawn[key] == single[key], key
    assert draws["draws"][2]["failed_mass_g"] == single["measures"]["failed_mass_g"]
    assert draws["draws"][2]["peak_rear_bulge_cm"] == single["measures"]["peak_rear_bulge_cm"]
    assert draws["draws"][2]["compact_mass_g"] == json.loads(
        (alone / "debris" / "stage.json").read_text())["compact_fragments"]["mass_g"]
    for stage in ("binning", "debris"):
        a = json.loads((out / "draws" / "seed3" / stage / "stage.json").read_text())
        b = json.loads((alone / stage / "stage.json").read_text())
        assert {k: v for k, v in a.items() if k not in ("wall_time_s", "settings", "timings_s")} == \
            {k: v for k, v in b.items() if k not in ("wall_time_s", "settings", "stage", "timings_s")} | {"stage": stage}
    assert not list((out / "draws").rglob("*.h5"))      # the draws keep what a lean shot keeps
    assert not list((out / "draws").rglob("*.png"))     # and draw no figures: the report draws them all in one


def test_a_run_whose_own_wall_fails_stops_the_draws_running_beside_it(tmp_path, make_case, monkeypatch):
    """The further draws start before the run's own binning and run beside its chain: an error there (here the
    wall stage's) stops them, leaves no worker process and writes no run folder."""
    import multiprocessing

    from impactdyn.whipple import _pipeline

    def failing_wall(s):
        raise InputError("the run's own wall failed")

    monkeypatch.setattr(_pipeline, "_RUN", _pipeline._RUN | {"wall": failing_wall})
    monkeypatch.setattr(_pipeline, "draw_schedule", lambda threads, n_draws: ("processes", 2, 1))  # on any machine
    keys = dict(shield__failure_model="fragmentation", shield__spacing_cm=0.05, shield__handoff_us=3.0,
                projectile__velocity_km_s=2.0, wall_solver__max_time_us=30.0, shield__failed_fragments="grady",
                filter__t_cut_us=12.0, shield__fragment_draws=4)
    out = tmp_path / "run"
    with pytest.raises(InputError, match="the run's own wall failed"):
        run_whipple(load_whipple_case(make_case(tmp_path, **keys)), out)
    assert multiprocessing.active_children() == []
    assert not out.exists() and not list(tmp_path.glob(".run.*"))


@pytest.mark.parametrize("draws, message", [("0", "shield.fragment_draws: must be greater than or equal to 1"),
                                            ("-2", "shield.fragment_draws: must be greater than or equal to 1"),
                                            ("65", "shield.fragment_draws: must be less than or equal to 64"),
                                            ("2.5", "'--draws'"), ("many", "'--draws'")])
def test_a_bad_number_of_draws_is_refused_naming_it_before_any_work(tmp_path, capsys, make_case, draws, message):
    case = make_case(tmp_path, shield__failure_model="fragmentation", shield__failed_fragments="grady")
    out = tmp_path / "run"
    assert main(["whipple", "run", str(case), "-o", str(out), "--draws", draws]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err
    assert not out.exists()


def test_draws_need_the_random_partition(tmp_path, capsys, make_case):
    out = tmp_path / "run"
    assert main(["whipple", "run", str(make_case(tmp_path, shield__fragment_draws=2)), "-o", str(out)]) == 2
    assert "fragment_draws = 2 needs failed_fragments = \"grady\"" in capsys.readouterr().err
    assert not out.exists()


@pytest.mark.parametrize("threads, n_draws, schedule", [
    (1, 7, ("serial", 1, 1)),              # a validation's shot: its one thread, the draws in turn
    (2, 7, ("processes", 2, 1)),           # a run on two cores: two draws at a time, a thread each
    (8, 3, ("processes", 3, 2)),           # more threads than draws: each draw gets its share of seven
    (2, 1, ("processes", 1, 1)),           # one further draw beside the run's own chain, a thread each
    (4, 0, ("serial", 1, 4))])             # no further draw: nothing to share
def test_the_further_draws_share_the_runs_threads_as_processes(threads, n_draws, schedule):
    from impactdyn.whipple._pipeline import draw_schedule

    assert draw_schedule(threads, n_draws) == schedule


def test_plots_switched_off_draw_neither_the_debris_nor_the_wall_and_the_report_says_so(tmp_path, make_case):
    out = tmp_path / "run"
    assert main(["whipple", "run", str(make_case(tmp_path, output__plots=False)), "-o", str(out)]) == 0
    assert not list((out / "debris").rglob("*.png")) and not list((out / "wall").rglob("*.png"))
    assert "wall_front.png was not drawn (plots switched off)" in (out / "report.html").read_text()
