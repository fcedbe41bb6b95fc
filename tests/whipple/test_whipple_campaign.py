"""`impactdyn whipple campaign`: a (velocity, diameter) grid in parallel, drawn over the BLE curve (issue 4)."""

import csv
import json

import pytest

from impactdyn.cli import main
from impactdyn.whipple import ble_verdict, load_whipple_case


def test_campaign_runs_every_shot_and_tabulates_it(tmp_path, make_case):
    case = make_case(tmp_path)
    out = tmp_path / "campaign"
    assert main(["whipple", "campaign", str(case), "--velocity", "6:7:2", "--diameter", "0.45:0.45:1",
                 "-o", str(out), "--workers", "2"]) == 0
    rows = list(csv.DictReader((out / "campaign.csv").open()))
    assert [(float(r["velocity_km_s"]), float(r["diameter_cm"])) for r in rows] == [(6.0, 0.45), (7.0, 0.45)]
    base = load_whipple_case(case)
    for r in rows:
        shot = base.model_copy(update={"projectile": base.projectile.model_copy(
            update={"velocity_km_s": float(r["velocity_km_s"])})})
        assert r["ble_verdict"] == ble_verdict(shot)["verdict"]
        summary = json.loads((out / r["run"] / "summary.json").read_text())
        assert float(r["peak_areal_momentum_N_s_cm2"]) == pytest.approx(
            summary["deposition"]["peak_areal_momentum_N_s_cm2"])
        assert summary["shot"]["projectile"]["velocity_km_s"] == float(r["velocity_km_s"])
        # the wall stage's verdict beside the equation's, with its caution
        assert r["wall_verdict"] == summary["wall"]["verdict"]
        assert r["wall_agrees_with_equation"] == str(summary["wall"]["agrees_with_equation"])
        assert r["caution"] == summary["wall"]["caution"] and r["caution"].startswith("on the validation shots")
        # a lean shot does not write the decks and ParaView files it would delete
        assert json.loads((out / r["run"] / "decks" / "stage.json").read_text())["files"] == []
        wall_files = json.loads((out / r["run"] / "wall" / "stage.json").read_text())["files"]
        assert wall_files and not any(f.endswith((".vtu", ".pvd")) for f in wall_files)
    assert (out / "campaign.png").stat().st_size > 10_000
    assert len(json.loads((out / "campaign.json").read_text())) == 2
    # resumed with every shot finished: the shots are read back, none is run again, the table is the same
    table = (out / "campaign.csv").read_text()
    stamps = sorted(p.stat().st_mtime_ns for p in out.glob("runs/*/summary.json"))
    assert main(["whipple", "campaign", str(case), "--velocity", "6:7:2", "--diameter", "0.45:0.45:1",
                 "-o", str(out), "--resume"]) == 0
    assert (out / "campaign.csv").read_text() == table
    assert sorted(p.stat().st_mtime_ns for p in out.glob("runs/*/summary.json")) == stamps


@pytest.mark.parametrize("args, message", [
    (["--velocity", "6:7", "--diameter", "0.4:0.5:2"], "--velocity '6:7': expected START:STOP:N"),
    (["--velocity", "6:7:2", "--diameter", "0.4:0.5:0"], "--diameter '0.4:0.5:0': N must be at least 1"),
    (["--velocity", "-6:7:2", "--diameter", "0.4:0.5:2"], "projectile.velocity_km_s: must be greater than 0"),
])
def test_bad_grids_exit_2_before_any_work(tmp_path, capsys, make_case, args, message):
    case = make_case(tmp_path)
    out = tmp_path / "campaign"
    assert main(["whipple", "campaign", str(case), *args, "-o", str(out)]) == 2
    assert message in capsys.readouterr().err
    assert not out.exists()
