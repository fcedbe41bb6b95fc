"""Ballistic-limit campaigns: a grid of (velocity, diameter) shots of one Whipple case, run in parallel.

Every shot is a full Whipple run (:func:`run_whipple`) in ``runs/V<v>_d<d>/``.
The campaign folder (a family folder, :mod:`impactdyn._family`: written as the shots finish,
resumable) adds ``campaign.csv`` and ``campaign.json`` (one row per
shot: the JSC critical diameter and verdict beside the wall stage's verdict, its
caution where the shot lies outside the wall stage's validation, and the simulated
cloud and wall figures) and ``campaign.png``: the JSC ballistic-limit curve with each
shot drawn at its (V, d), coloured by the simulated peak areal momentum on the wall
and shaped by the JSC verdict, with the wall stage's verdict marked over it.  For the
diameter where the simulated verdict changes, bisected per velocity, see
:func:`impactdyn.whipple.run_limit`.
"""

from __future__ import annotations

from pathlib import Path

from impactdyn._config import validate
from impactdyn._errors import InputError
from impactdyn._family import FamilyFolder, run_members
from impactdyn._sweep import case_variants
from impactdyn.units import AREAL_MOMENTUM_UNIT
from impactdyn.whipple._case import WhippleCase
from impactdyn.whipple._shots import run_shot, shot_name, shot_tasks, shot_variant, shot_workers
from impactdyn.whipple._stages import FAILED_VERDICTS

CAMPAIGN_HEADER = [
    "velocity_km_s", "diameter_cm", "ble_critical_diameter_cm", "ble_regime", "ble_verdict",
    "wall_verdict", "wall_agrees_with_equation", "crater_depth_ratio", "rear_bulge_cm", "caution",
    "peak_areal_momentum_N_s_cm2", "impulse_on_wall_normal_N_s_full_model", "leading_edge_velocity_km_s",
    "centre_of_mass_speed_km_s", "cone_half_angle_deg", "n_debris_particles_arrived", "wall_time_s", "run"]


def campaign_shots(raw: dict, velocities: list[float], diameters: list[float], source: str = "<case>"
                   ) -> list[tuple[float, float, WhippleCase]]:
    """Every (V, d) case of the grid, validated before any work."""
    pairs = [(float(v), float(d)) for v in velocities for d in diameters]
    base = validate(WhippleCase, raw, source)
    cases = case_variants(WhippleCase, raw, [shot_variant(base, v, d) for v, d in pairs], source)
    return [(v, d, case) for (v, d), case in zip(pairs, cases)]


def _row(v: float, d: float, s: dict) -> list:
    c, dep, ble, w = s["cloud"], s["deposition"], s["ble"], s["wall"]
    return [v, d, ble["critical_diameter_cm"], ble["regime"], ble["verdict"], w["verdict"], w["agrees_with_equation"],
            w.get("crater_depth_ratio", ""), w.get("rear_bulge_cm", ""), w["caution"] or "",
            dep["peak_areal_momentum_N_s_cm2"],
            dep["impulse_on_wall_normal_N_s_full_model"], c.get("leading_edge_velocity_km_s", ""),
            c.get("centre_of_mass_speed_km_s", ""), c.get("cone_half_angle_deg", ""),
            s["stages"]["debris"]["n_arrived"], s["wall_time_s"], f"runs/{shot_name(v, d)}"]


def run_campaign(raw: dict, velocities: list[float], diameters: list[float], outdir: str | Path, *,
                 source: str = "<case>", force: bool = False, resume: bool = False, scheduler: str = "processes",
                 workers: int | None = None, address: str | None = None, keep_all: bool = False,
                 progress=None) -> list[list]:
    """Run the campaign into ``outdir`` (module docstring); returns the table rows.

    ``raw``: the base case as read from TOML (the grid replaces the projectile's
    velocity and diameter); ``scheduler``: ``processes`` (``workers`` local
    processes, the cores shared among them), ``dask`` (``address``, or a
    LocalCluster) or ``serial``; ``keep_all`` keeps every file of each shot (default: a lean
    folder, :mod:`._shots`).  The table is rewritten after each shot, so an interrupted campaign
    leaves it with the shots it finished; ``resume`` goes on in that folder and runs only the
    shots it lacks.  ``progress()`` is called after each shot.
    """
    if not velocities or not diameters:
        raise InputError("campaign: needs at least one velocity and one diameter")
    grid = campaign_shots(raw, velocities, diameters, source)
    settings = {"case": validate(WhippleCase, raw, source).model_dump(mode="json"),
                "velocities_km_s": [float(v) for v in velocities], "diameters_cm": [float(d) for d in diameters],
                "keep_all": keep_all}
    rows: list = [None] * len(grid)
    with FamilyFolder(outdir, "whipple campaign", settings, table="campaign.csv", member="shot", force=force,
                      resume=resume) as family:
        def record(k: int, summary: dict) -> None:
            v, d, _ = grid[k]
            rows[k] = _row(v, d, summary)
            family.finished += 1
            _write_tables(family, [r for r in rows if r is not None])
            if progress:
                progress()

        summaries = [family.path / "runs" / shot_name(v, d) / "summary.json" for v, d, _ in grid]
        run_members(run_shot, summaries,
                    lambda pending: shot_tasks([grid[k][2] for k in pending], [summaries[k].parent for k in pending],
                                               scheduler, workers, keep_all),
                    record, scheduler=scheduler, workers=shot_workers(scheduler, workers, len(grid)), address=address)
        _write_tables(family, rows)
        _plot(family.path / "campaign.png", grid[0][2], rows)
    return rows


def _write_tables(folder: FamilyFolder, rows: list[list]) -> None:
    """``campaign.csv`` and ``campaign.json``: the finished shots, in grid order."""
    folder.write_csv("campaign.csv", CAMPAIGN_HEADER, rows)
    folder.write_json("campaign.json", [dict(zip(CAMPAIGN_HEADER, r)) for r in rows])


def _plot(path: Path, case: WhippleCase, rows: list) -> None:
    import numpy as np

    from impactdyn.ble import ballistic_limit_curve, plot_ballistic_limit
    from impactdyn.materials import get_material
    from impactdyn.whipple._case import ble_shield

    p, w, b = case.projectile, case.wall, case.bumper
    table = [dict(zip(CAMPAIGN_HEADER, r)) for r in rows]
    v = np.array([r["velocity_km_s"] for r in table])
    d = np.array([r["diameter_cm"] for r in table])
    curve = ballistic_limit_curve(ble_shield(case), np.linspace(1.0, max(15.0, 1.1 * v.max()), 281),
                                  p.obliquity_deg, get_material(p.material).rho0)
    plot_ballistic_limit([curve], path, outcomes=(v, d, np.array([r["peak_areal_momentum_N_s_cm2"] for r in table]),
                                                  np.array([r["ble_verdict"] == "perforation" for r in table]),
                                                  f"simulated peak areal momentum on the wall ({AREAL_MOMENTUM_UNIT})"),
                         simulated=(v, d, np.array([r["wall_verdict"] in FAILED_VERDICTS for r in table])),
                         title=f"Campaign: t_b = {b.thickness_cm:g} cm, t_w = {w.thickness_cm:g} cm, "
                               f"S = {w.spacing_cm:g} cm, θ = {p.obliquity_deg:g}°")
