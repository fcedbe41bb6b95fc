"""Sphinx extension: the verification-and-validation text that the package computes in seconds.

At ``builder-inited`` it writes into ``vv/_generated/``:

* ``ble-scores.md``: the JSC equations scored on the packaged test database
  (:func:`impactdyn.ble.validate`, about a second), the table that ``impactdyn ble validate`` prints;
* ``limit.md``: the limit of the simulated verdict (:func:`impactdyn.whipple.limit_statement`), with the
  figures of the package's validation record, which the pages that lead to the verdict open with;
* ``validation-shots.md``: the shots of the recorded validation sets (each set's rule applied to the
  packaged database), each with the test's outcome and the JSC 2011 verdict as ``whipple validate``
  computes it.

The pages include them (``{include}``), so the numbers follow the code, the database and the record.
The folder is a build output: ignored by git (``docs/vv/.gitignore``) and left out of the page
sources (``exclude_patterns``).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from impactdyn import ble, whipple

EQUATIONS = ("jsc1993", "jsc2011")


def _pct(part: int, whole: int) -> str:
    return f"{100.0 * part / whole:.1f} %" if whole else "–"


def _row(equation: str, group: str, s: Any) -> str:
    return (f"| {equation} | {group} | {s.shots} | {_pct(s.correct, s.shots)} | "
            f"{_pct(s.false_safe, s.perforated)} ({s.false_safe}/{s.perforated}) | "
            f"{_pct(s.false_alarm, s.shots - s.perforated)} ({s.false_alarm}/{s.shots - s.perforated}) |")


def ble_scores_table() -> str:
    """The equations' scores on every shot, by regime, in Markdown."""
    lines = ["| equation | shots | n | accuracy | false-safe | false-alarm |",
             "| --- | --- | --- | --- | --- | --- |"]
    for name in EQUATIONS:
        v = ble.validate(name)
        lines.append(_row(name, "all shots", v.overall))
        if v.with_fixed_point is not None and v.with_fixed_point.shots != v.overall.shots:
            lines.append(_row(name, "with a fixed point", v.with_fixed_point))
        for regime, s in v.by_regime.items():
            lines.append(_row(name, f"regime: {regime}", s))
    return "\n".join(lines) + "\n"


def limit_paragraph() -> str:
    """The limit of the simulated verdict under the README's heading for it, for the top of a page: a warning
    box, as the report puts its caution."""
    return ("```{admonition} The limit: read this before the simulated verdict\n:class: warning\n\n"
            f"{whipple.limit_statement()}\n```\n")


def _outcome(perforated: bool) -> str:
    return "P" if perforated else "NP"


def validation_shots_table() -> str:
    """The recorded validation sets' shots in Markdown, a compact table per set, from the packaged database:
    every column filled, the JSC verdict in bold where it is not the test's outcome, and a legend."""
    db = ble.read_database()
    lines = []
    for entry in whipple.validation_record().sets:
        # the caption names the rule without backticks: a backtick ends a fence's info string
        lines += [f"```{{table}} Validation set {entry.name.removeprefix('set-')} (rule {entry.name})",
                  ":class: compact", "",
                  "| line | source, shot | test | d (cm) | V (km/s) | θ (°) | t_b / t_w / S (cm) | JSC 2011 (d_c, cm) |",
                  "| --- | --- | --- | --- | --- | --- | --- | --- |"]
        for i in whipple.select_shots(whipple.load_rule(entry.name), db):
            shot = whipple.database_shot(int(db.line[i]), db)
            jsc = whipple.ble_verdict(whipple.WhippleCase.model_validate(whipple.database_shot_case(shot)))
            called = jsc["verdict"] == "perforation"
            verdict = _outcome(called) if called == shot.perforated else f"**{_outcome(called)}**"
            lines.append(
                f"| {shot.line} | {shot.source}, {shot.shot_id} | {_outcome(shot.perforated)} | "
                f"{shot.diameter_cm:.3f} | {shot.velocity_km_s:.2f} | {shot.obliquity_deg:g} | "
                f"{shot.bumper_thickness_cm:g} / {shot.wall_thickness_cm:g} / {shot.spacing_cm:g} | "
                f"{verdict} ({jsc['threshold_cm']:.3f}) |")
        lines += ["```", ""]
    legend = ("P: the rear wall perforated or spalled; NP: it held. t_b, t_w: bumper and wall thickness; "
              "S: stand-off. The JSC 2011 column gives the equation's verdict and the diameter above which "
              "it calls perforation (its critical diameter d_c at the shot's speed and obliquity), with the "
              "projectile density of the library material that models the shot's alloy, as `whipple validate` "
              "scores it; **bold**: the equation's verdict is not the test's outcome.")
    return "\n".join(lines) + legend + "\n"


def generated_texts() -> dict[str, str]:
    return {"ble-scores.md": ble_scores_table(), "limit.md": limit_paragraph(),
            "validation-shots.md": validation_shots_table()}


def write_tables(app: Any) -> None:
    out = Path(app.srcdir) / "vv" / "_generated"
    out.mkdir(parents=True, exist_ok=True)
    for name, text in generated_texts().items():
        target = out / name
        if not target.exists() or target.read_text(encoding="utf-8") != text:  # unchanged: no rebuild
            target.write_text(text, encoding="utf-8")


def setup(app: Any) -> dict[str, Any]:
    app.connect("builder-inited", write_tables)
    return {"parallel_read_safe": True}
