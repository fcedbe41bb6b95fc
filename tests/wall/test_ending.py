"""How a wall run ends (``measures["ended_by"]``), the peak of the rear bulge, and the permanent bulge
of a wall brought to rest (``settle``)."""

import dataclasses

import numpy as np
import pytest

from impactdyn import wall
from impactdyn.wall import _settle
from impactdyn.materials import AL_6061_T6_MAT13
from impactdyn.wallgrid import WallDeposition, WallGrid

from .conftest import SMALL_WALL, elastic_model, two_records

GRID = SMALL_WALL
DEP = two_records()


def _run(**options):
    return wall.run_wall(GRID, DEP, "al6061-t6", wall.WallOptions(mesh="report", output_interval_us=None, **options)).measures


@pytest.mark.parametrize("options, ended_by, t_end", [
    ({"max_time_us": 6.0}, "ceiling", 6.0),      # the clamped wall still rings at 6 µs
    ({"end_time_us": 4.0}, "end_time", 4.0),
])
def test_a_run_says_which_end_it_met(options, ended_by, t_end):
    m = _run(**options)
    assert m["ended_by"] == ended_by
    assert m["end_time_us"] == pytest.approx(t_end, abs=0.2)
    assert 0.0 < m["kinetic_left_fraction"] <= 1.0


def test_decay_ends_the_run_before_the_ceiling():
    """With a decay fraction just under 1 the run ends at the first sample after the last
    arrival at which the wall's kinetic energy is below its peak."""
    m = _run(max_time_us=50.0, decay_fraction=0.999)
    assert m["ended_by"] == "decay"
    assert 2.5 <= m["end_time_us"] < 50.0
    assert m["kinetic_left_fraction"] <= 0.999


def test_peak_bulge_bounds_the_bulge_at_the_end():
    m = _run(max_time_us=6.0)
    assert m["peak_rear_bulge_cm"] > 0.0
    assert m["peak_rear_bulge_cm"] >= m["rear_bulge_end_cm"]
    assert m["peak_rear_bulge_cm"] >= m["rear_bulge_cm"]
    assert 1.0 <= m["peak_rear_bulge_time_us"] <= m["end_time_us"]


def _settled(model, impulse):
    return wall.run_wall(GRID, two_records(impulse), model, wall.WallOptions(mesh="report", output_interval_us=None, max_time_us=6.0,
                                                            settle=True)).measures


def test_an_elastic_wall_settles_back_to_its_shape():
    """Kinetic damping brings a wall loaded below yield back to rest where it started."""
    m = _settled(elastic_model("johnson_cook"), 1e-6)
    assert m["settled"] and m["settle_resets"] > 0
    assert m["peak_rear_bulge_cm"] > 0.0
    assert m["permanent_rear_bulge_cm"] < 1e-2 * m["peak_rear_bulge_cm"]


def test_a_yielded_wall_keeps_a_permanent_bulge_below_its_peak():
    m = _settled("al6061-t6", 2e-4)
    assert m["settled"]
    assert m["energy"]["plastic"] > 0.1 * m["energy"]["internal"]
    assert 0.1 * m["peak_rear_bulge_cm"] < m["permanent_rear_bulge_cm"] < m["peak_rear_bulge_cm"]


def _struck_plate() -> tuple[wall.WallSolver, int]:
    """A clamped elastic–plastic plate struck on a central patch (0.025 cm/µs, the kind of
    verification/verify_wall_calculix.py), at t = 0, and its rear-face centre node."""
    card = dataclasses.replace(AL_6061_T6_MAT13, failure_strain=0.0, failure_pressure=-1.0e30)
    grid = WallGrid.uniform((0.0, 1.0), (0.0, 0.16), (-1.0, 1.0), (11, 5, 21))
    mesh = wall.build_mesh(grid, card.density, 1, 1, "clamped")
    x = mesh.coordinates
    v = np.zeros_like(x)
    v[:, 1] = np.where((x[:, 0] < 0.3) & (np.abs(x[:, 2]) < 0.3), 0.025, 0.0) * ~mesh.fixed[:, 1]
    solver = wall.WallSolver(mesh, wall.wall_model("mat13", card),
                             wall.WallOptions(material_model="mat13", supports="clamped"), velocity=v)
    return solver, int(np.flatnonzero((x[:, 0] == 0.0) & (x[:, 2] == 0.0) & (x[:, 1] == 0.16))[0])


@pytest.fixture(scope="module")
def ringing_mean() -> float:
    """The struck plate yields in its first swing (peak ~0.127 cm at 15 µs) and then rings
    elastically: the mean of its centre deflection over 50–100 µs, the permanent shape it rings
    about (the measure of verification/verify_wall_calculix.py)."""
    solver, centre = _struck_plate()
    ringing = []
    while solver.time < 100.0:
        solver.advance(solver.time + 0.25)
        if solver.time >= 50.0:
            ringing.append(solver.x[centre, 1] - solver.mesh.coordinates[centre, 1])
    assert solver.energies()["plastic"] > 0.0
    assert max(ringing) - min(ringing) > 0.02 * np.mean(ringing)      # still ringing
    return float(np.mean(ringing))


@pytest.mark.parametrize("start_us", [3.0, 12.0, 60.0])
def test_the_settled_bulge_is_the_mean_the_ringing_plate_swings_about(ringing_mean, start_us):
    """Wherever the settling starts — in the first outward swing (3 µs: with kinetic damping from
    there, 0.059 cm, the swing's remaining plastic work taken away), near its turning point
    (12 µs: damped from there, +4 %, the rebound's reverse yielding missed), or in the elastic
    ringing (60 µs) — the plate comes to rest at the mean it rings about."""
    solver, centre = _struck_plate()
    solver.advance(start_us)
    m = solver.settle()
    assert m["settled"] and m["rebound_end_us"] > start_us
    deflection = solver.x[centre, 1] - solver.mesh.coordinates[centre, 1]
    assert deflection == pytest.approx(ringing_mean, rel=0.01)
    assert m["permanent_rear_bulge_cm"] == pytest.approx(deflection, rel=1e-3)


def test_settling_reports_its_progress_from_0_to_1():
    calls = []
    m = wall.run_wall(GRID, two_records(2e-4), "al6061-t6", wall.WallOptions(mesh="report", output_interval_us=None, max_time_us=6.0,
                                                                             settle=True),
                      settle_progress=lambda done, total: calls.append((done, total))).measures
    assert m["settled"] and len(calls) > 2
    assert calls[0] == (0.0, 1.0) and calls[-1] == (1.0, 1.0)
    assert all(0.0 <= done <= 1.0 and total == 1.0 for done, total in calls)
    assert any(0.0 < done < 1.0 for done, _ in calls)      # the force ratio's way down is shown


def test_a_breakdown_while_settling_loses_only_the_permanent_bulge(monkeypatch):
    """The wall swings on far past the run while it is brought to rest; a breakdown there keeps the
    run's verdict and measures and says why the permanent bulge is missing."""
    from impactdyn.whipple import wall_permanent_bulge

    def broken(solver, max_steps):
        solver.advance(solver.time + 0.5)
        raise wall.WallSolverError("wall solver broke down at t = 6.5 us: non-positive volume in 1 element(s)")

    options = wall.WallOptions(mesh="report", output_interval_us=None, max_time_us=6.0)
    plain = wall.run_wall(GRID, two_records(2e-4), "al6061-t6", options)
    monkeypatch.setattr(_settle, "rebound", broken)
    result = wall.run_wall(GRID, two_records(2e-4), "al6061-t6", options.replaced(settle=True))
    m = result.measures
    assert result.verdict == plain.verdict and m["rear_bulge_cm"] == plain.measures["rear_bulge_cm"]
    assert m["permanent_rear_bulge_cm"] is None and not m["settled"]
    assert "non-positive volume" in m["settle_error"]
    assert wall_permanent_bulge(m).startswith("not measured: wall solver broke down at t = 6.5 us")


def _holed_wall(hold_us, late=()):
    """A 1 × 0.2 × 1-cm clamped wall of 20 × 4 × 20 bricks whose central 4 × 4 patch of face elements
    is each hit by four impulses of 5e-5 g·cm/µs over 0.75 µs: holed within 0.5 µs.  ``late``: (time µs,
    impulse g·cm/µs) of further records on a corner face element, as a late compact fragment lands."""
    grid = WallGrid.uniform((0.0, 1.0), (0.0, 0.2), (0.0, 1.0), (21, 5, 21))
    face = np.array([k * 20 + i for k in range(8, 12) for i in range(8, 12)])
    elements, times = np.repeat(face, 4), np.tile([0.0, 0.25, 0.5, 0.75], face.size)
    impulse = np.array([[0.0, 5e-5, 0.0]] * elements.size)
    if late:
        elements = np.concatenate([elements, np.full(len(late), 2 * 20 + 2)])
        times = np.concatenate([times, [t for t, _ in late]])
        impulse = np.concatenate([impulse, [[0.0, j, 0.0] for _, j in late]])
    dep = WallDeposition(element=elements, time=times, impulse=impulse)
    return wall.run_wall(grid, dep, "al6061-t6", wall.WallOptions(mesh="report", output_interval_us=None,
                                                                  max_time_us=20.0, perforation_hold_us=hold_us))


def test_a_holed_wall_ends_when_its_path_has_held_after_the_last_arrival():
    held = _holed_wall(1.0)
    m = held.measures
    assert held.verdict == wall.PERFORATION
    assert m["ended_by"] == "perforated"
    assert 0.0 < m["perforated_at_us"] <= 0.75
    # the hold counts from the later of the path and the last arrival (0.75 µs), to a history sample
    assert 1.75 <= m["end_time_us"] < 1.75 + wall.WallOptions().history_interval_us + 1e-9
    assert m["impulse_applied"][1] == pytest.approx(m["impulse_deposited"][1], rel=1e-12)


def test_a_late_record_does_not_hold_a_settled_perforation_open():
    """A record arriving long after the hole has settled (a slow compact fragment at 15 µs) is not
    waited for: the run ends 1 µs after the last record so far, and counts the late one unapplied."""
    held = _holed_wall(1.0, late=[(15.0, 1e-6)])
    m = held.measures
    assert held.verdict == wall.PERFORATION and m["ended_by"] == "perforated"
    assert 1.75 <= m["end_time_us"] < 1.75 + wall.WallOptions().history_interval_us + 1e-9
    assert m["unapplied_records"] == 1
    assert m["impulse_unapplied"][1] == pytest.approx(1e-6, rel=1e-12)
    assert m["impulse_applied"][1] + m["impulse_unapplied"][1] == pytest.approx(m["impulse_deposited"][1], rel=1e-12)


def test_a_record_arriving_during_the_hold_starts_it_again():
    """The hold counts from the last record so far: one at 1.5 µs (inside the first hold, which would
    end at 1.75 µs) moves the end to 2.5 µs, and every record is applied."""
    m = _holed_wall(1.0, late=[(1.5, 1e-6)]).measures
    assert m["ended_by"] == "perforated"
    assert 2.5 <= m["end_time_us"] < 2.5 + wall.WallOptions().history_interval_us + 1e-9
    assert m["unapplied_records"] == 0 and m["impulse_unapplied"] == [0.0, 0.0, 0.0]


def test_without_a_hold_a_holed_wall_runs_on_to_the_same_verdict():
    on = _holed_wall(None)
    m = on.measures
    assert on.verdict == wall.PERFORATION and m["ended_by"] in ("decay", "ceiling")
    assert m["end_time_us"] > 1.75 + 1.0
    assert m["perforated_at_us"] == _holed_wall(1.0).measures["perforated_at_us"]


def test_an_unholed_wall_says_it_was_never_perforated():
    m = _run(max_time_us=6.0)
    assert m["ended_by"] == "ceiling" and m["perforated_at_us"] is None
