"""Sphinx extension: the verification-and-validation tables that the package computes in seconds.

At ``builder-inited`` it writes ``vv/_generated/ble-scores.md``: the JSC equations scored on the
packaged test database (:func:`impactdyn.ble.validate`, about a second), the table that
``impactdyn ble validate`` prints.  The V&V manual and the ballistic-limit page include it
(``{include}``), so the numbers follow the code and the database.  The folder is a build output:
ignored by git (``docs/vv/.gitignore``) and left out of the page sources (``exclude_patterns``).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from impactdyn import ble

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


def write_tables(app: Any) -> None:
    out = Path(app.srcdir) / "vv" / "_generated"
    out.mkdir(parents=True, exist_ok=True)
    target = out / "ble-scores.md"
    text = ble_scores_table()
    if not target.exists() or target.read_text(encoding="utf-8") != text:  # unchanged: no rebuild
        target.write_text(text, encoding="utf-8")


def setup(app: Any) -> dict[str, Any]:
    app.connect("builder-inited", write_tables)
    return {"parallel_read_safe": True}
