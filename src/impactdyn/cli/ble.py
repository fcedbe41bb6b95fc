"""``impactdyn ble``: ballistic limit equations (NASA JSC Whipple shield, Cour-Palais single wall).

Every bad option value is an :class:`~impactdyn.InputError` whose message starts with the
option's name (exit code 2, no traceback), raised before any work is done.
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Optional

import typer

from impactdyn._errors import InputError

app = typer.Typer(help="Ballistic limit equations: NASA JSC Whipple shield, Cour-Palais single wall "
                       "(cm, g/cm³, km/s, ksi).", no_args_is_help=True)

_EQUATION_HELP = "Whipple equation by name: jsc1993 or jsc2011 (default: jsc2011)."


@contextmanager
def _option(name: str) -> Iterator[None]:
    """Prefix the message of an :class:`InputError` raised inside with the option ``name``."""
    try:
        yield
    except InputError as err:
        raise InputError(f"{name}: {err}") from None


def _check_options(**checks) -> None:
    """``option=(check, field, value)``: run each check, naming the option if it fails."""
    for option, (check, *args) in checks.items():
        with _option("--" + option.replace("_", "-")):
            check(*args)


def _shield(bumper_cm, wall_cm, spacing_cm, yield_ksi, bumper_density, wall_density):
    """The WhippleShield of the options, each value checked under its option's name."""
    from impactdyn.ble import WhippleShield
    from impactdyn.ble import check_positive as positive

    _check_options(bumper_cm=(positive, "bumper_thickness_cm", bumper_cm),
                   wall_cm=(positive, "wall_thickness_cm", wall_cm),
                   spacing_cm=(positive, "spacing_cm", spacing_cm),
                   yield_ksi=(positive, "wall_yield_ksi", yield_ksi),
                   bumper_density=(positive, "bumper_density_g_cm3", bumper_density),
                   wall_density=(positive, "wall_density_g_cm3", wall_density))
    return WhippleShield(bumper_cm, wall_cm, spacing_cm, yield_ksi, bumper_density, wall_density)


def _equation(name: str | None):
    from impactdyn.ble import get_equation

    with _option("--equation"):
        return get_equation(name)


def _print_table(title: str, rows: list[tuple[str, str]], header: tuple[str, ...] | None = None) -> None:
    from rich.console import Console
    from rich.table import Table

    t = Table(title=title, show_header=header is not None)
    for name in header or ("quantity", "value"):
        t.add_column(name)
    for row in rows:
        t.add_row(*row)
    Console().print(t)


def _cm(x: float | None) -> str:
    return "none (no fixed point)" if x is None else f"{x:.4f} cm"


@app.command()
def whipple(
    bumper_cm: float = typer.Option(..., "--bumper-cm", help="Bumper thickness t_b (cm)."),
    wall_cm: float = typer.Option(..., "--wall-cm", help="Rear wall thickness t_w (cm)."),
    spacing_cm: float = typer.Option(..., "--spacing-cm", help="Standoff S between bumper and rear wall (cm)."),
    yield_ksi: float = typer.Option(..., "--yield-ksi", help="Rear wall yield stress σ (ksi)."),
    velocity_km_s: float = typer.Option(..., "--velocity-km-s", help="Impact speed V (km/s)."),
    obliquity_deg: float = typer.Option(0.0, "--obliquity-deg",
                                        help="Angle from the target normal, 0 ≤ θ < 90 (evaluated at 65 above 65)."),
    projectile_density: float = typer.Option(2.7, "--projectile-density", help="ρ_p (g/cm³)."),
    bumper_density: float = typer.Option(2.7, "--bumper-density", help="ρ_b (g/cm³)."),
    wall_density: float = typer.Option(2.7, "--wall-density", help="ρ_w (g/cm³), for the rear-wall-only limit."),
    equation: Optional[str] = typer.Option(None, "--equation", help=_EQUATION_HELP),
    diameter_cm: Optional[float] = typer.Option(None, "--diameter-cm",
                                                help="A shot's sphere diameter: give a verdict."),
    plot: Optional[Path] = typer.Option(None, "--plot", help="Write the curve d_c(V), 1–15 km/s (e.g. curve.png)."),
    test_shots: bool = typer.Option(False, "--test-shots",
                                    help="Draw the database's shots near this shield on the plot "
                                         "(t_b, t_w, S within ±10 %, θ within ±10°)."),
    force: bool = typer.Option(False, "--force", help="Overwrite an existing plot file."),
    as_json: bool = typer.Option(False, "--json", help="Print JSON instead of a table."),
):
    """Critical diameter, regime and verdict of a Whipple shield (NASA JSC equations)."""
    from impactdyn.ble import (
        ballistic_limit,
        jsc_verdict,
        normal_velocity,
        rear_wall,
        regime_boundaries,
        single_wall_critical_diameter,
    )
    from impactdyn.ble import check_obliquity as scalar_obliquity
    from impactdyn.ble import check_positive as positive

    eq = _equation(equation)
    shield = _shield(bumper_cm, wall_cm, spacing_cm, yield_ksi, bumper_density, wall_density)
    _check_options(velocity_km_s=(positive, "velocity_km_s", velocity_km_s),
                   obliquity_deg=(scalar_obliquity, obliquity_deg),
                   projectile_density=(positive, "projectile_density", projectile_density))
    if diameter_cm is not None:
        _check_options(diameter_cm=(positive, "diameter_cm", diameter_cm))
    if plot is not None:
        from impactdyn.ble import check_plot_path

        with _option("--plot"):
            check_plot_path(plot, force)
    if diameter_cm is None:
        limit = ballistic_limit(shield, velocity_km_s, obliquity_deg, projectile_density, eq.name)
        dc = float(limit.critical_diameter_cm)
        answer = {"critical_diameter_cm": None if math.isnan(dc) else dc, "threshold_cm": float(limit.threshold_cm),
                  "regime": str(limit.regime[()]), "note": limit.note[()]}
    else:
        answer = jsc_verdict(shield, diameter_cm, velocity_km_s, obliquity_deg, projectile_density, eq.name)
    v_lo, v_hi = regime_boundaries(obliquity_deg, eq.name)
    out = {
        "equation": eq.name,
        "equation_title": eq.title,
        "shield": shield.as_dict(),
        "velocity_km_s": velocity_km_s,
        "obliquity_deg": obliquity_deg,
        "projectile_density_g_cm3": projectile_density,
        "normal_velocity_km_s": normal_velocity(velocity_km_s, obliquity_deg),
        "regime": answer["regime"],
        "regime_boundaries_km_s": [v_lo, v_hi],
        "critical_diameter_cm": answer["critical_diameter_cm"],
        "threshold_cm": answer["threshold_cm"],
        "note": answer["note"],
        "rear_wall_only_critical_diameter_cm": single_wall_critical_diameter(
            rear_wall(shield), velocity_km_s, obliquity_deg, projectile_density),
    }
    if diameter_cm is not None:
        out |= {"diameter_cm": diameter_cm, "verdict": answer["verdict"]}
    if plot is not None:
        from impactdyn.ble import ballistic_limit_curve, nearby_shots, plot_ballistic_limit

        curve = ballistic_limit_curve(shield, None, obliquity_deg, projectile_density, eq.name)
        shot = None if diameter_cm is None else (velocity_km_s, diameter_cm, out["verdict"] == "perforation")
        plot_ballistic_limit([curve], plot, shot=shot,
                             shots=nearby_shots(shield, obliquity_deg) if test_shots else None,
                             title=f"Whipple shield {_shield_label(bumper_cm, wall_cm, spacing_cm, yield_ksi)}\n"
                                   f"θ = {obliquity_deg:g}°, ρ_p = {projectile_density:g} g/cm³")
        out["plot"] = str(plot)
    if as_json:
        typer.echo(json.dumps(out, indent=2))
        return
    rows = [
        ("equation", f"{eq.name}: {eq.title}"),
        ("velocity V / normal V cos θ", f"{velocity_km_s:g} / {out['normal_velocity_km_s']:.4f} km/s"),
        ("regime", f"{out['regime']} (boundaries at V = {v_lo:.4f} and {v_hi:.4f} km/s)"),
        ("critical diameter d_c", _cm(out["critical_diameter_cm"])),
        ("rear wall alone (Cour-Palais)", f"{out['rear_wall_only_critical_diameter_cm']:.4f} cm"),
    ]
    if out["note"] is not None:
        rows += [("perforation threshold", _cm(out["threshold_cm"])), ("note", out["note"])]
    if diameter_cm is not None:
        rows.append((f"shot d = {diameter_cm:g} cm", out["verdict"]))
    if plot is not None:
        rows.append(("plot", str(plot)))
    _print_table(f"Whipple shield, θ = {obliquity_deg:g}°, ρ_p = {projectile_density:g} g/cm³", rows)


def _percent(x: float | None) -> str:
    return "–" if x is None else f"{100 * x:.1f} %"


def _score_rows(validation) -> list[tuple[str, ...]]:
    groups = [("all shots", validation.overall), ("with a fixed point", validation.with_fixed_point)]
    groups += [(f"regime: {k}", s) for k, s in validation.by_regime.items()]
    groups += [(f"obliquity {k}", s) for k, s in validation.by_obliquity.items()]
    return [(name, str(s.shots), _percent(s.accuracy), _percent(s.false_safe_rate), _percent(s.false_alarm_rate))
            for name, s in groups]


@app.command()
def validate(
    equation: Optional[str] = typer.Option(None, "--equation", help="Score one equation (default: every one)."),
    database: Optional[Path] = typer.Option(None, "--database",
                                            help="Test database CSV (default: the packaged 1135 shots)."),
    plot: Optional[Path] = typer.Option(None, "--plot", help="Write d/d_c against V cos θ (e.g. validate.png)."),
    force: bool = typer.Option(False, "--force", help="Overwrite an existing plot file."),
    as_json: bool = typer.Option(False, "--json", help="Print JSON instead of tables."),
    bumper_cm: Optional[float] = typer.Option(None, "--bumper-cm", help="Configuration: bumper thickness t_b (cm)."),
    wall_cm: Optional[float] = typer.Option(None, "--wall-cm", help="Configuration: rear wall thickness t_w (cm)."),
    spacing_cm: Optional[float] = typer.Option(None, "--spacing-cm", help="Configuration: standoff S (cm)."),
    yield_ksi: float = typer.Option(40.0, "--yield-ksi", help="Configuration: rear wall yield stress σ (ksi)."),
    bumper_density: float = typer.Option(2.7, "--bumper-density", help="Configuration: ρ_b (g/cm³)."),
    obliquity_deg: float = typer.Option(0.0, "--obliquity-deg", help="Configuration: angle from the normal."),
    projectile_density: float = typer.Option(2.7, "--projectile-density", help="Configuration: ρ_p (g/cm³)."),
    band: float = typer.Option(0.10, "--band", help="Shots near the configuration: relative band on t_b, t_w, S."),
    obliquity_band_deg: float = typer.Option(10.0, "--obliquity-band-deg",
                                             help="Shots near the configuration: obliquity within ± this."),
):
    """Score the Whipple equations on the test database: accuracy, false-safe and false-alarm rates.

    With --bumper-cm, --wall-cm and --spacing-cm, also the shots near that configuration
    (and, with --plot, its curves with those shots on them).
    """
    from impactdyn.ble import EQUATIONS, read_database
    from impactdyn.ble import validate as score
    from impactdyn.ble import check_obliquity as scalar_obliquity
    from impactdyn.ble import check_positive as positive

    names = list(EQUATIONS) if equation is None else [_equation(equation).name]
    config = (bumper_cm, wall_cm, spacing_cm)
    if any(x is not None for x in config) and None in config:
        raise InputError("--bumper-cm, --wall-cm and --spacing-cm describe one configuration: give all three")
    shield = None
    if bumper_cm is not None:
        shield = _shield(bumper_cm, wall_cm, spacing_cm, yield_ksi, bumper_density, 2.7)
        _check_options(obliquity_deg=(scalar_obliquity, obliquity_deg),
                       projectile_density=(positive, "projectile_density", projectile_density),
                       band=(positive, "band", band),
                       obliquity_band_deg=(positive, "obliquity_band_deg", obliquity_band_deg))
    if plot is not None:
        from impactdyn.ble import check_plot_path

        with _option("--plot"):
            check_plot_path(plot, force)
    db = read_database(database)
    results = [score(name, db) for name in names]
    out = {"database": db.path, "shots": len(db), "equations": [r.as_dict() for r in results]}
    near = curves = None
    if shield is not None:
        from impactdyn.ble import ballistic_limit_curve, nearby_shots

        near = nearby_shots(shield, obliquity_deg, db, band, obliquity_band_deg)
        curves = [ballistic_limit_curve(shield, None, obliquity_deg, projectile_density, name) for name in names]
        out["configuration"] = {
            "shield": shield.as_dict(), "obliquity_deg": obliquity_deg, "band": band,
            "obliquity_band_deg": obliquity_band_deg, "nearby_shots": len(near), "nearby_lines": near.line.tolist(),
            "scores": {name: score(name, near).overall.as_dict() for name in names},
        }
    if plot is not None:
        from impactdyn.ble import plot_validation

        plot_validation(results, plot, curves, near,
                        None if shield is None else
                        f"{_shield_label(bumper_cm, wall_cm, spacing_cm, yield_ksi)}, θ = {obliquity_deg:g}°: "
                        f"{len(near)} shots within ±{100 * band:g} %, ±{obliquity_band_deg:g}°")
        out["plot"] = str(plot)
    if as_json:
        typer.echo(json.dumps(out, indent=2))
        return
    for r in results:
        _print_table(f"{r.equation}: {r.title} on {len(db)} shots ({r.no_fixed_point} without a fixed point)",
                     _score_rows(r), ("shots", "n", "accuracy", "false-safe", "false-alarm"))
    if shield is not None:
        c = out["configuration"]
        typer.echo(f"{c['nearby_shots']} shots near the configuration (each with its own shield); called right: "
                   + ", ".join(f"{k} {s['correct']}" for k, s in c["scores"].items()))
    if plot is not None:
        typer.echo(f"plot: {plot}")


def _shield_label(bumper_cm: float, wall_cm: float, spacing_cm: float, yield_ksi: float) -> str:
    return f"t_b = {bumper_cm:g} cm, t_w = {wall_cm:g} cm, S = {spacing_cm:g} cm, σ = {yield_ksi:g} ksi"


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
    diameter_cm: Optional[float] = typer.Option(None, "--diameter-cm",
                                                help="A shot's sphere diameter: give a verdict."),
    as_json: bool = typer.Option(False, "--json", help="Print JSON instead of a table."),
):
    """Critical diameter of a monolithic plate (Cour-Palais; NASA/TM-2009-214785 §4)."""
    from impactdyn.ble import SingleWall, single_wall_critical_diameter, single_wall_perforates
    from impactdyn.ble import check_obliquity as scalar_obliquity
    from impactdyn.ble import check_positive as positive

    _check_options(thickness_cm=(positive, "thickness_cm", thickness_cm),
                   velocity_km_s=(positive, "velocity_km_s", velocity_km_s),
                   obliquity_deg=(scalar_obliquity, obliquity_deg),
                   projectile_density=(positive, "projectile_density", projectile_density),
                   density=(positive, "density_g_cm3", density),
                   brinell=(positive, "brinell_hardness", brinell),
                   sound_speed_km_s=(positive, "sound_speed_km_s", sound_speed_km_s))
    if diameter_cm is not None:
        _check_options(diameter_cm=(positive, "diameter_cm", diameter_cm))
    wall = SingleWall(thickness_cm, density, brinell, sound_speed_km_s)
    with _option("--mode"):  # every other value is checked above
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
