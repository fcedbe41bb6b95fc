"""How the simulation does on real test shots: run a set of database shots and score the verdicts.

Each shot is the database shot's case on a base case (:func:`~impactdyn.whipple.database_shot_case`),
run end to end as a lean shot (:mod:`._shots`) into ``runs/line<N>/``.  A shot counts as
called perforated when the wall stage's verdict is a perforation or a detached spall (JSC test
practice counts both as a failed rear wall); the JSC 2011 equation (the package default) is
scored on the same shots.

Scores are reported by band of the distance from the equation's limit, |d/d_lim − 1| (< 5 %,
5–15 %, 15–30 %, ≥ 30 %, and overall; :func:`impactdyn.ble.score_by_distance`): near the limit
the tests themselves flip (the equation calls half of the shots within 5 % of it right), so a
score without its band and its interval cannot tell a better model from luck.  Each accuracy,
false-safe rate (perforated in the test, called safe) and false-alarm rate has its 95 % Wilson
interval; the exact McNemar test compares the simulation with the equation on the same shots.

Folder (a family folder, :mod:`impactdyn._family`: written as the shots finish, resumable):
``validation.csv`` / ``validation.json`` (one row per shot), ``scores.json``, ``validation.png``
(the shots as d/d_lim against V cos θ, marked by agreement with the test) and ``validation.html``
(:func:`validation_page`: the selection and the case's options in words, what stands behind the
simulated verdict, the scores, every shot).
"""

from __future__ import annotations

import html
import json
import math
from pathlib import Path

import numpy as np

from impactdyn._config import non_defaults, set_dotted, validate
from impactdyn._errors import InputError
from impactdyn._family import FamilyFolder, run_members
from impactdyn.ble import DISTANCE_BANDS, mcnemar, score_by_distance
from impactdyn.whipple._case import TEST_OUTCOMES, WhippleCase
from impactdyn.whipple._stages import FAILED_VERDICTS
from impactdyn.whipple._report import ble_verdict, verdict_record
from impactdyn.whipple._selection import shipped_rule
from impactdyn.whipple._shots import run_shot, shot_tasks, shot_workers
from impactdyn.whipple._database_shot import (EXAMPLE_CASE, DatabaseShot, database_shot_case, load_base_case,
                                              shot_settings)

VALIDATION_HEADER = ["line", "source", "shot_id", "diameter_cm", "velocity_km_s", "obliquity_deg",
                     "normal_velocity_km_s", "jsc_limit_cm", "d_over_limit", "test_perforated", "jsc_perforated",
                     "simulated_verdict", "simulated_perforated", "simulated_right", "jsc_right", "n_draws",
                     "p_perforation", "caution", "run"]


def run_validation(shots: list[DatabaseShot], outdir: str | Path, *, selection: dict, base: str | Path | None = None,
                   force: bool = False, resume: bool = False, scheduler: str = "processes",
                   workers: int | None = None, address: str | None = None, keep_all: bool = False,
                   draws: int | None = None, progress=None) -> dict:
    """Run ``shots`` into ``outdir`` and score them (module docstring); returns ``scores.json``'s content.

    ``selection``: how the shots were chosen (the rule's name and hash, or the lines given),
    recorded with the folder so that a resume under another selection is refused.  ``draws``: the
    fragments' draws of every shot (``shield.fragment_draws``; None: the base case's).
    """
    if not shots:
        raise InputError("validate: the selection holds no shot")
    raws = [database_shot_case(shot, base) for shot in shots]
    if draws is not None:
        raws = [set_dotted(raw, "shield.fragment_draws", draws) for raw in raws]
    cases = [validate(WhippleCase, raw, source=f"test shot {shot.name}" + ("" if draws is None else f" (--draws {draws})"))
             for shot, raw in zip(shots, raws)]
    settings = {"selection": selection, "keep_all": keep_all,
                # the [test_shot] table restates the selection's shot and changes no result: without it a folder
                # started before the cases carried it resumes
                "cases": {_run_name(s): c.model_dump(mode="json", exclude={"test_shot"}) for s, c in zip(shots, cases)}}
    rows: list = [None] * len(shots)
    with FamilyFolder(outdir, "whipple validate", settings, table="validation.csv", member="shot", force=force,
                      resume=resume) as family:
        def record(k: int, summary: dict) -> None:
            rows[k] = _row(shots[k], cases[k], summary)
            family.finished += 1
            _write_table(family, [r for r in rows if r is not None])
            if progress:
                progress()

        summaries = [family.path / "runs" / _run_name(shot) / "summary.json" for shot in shots]
        run_members(run_shot, summaries,
                    lambda pending: shot_tasks([cases[k] for k in pending], [summaries[k].parent for k in pending],
                                               scheduler, workers, keep_all),
                    record, scheduler=scheduler, workers=shot_workers(scheduler, workers, len(shots)), address=address)
        scores = score_validation(rows) | {"selection": selection}
        family.write_json("scores.json", scores)
        _plot(family.path / "validation.png", rows)
        if scores["forecast"]:
            from impactdyn.ble import plot_reliability

            plot_reliability(scores["forecast"], family.path / "reliability.png")
        family.write_text("validation.html", validation_page(rows, scores, Path(base or EXAMPLE_CASE).name,
                                                             case_options(shots[0], cases[0], base),
                                                             verdict_record(cases[0])))
    return scores


def case_options(shot: DatabaseShot, case: WhippleCase, base: str | Path | None = None) -> dict:
    """Dotted key → value of the settings of ``shot``'s case ``case`` (on the base case file ``base``) that
    differ from the package's defaults, the shot's own (:func:`shot_settings`) left out: the options every
    shot of a validation shares (the base case's, ``--draws``)."""
    own = shot_settings(shot, load_base_case(base)[1])
    return {k: v for k, v in non_defaults(case).items() if k not in own}


def score_validation(rows: list[dict]) -> dict:
    """The simulated and the JSC verdicts scored against the tests by distance band, and McNemar's test; with
    the draws' P(perforation) of each shot (``p_perforation`` of ``n_draws``), the forecasts' Brier score and
    log-loss against JSC 2011's verdict as 0/1 and the database's logistic in d/d_c refitted without these
    shots (:func:`impactdyn.ble.forecast_scores`)."""
    ratio = np.array([r["d_over_limit"] for r in rows], dtype=float)
    truth = np.array([r["test_perforated"] for r in rows], dtype=bool)
    simulated = np.array([r["simulated_perforated"] for r in rows], dtype=bool)
    jsc = np.array([r["jsc_perforated"] for r in rows], dtype=bool)
    test = mcnemar(truth, simulated, jsc)
    return {"n_shots": len(rows),
            "simulated": score_by_distance(ratio, truth, simulated).as_dict(),
            "jsc": score_by_distance(ratio, truth, jsc).as_dict(),
            "mcnemar_simulated_vs_jsc": {"simulated_right_jsc_wrong": test.b, "jsc_right_simulated_wrong": test.c,
                                         "p_exact": test.p_exact, "p_mid": test.p_mid},
            "forecast": _forecast(rows)}


def _forecast(rows: list[dict]) -> dict | None:
    """The forecast scores (:func:`score_validation`); None for rows without the draws' P (older folders)."""
    from impactdyn.ble import database_logistic, forecast_scores

    if not rows or any(r.get("p_perforation") is None for r in rows):
        return None
    baselines = {"jsc": np.array([float(r["jsc_perforated"]) for r in rows])}
    logistic = database_logistic(exclude_lines=[r["line"] for r in rows])
    if logistic is not None:
        baselines["database_logistic"] = logistic(np.array([r["d_over_limit"] for r in rows], dtype=float))
    return forecast_scores([r["p_perforation"] for r in rows], [r["n_draws"] for r in rows],
                           [r["test_perforated"] for r in rows], baselines)


def _run_name(shot: DatabaseShot) -> str:
    return f"line{shot.line}"


def _row(shot: DatabaseShot, case: WhippleCase, summary: dict) -> dict:
    jsc = ble_verdict(case)
    limit = jsc["threshold_cm"]
    wall = summary["wall"]
    called = wall["verdict"] in FAILED_VERDICTS
    jsc_called = jsc["verdict"] == "perforation"
    return {"line": shot.line, "source": shot.source, "shot_id": shot.shot_id, "diameter_cm": shot.diameter_cm,
            "velocity_km_s": shot.velocity_km_s, "obliquity_deg": shot.obliquity_deg,
            "normal_velocity_km_s": shot.velocity_km_s * float(np.cos(np.radians(shot.obliquity_deg))),
            "jsc_limit_cm": limit, "d_over_limit": shot.diameter_cm / limit if limit else None,
            "test_perforated": shot.perforated, "jsc_perforated": jsc_called, "simulated_verdict": wall["verdict"],
            "simulated_perforated": called, "simulated_right": called == shot.perforated,
            # a shot run before the draws stage (a resumed folder) has no P: its forecast is not scored
            "n_draws": summary.get("draws", {}).get("n_draws"),
            "p_perforation": summary.get("draws", {}).get("probability"),
            "jsc_right": jsc_called == shot.perforated, "caution": wall.get("caution") or "",
            "run": f"runs/{_run_name(shot)}"}


def _write_table(folder: FamilyFolder, rows: list[dict]) -> None:
    """``validation.csv`` and ``validation.json``: the finished shots, in selection order."""
    folder.write_csv("validation.csv", VALIDATION_HEADER, [[r[k] for k in VALIDATION_HEADER] for r in rows])
    folder.write_json("validation.json", rows)


def _plot(path: Path, rows: list[dict]) -> None:
    """The shots as d/d_lim against V cos θ: filled circles where the test's wall failed, open squares where
    it did not, green where the simulation called it right and red where not."""
    from impactdyn._plotting import pyplot, save_figure

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 4.5), constrained_layout=True)
    for right, colour, label in ((True, "tab:green", "simulation agrees with the test"),
                                 (False, "tab:red", "simulation disagrees")):
        for perforated, marker in ((True, "o"), (False, "s")):
            pick = [r for r in rows if r["simulated_right"] == right and r["test_perforated"] == perforated
                    and r["d_over_limit"] is not None]
            if pick:
                ax.scatter([r["normal_velocity_km_s"] for r in pick], [r["d_over_limit"] for r in pick],
                           marker=marker, edgecolors=colour, facecolors=colour if perforated else "none",
                           label=f"{label} (test: {TEST_OUTCOMES[perforated]})")
    ax.axhline(1.0, color="k", lw=0.8)
    for edge in (0.95, 1.05, 0.85, 1.15, 0.70, 1.30):
        ax.axhline(edge, color="0.7", lw=0.5, ls=":")
    ax.set_xlabel("normal velocity V cos θ (km/s)")
    ax.set_ylabel("d / d_lim (JSC 2011)")
    ax.legend(fontsize=7, loc="best")
    ax.grid(alpha=0.3)
    save_figure(fig, path)


def _ratio_text(ratio: float | None) -> str:
    return "–" if ratio is None else f"{ratio:.3f}"


def _forecast_table(forecast: dict | None) -> str:
    """The forecasts' scores (:func:`score_validation`) as a table, lower is better; empty without them."""
    if not forecast:
        return ""
    names = {"simulated": "simulation, P = k/N over the fragments' draws", "jsc": "JSC 2011 verdict as 0 or 1",
             "database_logistic": "the test database's logistic in d/d_c (these shots left out)"}
    cells = "".join(f"<tr><td>{html.escape(names.get(k, k))}</td><td>{f['brier']:.3f} ({f['brier_95'][0]:.3f}–"
                    f"{f['brier_95'][1]:.3f})</td><td>{f['log_loss']:.3f} ({f['log_loss_95'][0]:.3f}–"
                    f"{f['log_loss_95'][1]:.3f})</td></tr>" for k, f in forecast.items())
    return ("<h2>The verdicts as forecasts (lower is better; 95 % bootstrap intervals)</h2><table><tr><th>forecast"
            "</th><th>Brier score</th><th>log-loss (P clipped to [1/2N, 1 − 1/2N])</th></tr>" + cells + "</table>"
            '<img src="reliability.png" alt="reliability diagram: observed frequency of perforation against the '
            'forecast P">')


def selection_statement(selection: dict) -> str:
    """The shots a validation ran (its ``selection`` record), in words: a shipped rule by its name, whether it
    is fixed and its description; another rule by its name and hash; or the lines given."""
    if "lines" in selection:
        lines = selection["lines"]
        return (f"lines {', '.join(map(str, lines))} of the test database "
                f"({len(lines)} shot{'s' if len(lines) != 1 else ''})")
    name, fixed = selection["rule"], selection.get("fixed")
    state = f"fixed on {fixed}" if fixed else "not fixed: these scores cannot judge a change"
    rule = shipped_rule(name, selection["sha256"])
    if rule is None:
        return f"the shots of rule {name} ({state}; sha256 {selection['sha256'][:12]}…)"
    return f"the shots of the shipped rule {name} ({state}): {rule.description}"


def option_lines(options: dict) -> list[str]:
    """The case's settings that differ from the package's defaults (:func:`impactdyn._config.non_defaults`),
    each as a case file writes it: ``[shield] failed_fragments = "grady"``."""
    return [f"[{key.rpartition('.')[0]}] {key.rpartition('.')[2]} = {json.dumps(value)}"
            for key, value in options.items()]


def _options_html(options: dict) -> str:
    if not options:
        return "none: the shots' numerics are the package's defaults."
    return "<ul>" + "".join(f"<li><code>{html.escape(line)}</code></li>" for line in option_lines(options)) + "</ul>"


def band_label(band: str) -> str:
    """A band of |d/d_lim − 1| (:data:`impactdyn.ble.DISTANCE_BANDS`) as people read it: "< 5 %",
    "5–15 %", "≥ 30 %"; the overall score's "all"."""
    if band not in DISTANCE_BANDS:
        return "all"
    low, high = (100 * edge for edge in DISTANCE_BANDS[band])
    if low == 0:
        return f"< {high:g} %"
    return f"≥ {low:g} %" if math.isinf(high) else f"{low:g}–{high:g} %"


def _called(perforated: bool) -> str:
    """The JSC equation's call in the verdicts' words."""
    return "perforation" if perforated else "no perforation"


def validation_page(rows: list[dict], scores: dict, base: str, options: dict, record: str) -> str:
    """``validation.html``: the selection (:func:`selection_statement`) and the case, the shots' numerics
    taken from the case file ``base``, with its ``options`` that differ from the package's defaults
    (:func:`option_lines`) and what stands behind the simulated verdict with them (``record``:
    :func:`impactdyn.whipple._report.verdict_record`); the scores by band beside the equation's, McNemar's
    test, every shot; each outcome and verdict in the report's words."""
    def interval(p: dict) -> str:
        if p["of"] == 0:
            return "–"
        return f"{p['count']}/{p['of']} = {100 * p['rate']:.0f} % ({100 * p['low']:.0f}–{100 * p['high']:.0f} %)"

    band_rows = []
    for who, name in (("simulated", "simulation"), ("jsc", "JSC 2011")):
        for b in [*scores[who]["bands"], scores[who]["overall"]]:
            band_rows.append(f"<tr><td>{name}</td><td>{html.escape(band_label(b['band']))}</td>"
                             f"<td>{interval(b['accuracy'])}</td><td>{interval(b['false_safe'])}</td>"
                             f"<td>{interval(b['false_alarm'])}</td></tr>")
    m = scores["mcnemar_simulated_vs_jsc"]
    shot_rows = "".join(
        f"<tr><td>{r['line']}</td><td>{html.escape(str(r['source']))} {html.escape(str(r['shot_id']))}</td>"
        f"<td>{r['diameter_cm']:.4g}</td><td>{r['velocity_km_s']:.3g}</td><td>{r['obliquity_deg']:g}</td>"
        f"<td>{_ratio_text(r['d_over_limit'])}</td><td>{TEST_OUTCOMES[r['test_perforated']]}</td>"
        f"<td>{_called(r['jsc_perforated'])}</td><td>{html.escape(r['simulated_verdict'])}</td>"
        f"<td>{'yes' if r['simulated_right'] else 'no'}</td><td><a href=\"{r['run']}/report.html\">run</a></td></tr>"
        for r in rows)
    return f"""<!doctype html><html><head><meta charset="utf-8"><title>Validation on test shots</title>
<style>body{{font-family:sans-serif;max-width:70em;margin:2em auto}}
td,th{{padding:2px 8px;border-bottom:1px solid #ddd}}.bands td{{white-space:nowrap}}
.caution{{border-left:4px solid #c77700;background:#fff6e5;padding:0.5em 1em}}</style></head>
<body><h1>Validation on {scores['n_shots']} test shots</h1>
<p><strong>Selection:</strong> {html.escape(selection_statement(scores['selection']))}</p>
<p><strong>Case:</strong> each test shot's projectile, bumper and wall on the numerics of
<code>{html.escape(base)}</code>; its settings that differ from the package's defaults: {_options_html(options)}</p>
<p class="caution"><strong>What stands behind the simulated verdict:</strong> {html.escape(record)}</p>
<h2>Scores by distance from the equation's limit, |d/d_lim − 1| (95 % Wilson intervals)</h2>
<table class="bands"><tr><th>verdict of</th><th>band</th><th>right</th><th>false-safe (no perforation called, of the tests with
perforation or detached spall)</th><th>false alarm (perforation called, of the tests with no perforation)</th></tr>
{''.join(band_rows)}</table>
<p>Exact McNemar test, simulation against the equation on the same shots: simulation right and equation wrong on
{m['simulated_right_jsc_wrong']}, the reverse on {m['jsc_right_simulated_wrong']}; p = {m['p_exact']:.3g}
(mid-p {m['p_mid']:.3g}).</p>
{_forecast_table(scores.get("forecast"))}
<img src="validation.png" alt="shots as d/d_lim against V cos θ">
<h2>Shots</h2><table><tr><th>line</th><th>shot</th><th>d (cm)</th><th>V (km/s)</th><th>θ (°)</th><th>d/d_lim</th>
<th>test</th><th>JSC</th><th>simulated</th><th>simulation right</th><th></th></tr>{shot_rows}</table></body></html>
"""
