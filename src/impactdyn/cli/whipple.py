"""``impactdyn whipple``: the end-to-end Whipple-shield pipeline and ballistic-limit campaigns."""

from __future__ import annotations

from pathlib import Path
from typing import List, Optional

import typer

from impactdyn.cli._progress import progress_bars

app = typer.Typer(help="Whipple shield: SPH shield impact → debris cloud → rear-wall load → the wall's response "
                       "and verdict → decks and report.",
                  no_args_is_help=True)

STAGE_HELP = "shield, binning, debris, wall, draws, decks or report"
KEEP_HELP = ("lean (default): what the report, ParaView and a restart (--from) need; all: every file besides "
             "(the debris particles' states and VTU files, every frame of the wall's ParaView series, the "
             "LS-DYNA and DYNA3D decks).")
RESUME_HELP = ("Go on in the folder an interrupted run of the same command left: its finished shots are "
               "read back, not run again (the case and options must be the same).")
DRAWS_HELP = ("Draws of the fragments' random partition ([shield] fragment_draws, 1-64; needs failed_fragments = "
              "\"grady\"): the SPH once, then per draw the fragments, the debris and the wall; prints the "
              "perforations in k of N draws with P and its 95 % interval.")


@app.command()
def run(
    case: Path = typer.Argument(..., help="Whipple case file (TOML)."),
    out: Path = typer.Option(..., "-o", "--out", help="Run folder to create (or to restart, with --from)."),
    start: str = typer.Option("shield", "--from", help=f"First stage to run ({STAGE_HELP}); the earlier "
                                                       "stages are taken from the existing run folder."),
    force: bool = typer.Option(False, "--force", help="Overwrite an existing run folder."),
    keep: str = typer.Option("lean", "--keep", metavar="lean|all", help=KEEP_HELP),
    draws: Optional[int] = typer.Option(None, "--draws", metavar="N", help=DRAWS_HELP),
):
    """Run a shot end to end: shield impact, binning, debris flight and deposition on the rear wall, the wall's
    finite-element response and its verdict (perforation, detached spall or no perforation, beside the JSC
    equation's), wall decks, report."""
    from impactdyn._config import load_toml

    _check_keep(keep)
    _echo_summary(_run_with_progress(_with_draws(load_toml(case), draws, str(case)), out, start, force, keep), out)


@app.command()
def shot(
    database: str = typer.Option(..., "--database", metavar="LINE|ID",
                                 help="The test shot: its line in the test database file, or its shot ID "
                                      "(line:N or id:X where a number is both)."),
    out: Optional[Path] = typer.Option(None, "-o", "--out", help="Run folder to create."),
    from_case: Optional[Path] = typer.Option(None, "--from-case",
                                             help="Base case whose numerics the shot takes (default: the "
                                                  "Table 2 7a example, examples/whipple/table2_7a.toml)."),
    write_case: Optional[Path] = typer.Option(None, "--write-case",
                                              help="Write the shot's case file (TOML) here and run nothing; print the "
                                                   "test's outcome and the JSC verdict."),
    force: bool = typer.Option(False, "--force", help="Overwrite an existing run folder or case file."),
    keep: str = typer.Option("lean", "--keep", metavar="lean|all", help=KEEP_HELP),
    draws: Optional[int] = typer.Option(None, "--draws", metavar="N", help=DRAWS_HELP),
):
    """Run a shot of the test database (or write its case) and print the test's outcome beside the verdicts."""
    from impactdyn._errors import InputError
    from impactdyn._runfolder import atomic_output
    from impactdyn.whipple import (WhippleCase, alloy_substitutions, ble_verdict, database_shot, database_shot_case,
                                   database_shot_case_text)

    if (out is None) == (write_case is None):
        raise InputError("give -o OUT to run the shot, or --write-case FILE to write its case and run nothing")
    _check_keep(keep)
    test = database_shot(database)
    raw = database_shot_case(test, from_case)
    if write_case is not None and write_case.exists() and not force:
        raise InputError(f"{write_case}: exists; pass --force to overwrite it")
    for note in alloy_substitutions(test).values():
        typer.echo(f"note: {note}")
    if write_case is not None:
        text = database_shot_case_text(test, raw, from_case)
        with atomic_output(write_case) as tmp:
            tmp.write_text(text)
        typer.echo(f"case of {test.name} in {write_case}")
        typer.echo(f"test {test.name}: {test.outcome}; simulated: not run "
                   f"(impactdyn whipple run {write_case} -o OUT); JSC: {ble_verdict(WhippleCase.model_validate(raw))['verdict']}")
        return
    s = _run_with_progress(_with_draws(raw, draws, f"shot {test.name}"), out, "shield", force, keep)
    _echo_summary(s, out)
    typer.echo(f"test {test.name}: {test.outcome}; simulated: {s['wall']['verdict']}; JSC: {s['ble']['verdict']}")


def _with_draws(raw: dict, draws: int | None, source: str):
    """The case of ``raw`` with ``--draws`` set as ``shield.fragment_draws`` (validated: a bad N is refused
    naming the flag and the key)."""
    from impactdyn._config import set_dotted, validate
    from impactdyn.whipple import WhippleCase

    if draws is None:
        return validate(WhippleCase, raw, source)
    return validate(WhippleCase, set_dotted(raw, "shield.fragment_draws", draws), f"{source} (--draws {draws})")


def _check_keep(keep: str) -> None:
    """``--keep``: lean or all (before the case is read or any work done)."""
    from impactdyn._errors import InputError

    if keep not in ("lean", "all"):
        raise InputError(f"--keep {keep!r}: choose lean or all")


def _run_with_progress(case, out: Path, start: str, force: bool, keep: str = "lean") -> dict:
    """Run the pipeline under the progress bars; returns its summary."""
    from impactdyn.whipple import run_whipple

    bar, update = progress_bars(counts=False)
    with bar:
        return run_whipple(case, out, start=start, force=force, progress=update, keep=keep)


def _echo_summary(s: dict, out: Path) -> None:
    """The lines a finished run prints: the equation's verdict, the cloud, the load and the wall's response."""
    from impactdyn.units import AREAL_MOMENTUM_UNIT
    from impactdyn.whipple import draws_statement, wall_ending, wall_permanent_bulge

    ble, cloud, dep = s["ble"], s["cloud"], s["deposition"]
    typer.echo(f"ballistic limit ({ble['equation']}): perforation above d = {ble['threshold_cm']:.4f} cm "
               f"({ble['regime']} regime) → {ble['verdict']}")
    if cloud.get("n_debris_particles"):
        typer.echo(f"debris cloud: leading edge {cloud['leading_edge_velocity_km_s']:.3f} km/s, centre of mass "
                   f"{cloud['centre_of_mass_speed_km_s']:.3f} km/s at {cloud['axis_angle_from_normal_deg']:.1f}°, "
                   f"cone half-angle {cloud['cone_half_angle_deg']:.1f}°")
    typer.echo(f"wall: peak areal momentum {dep['peak_areal_momentum_N_s_cm2']:.4g} {AREAL_MOMENTUM_UNIT}, normal impulse "
               f"{dep['impulse_on_wall_normal_N_s_full_model']:.4g} N·s (full model); "
               f"{s['wall_time_s']:.1f} s")
    ledger = dep.get("momentum_ledger_g_cm_us")
    if ledger and ledger["in"][1] > 0:
        share = {k: 100.0 * ledger[k][1] / ledger["in"][1]
                 for k in ("deposited", "outside_window", "added_at_wall")}
        ejecta = (f" (the crater ejecta's {share['added_at_wall']:.1f} % included, wall.momentum_transfer)"
                  if ledger["added_at_wall"][1] else "")
        typer.echo(f"the debris's normal momentum: {share['deposited']:.1f} % on the wall{ejecta}, "
                   f"{share['outside_window']:.1f} % outside the arrival window ([filter] t_min_us, t_cut_us; "
                   "compact fragments: the wall run)")
    w = s["wall"]
    if s["draws"]["n_draws"] > 1:
        typer.echo(f"over the fragments' draws: {draws_statement(s['draws'])}")
    typer.echo(f"wall response: {w['verdict']} ({w['criterion']}); crater depth {w.get('crater_depth_ratio', 0):.2f} "
               f"of the thickness, rear bulge {w.get('rear_bulge_cm', 0):.3g} cm; report in {Path(out) / 'report.html'}")
    if w.get("caution"):
        typer.echo(f"caution: {w['caution']}")
    if w.get("ended_by") in ("ceiling", "perforated"):
        typer.echo(f"wall run ended at {wall_ending(w)}")
    if "settled" in w:
        typer.echo(f"rear-face permanent bulge (the wall brought to rest): {wall_permanent_bulge(w)}")


@app.command()
def campaign(
    case: Path = typer.Argument(..., help="Base Whipple case file (TOML)."),
    velocity: str = typer.Option(..., "--velocity", help="Impact velocities START:STOP:N (km/s), e.g. 5:11:4."),
    diameter: str = typer.Option(..., "--diameter", help="Sphere diameters START:STOP:N (cm), e.g. 0.3:0.7:5."),
    out: Path = typer.Option(..., "-o", "--out", help="Campaign folder to create."),
    force: bool = typer.Option(False, "--force", help="Overwrite an existing folder."),
    resume: bool = typer.Option(False, "--resume", help=RESUME_HELP),
    workers: Optional[int] = typer.Option(None, "--workers", help="Shots run at once (default: all cores)."),
    dask: Optional[str] = typer.Option(None, "--dask", help="'local' for a LocalCluster, or a scheduler address."),
    keep_all: bool = typer.Option(False, "--keep-all", help="Keep every file of each shot (default: a lean "
                                                            "folder: summary, report, plots, wall measures, decks)."),
):
    """Run a grid of (velocity, diameter) shots in parallel and draw them over the ballistic-limit curve."""
    from rich.progress import Progress

    from impactdyn._config import load_toml, parse_range
    from impactdyn._runfolder import check_target
    from impactdyn.whipple import run_campaign

    check_target(out, force or resume)
    velocities = parse_range("--velocity", velocity, "5:11:4")
    diameters = parse_range("--diameter", diameter, "0.3:0.7:5")
    raw = load_toml(case)
    with Progress(transient=True) as bar:
        task = bar.add_task("shots", total=len(velocities) * len(diameters))
        rows = run_campaign(raw, velocities, diameters, out, source=str(case), force=force, resume=resume,
                            scheduler="dask" if dask else "processes", workers=workers, address=dask,
                            keep_all=keep_all, progress=lambda: bar.advance(task))
    typer.echo(f"{len(rows)} shots; table in {out / 'campaign.csv'}, plot in {out / 'campaign.png'}")


@app.command()
def limit(
    case: Path = typer.Argument(..., help="Base Whipple case file (TOML); its diameter is searched."),
    velocity: str = typer.Option(..., "--velocity", help="Impact velocities START:STOP:N (km/s), e.g. 3:11:5."),
    out: Path = typer.Option(..., "-o", "--out", help="Folder to create."),
    resume: bool = typer.Option(False, "--resume", help=RESUME_HELP),
    tolerance: float = typer.Option(0.02, "--tolerance", help="Bisect until the bracket is this narrow (cm)."),
    bracket_ratio: float = typer.Option(1.25, "--bracket-ratio",
                                        help="First bracket d_JSC/r .. d_JSC*r, moved by r until it holds the "
                                             "change of verdict."),
    bracket: Optional[List[str]] = typer.Option(None, "--bracket",
                                                help="V:LOW:HIGH: start velocity V's search from the diameters "
                                                     "LOW..HIGH (cm) instead of the JSC bracket, e.g. the bracket "
                                                     "of an interrupted search; repeatable."),
    force: bool = typer.Option(False, "--force", help="Overwrite an existing folder."),
    workers: Optional[int] = typer.Option(None, "--workers", help="Shots run at once (default: all cores)."),
    dask: Optional[str] = typer.Option(None, "--dask", help="'local' for a LocalCluster, or a scheduler address."),
    keep_all: bool = typer.Option(False, "--keep-all", help="Keep every file of each shot."),
    draws: Optional[int] = typer.Option(None, "--draws", metavar="N",
                                        help=DRAWS_HELP + " The search closes on P = 0.5; a logistic over every "
                                             "draw gives the band P = 0.1-0.9."),
):
    """Find, for each velocity, the diameter where the simulated wall verdict changes (bisection)."""
    from rich.progress import Progress

    from impactdyn._config import load_toml, parse_range
    from impactdyn._runfolder import check_target
    from impactdyn.whipple import run_limit

    check_target(out, force or resume)
    velocities = parse_range("--velocity", velocity, "3:11:5")
    brackets = dict(_parse_bracket(spec) for spec in bracket or [])
    raw = load_toml(case)
    with Progress(transient=True) as bar:
        task = bar.add_task("shots", total=None)
        rows = run_limit(raw, velocities, out, source=str(case), tolerance_cm=tolerance, bracket_ratio=bracket_ratio,
                         brackets=brackets, force=force, resume=resume, scheduler="dask" if dask else "processes",
                         workers=workers, address=dask, keep_all=keep_all, draws=draws,
                         progress=lambda n: bar.update(task, completed=n))
    for r in rows:
        d = "–" if r["limit_diameter_cm"] is None else f"{r['limit_diameter_cm']:.4f} ± {r['half_width_cm']:.4f} cm"
        typer.echo(f"V = {r['velocity_km_s']:g} km/s: simulated limit {d} ({r['status']}, {r['n_shots']} shots); "
                   f"JSC {r['jsc_critical_diameter_cm']:.4f} cm")
        if r["p10_diameter_cm"] is not None:
            typer.echo(f"  over the draws: P = 0.5 at {r['draws_d50_cm']:.4f} cm, P = 0.1–0.9 from "
                       f"{r['p10_diameter_cm']:.4f} to {r['p90_diameter_cm']:.4f} cm ({r['band_note']})")
        elif r["band_note"]:
            typer.echo(f"  {r['band_note']}")
        if r["caution"]:
            typer.echo(f"  caution: {r['caution']}")
    typer.echo(f"table in {out / 'limit.csv'}, plot in {out / 'limit.png'}")


@app.command()
def validate(
    out: Path = typer.Option(..., "-o", "--out", help="Validation folder to create."),
    select: Optional[str] = typer.Option(None, "--select", metavar="RULE",
                                         help="The shots a selection rule picks: a shipped rule (set-1 … set-4) "
                                              "or a rule file (TOML)."),
    lines: Optional[str] = typer.Option(None, "--lines", metavar="L1,L2,...",
                                        help="These shots, by their lines in the test database file."),
    from_case: Optional[Path] = typer.Option(None, "--from-case",
                                             help="Base case whose numerics the shots take (default: the "
                                                  "Table 2 7a example)."),
    force: bool = typer.Option(False, "--force", help="Overwrite an existing folder."),
    resume: bool = typer.Option(False, "--resume", help=RESUME_HELP),
    workers: Optional[int] = typer.Option(None, "--workers", help="Shots run at once (default: all cores)."),
    dask: Optional[str] = typer.Option(None, "--dask", help="'local' for a LocalCluster, or a scheduler address."),
    keep_all: bool = typer.Option(False, "--keep-all", help="Keep every file of each shot."),
    draws: Optional[int] = typer.Option(None, "--draws", metavar="N", help=DRAWS_HELP),
):
    """Run test shots of the database and score the simulated verdicts, and the equation's, by distance
    from the equation's limit."""
    from rich.progress import Progress

    from impactdyn._errors import InputError
    from impactdyn._runfolder import check_target
    from impactdyn.ble import read_database
    from impactdyn.whipple import database_shot, load_rule, rule_hash, run_validation, select_shots

    if (select is None) == (lines is None):
        raise InputError("give --select RULE or --lines L1,L2,... (one of them)")
    check_target(out, force or resume)
    db = read_database()
    if select is not None:
        rule = load_rule(select)
        shots = [database_shot(int(db.line[i]), db) for i in select_shots(rule, db)]
        selection = {"rule": rule.name, "sha256": rule_hash(rule), "fixed": rule.fixed and rule.fixed.date}
    else:
        shots = [database_shot(_line(token), db) for token in lines.split(",")]
        selection = {"lines": [shot.line for shot in shots]}
    with Progress(transient=True) as bar:
        task = bar.add_task("shots", total=len(shots))
        scores = run_validation(shots, out, selection=selection, base=from_case, force=force, resume=resume,
                                scheduler="dask" if dask else "processes", workers=workers, address=dask,
                                keep_all=keep_all, draws=draws, progress=lambda: bar.advance(task))
    for who, name in (("simulated", "simulation"), ("jsc", "JSC 2011")):
        a = scores[who]["overall"]["accuracy"]
        typer.echo(f"{name}: {a['count']} of {a['of']} right ({100 * a['low']:.0f}–{100 * a['high']:.0f} %, 95 %)")
    for who, f in (scores.get("forecast") or {}).items():
        typer.echo(f"{who} as a forecast: Brier {f['brier']:.3f} ({f['brier_95'][0]:.3f}–{f['brier_95'][1]:.3f}), "
                   f"log-loss {f['log_loss']:.3f} ({f['log_loss_95'][0]:.3f}–{f['log_loss_95'][1]:.3f})")
    if select is not None and rule.fixed is None:
        typer.echo(f"note: rule {rule.name} is not fixed (impactdyn whipple fix-rule): these scores cannot judge a "
                   "change")
    typer.echo(f"table in {out / 'validation.csv'}, scores by band in {out / 'validation.html'}")


@app.command("fix-rule")
def fix_rule(rule: Path = typer.Argument(..., help="Selection rule file (TOML) to fix before its shots are run.")):
    """Write the date and the hash of a selection rule into it: from then on it cannot change."""
    from impactdyn.whipple import fix_rule as fix

    fixed = fix(rule)
    typer.echo(f"{rule}: rule {fixed.name} fixed on {fixed.fixed.date} (sha256 {fixed.fixed.sha256[:12]}…)")


def _line(token: str) -> int:
    from impactdyn._errors import InputError

    try:
        return int(token)
    except ValueError:
        raise InputError(f"--lines: {token.strip()!r} is not a line number") from None


def _parse_bracket(spec: str) -> tuple[float, tuple[float, float]]:
    """``V:LOW:HIGH`` → (V, (LOW, HIGH))."""
    from impactdyn._errors import InputError

    try:
        v, low, high = (float(part) for part in spec.split(":"))
    except ValueError:
        raise InputError(f"--bracket {spec!r}: expected V:LOW:HIGH (km/s, cm, cm), e.g. 7:0.95:1.10") from None
    return v, (low, high)
