"""``impactdyn ble``: ballistic limit equations (NASA JSC Whipple shield, Cour-Palais single wall)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Optional

import typer

app = typer.Typer(help="Ballistic limit equations: NASA JSC Whipple shield, Cour-Palais single wall "
                       "(cm, g/cm³, km/s, ksi).", no_args_is_help=True)


def _print_table(title: str, rows: list[tuple[str, str]]) -> None:
    from rich.console import Console
    from rich.table import Table

    t = Table(title=title, show_header=False)
    t.add_column("quantity")
    t.add_column("value")
    for k, v in rows:
        t.add_row(k, v)
    Console().print(t)


@app.command()
def whipple(
    bumper_cm: float = typer.Option(..., "--bumper-cm", help="Bumper thickness t_b (cm)."),
    wall_cm: float = typer.Option(..., "--wall-cm", help="Rear wall thickness t_w (cm)."),
    spacing_cm: float = typer.Option(..., "--spacing-cm", help="Standoff S between bumper and rear wall (cm)."),
    yield_ksi: float = typer.Option(..., "--yield-ksi", help="Rear wall yield stress σ (ksi)."),
    velocity_km_s: float = typer.Option(..., "--velocity-km-s", help="Impact speed V (km/s)."),
    obliquity_deg: float = typer.Option(0.0, "--obliquity-deg", help="Angle from the target normal, 0 ≤ θ < 90."),
    projectile_density: float = typer.Option(2.7, "--projectile-density", help="ρ_p (g/cm³)."),
    bumper_density: float = typer.Option(2.7, "--bumper-density", help="ρ_b (g/cm³)."),
    wall_density: float = typer.Option(2.7, "--wall-density", help="ρ_w (g/cm³), for the rear-wall-only limit."),
    diameter_cm: Optional[float] = typer.Option(None, "--diameter-cm", help="A shot's sphere diameter: give a verdict."),
    plot: Optional[Path] = typer.Option(None, "--plot", help="Write the curve d_c(V), 1–15 km/s (e.g. curve.png)."),
    force: bool = typer.Option(False, "--force", help="Overwrite an existing plot file."),
    as_json: bool = typer.Option(False, "--json", help="Print JSON instead of a table."),
):
    """Critical diameter and regime of a Whipple shield (Christiansen 1993; NASA/TM-2009-214785 §4)."""
    from impactdyn.ble import (
        WhippleShield,
        ballistic_limit_curve,
        critical_diameter,
        normal_velocity,
        perforates,
        rear_wall,
        regime,
        regime_boundaries,
        single_wall_critical_diameter,
    )
    from impactdyn.ble._check import positive

    shield = WhippleShield(bumper_thickness_cm=bumper_cm, wall_thickness_cm=wall_cm, spacing_cm=spacing_cm,
                           wall_yield_ksi=yield_ksi, bumper_density_g_cm3=bumper_density,
                           wall_density_g_cm3=wall_density)
    if diameter_cm is not None:
        positive("diameter_cm", diameter_cm)
    if plot is not None:
        from impactdyn.ble import check_plot_path

        check_plot_path(plot, force)
    dc = critical_diameter(shield, velocity_km_s, obliquity_deg, projectile_density)
    reg = regime(velocity_km_s, obliquity_deg)
    v_lo, v_hi = regime_boundaries(obliquity_deg)
    out = {
        "equation": "NASA JSC Whipple (Christiansen 1993; NASA/TM-2009-214785 §4)",
        "shield": shield.as_dict(),
        "velocity_km_s": velocity_km_s,
        "obliquity_deg": obliquity_deg,
        "projectile_density_g_cm3": projectile_density,
        "normal_velocity_km_s": normal_velocity(velocity_km_s, obliquity_deg),
        "regime": reg.value,
        "regime_boundaries_km_s": [v_lo, v_hi],
        "critical_diameter_cm": dc,
        "rear_wall_only_critical_diameter_cm": single_wall_critical_diameter(
            rear_wall(shield), velocity_km_s, obliquity_deg, projectile_density),
    }
    verdict = None
    if diameter_cm is not None:
        hit = perforates(shield, diameter_cm, velocity_km_s, obliquity_deg, projectile_density)
        verdict = "perforation" if hit else "no perforation"
        out |= {"diameter_cm": diameter_cm, "verdict": verdict}
    if plot is not None:
        from impactdyn.ble import plot_ballistic_limit

        curve = ballistic_limit_curve(shield, None, obliquity_deg, projectile_density)
        shot = None if diameter_cm is None else (velocity_km_s, diameter_cm, verdict == "perforation")
        plot_ballistic_limit([curve], plot, shot=shot,
                             title=f"Whipple shield t_b = {bumper_cm:g} cm, t_w = {wall_cm:g} cm, "
                                   f"S = {spacing_cm:g} cm, σ = {yield_ksi:g} ksi\nθ = {obliquity_deg:g}°, "
                                   f"ρ_p = {projectile_density:g} g/cm³")
        out["plot"] = str(plot)
    if as_json:
        typer.echo(json.dumps(out, indent=2))
        return
    rows = [
        ("velocity V / normal V cos θ", f"{velocity_km_s:g} / {out['normal_velocity_km_s']:.4f} km/s"),
        ("regime", f"{reg.value} (boundaries at V = {v_lo:.4f} and {v_hi:.4f} km/s)"),
        ("critical diameter d_c", f"{dc:.4f} cm"),
        ("rear wall alone (Cour-Palais)", f"{out['rear_wall_only_critical_diameter_cm']:.4f} cm"),
    ]
    if verdict is not None:
        rows.append((f"shot d = {diameter_cm:g} cm", verdict))
    if plot is not None:
        rows.append(("plot", str(plot)))
    _print_table(f"Whipple shield, θ = {obliquity_deg:g}°, ρ_p = {projectile_density:g} g/cm³", rows)


@app.command("single-wall")
def single_wall(
    thickness_cm: float = typer.Option(..., "--thickness-cm", help="Wall thickness t (cm)."),
    velocity_km_s: float = typer.Option(..., "--velocity-km-s", help="Impact speed V (km/s)."),
    obliquity_deg: float = typer.Option(0.0, "--obliquity-deg", help="Angle from the target normal, 0 ≤ θ < 90."),
    projectile_density: float = typer.Option(2.7, "--projectile-density", help="ρ_p (g/cm³)."),
    density: float = typer.Option(2.7, "--density", help="Wall density ρ_t (g/cm³)."),
    brinell: float = typer.Option(95.0, "--brinell", help="Wall Brinell hardness (Al 6061-T6: 95)."),
    sound_speed_km_s: float = typer.Option(5.1, "--sound-speed-km-s", help="Wall speed of sound C (km/s)."),
    mode: str = typer.Option("perforation", "--mode", help="perforation, detached_spall or incipient_spall."),
    diameter_cm: Optional[float] = typer.Option(None, "--diameter-cm", help="A shot's sphere diameter: give a verdict."),
    as_json: bool = typer.Option(False, "--json", help="Print JSON instead of a table."),
):
    """Critical diameter of a monolithic plate (Cour-Palais; NASA/TM-2009-214785 §4)."""
    from impactdyn.ble import SingleWall, single_wall_critical_diameter, single_wall_perforates
    from impactdyn.ble._check import positive

    wall = SingleWall(thickness_cm, density, brinell, sound_speed_km_s)
    if diameter_cm is not None:
        positive("diameter_cm", diameter_cm)
    dc = single_wall_critical_diameter(wall, velocity_km_s, obliquity_deg, projectile_density, mode)
    out = {"equation": "Cour-Palais single wall (NASA/TM-2009-214785 §4)", "wall": wall.as_dict(), "mode": mode,
           "velocity_km_s": velocity_km_s, "obliquity_deg": obliquity_deg,
           "projectile_density_g_cm3": projectile_density, "critical_diameter_cm": dc}
    if diameter_cm is not None:
        hit = single_wall_perforates(wall, diameter_cm, velocity_km_s, obliquity_deg, projectile_density, mode)
        words = mode.replace("_", " ")
        out |= {"diameter_cm": diameter_cm, "verdict": words if hit else f"no {words}"}
    if as_json:
        typer.echo(json.dumps(out, indent=2))
        return
    rows = [("critical diameter d_c", f"{dc:.4f} cm")]
    if diameter_cm is not None:
        rows.append((f"shot d = {diameter_cm:g} cm", out["verdict"]))
    _print_table(f"Single wall t = {thickness_cm:g} cm, V = {velocity_km_s:g} km/s, θ = {obliquity_deg:g}°, "
                 f"{mode}", rows)
