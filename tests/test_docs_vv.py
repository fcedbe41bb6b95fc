"""The verification-and-validation manual and the performance page keep their shape.

* one V&V page per kind of check, each in the manual's table of contents;
* ``benchmarks/BENCHMARKS.md`` holds current speed measurements only: at most 800 lines, no dated
  or superseded sections (the history is git's);
* a citation of a BENCHMARKS.md section by its title, in the hand-written docs, names a section
  that exists;
* MathJax is served with the site and smart quotes are off (they made "--vary" read "–vary");
* the equations' scores that the docs include are generated from the package;
* the pages that lead to the simulated verdict open with its limit, generated from the package's record;
* the validation shots' table is generated from the packaged database, every cell filled.
"""

import re
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
BENCHMARKS = ROOT / "benchmarks" / "BENCHMARKS.md"
KINDS = ("analytic", "cross-code", "convergence", "test-shots")
GENERATED = ("_build/", "vv/_generated/", "api/", "auto_tutorials/", "user-guide/case-files.md", "user-guide/cli.md")


@pytest.mark.parametrize("kind", KINDS)
def test_each_kind_of_check_has_a_page_in_the_manual(kind):
    assert (DOCS / "vv" / f"{kind}.md").is_file()
    index = (DOCS / "verification-and-validation.md").read_text(encoding="utf-8")
    toctree = index.split("```{toctree}", 1)[1].split("```", 1)[0]
    assert f"vv/{kind}" in toctree.split()


def test_benchmarks_is_current_and_short():
    text = BENCHMARKS.read_text(encoding="utf-8")
    assert len(text.splitlines()) <= 800
    headings = [line for line in text.splitlines() if line.startswith("#")]
    for heading in headings:
        assert not re.search(r"\b20\d\d-\d\d-\d\d\b", heading), heading
        assert not re.search(r"superseded|correction|issue \d|session \d", heading, re.I), heading
    assert not re.search(r"\bsuperseded\b", text, re.I)
    assert "## Wall stage: a holed wall stops early" in headings


def test_docs_cite_benchmark_sections_that_exist():
    titles = {line.lstrip("#").strip() for line in BENCHMARKS.read_text(encoding="utf-8").splitlines()
              if line.startswith("#")}
    cited = []
    for page in DOCS.rglob("*.md"):
        rel = page.relative_to(DOCS).as_posix()
        if rel.startswith(GENERATED):  # written from the docstrings at build time
            continue
        for m in re.finditer(r"BENCHMARKS\.md`?,\s*\"([^\"]+)\"", page.read_text(encoding="utf-8")):
            cited.append((page.relative_to(ROOT), m.group(1)))
    for page, title in cited:
        assert title in titles, f"{page} cites a BENCHMARKS.md section that does not exist: {title!r}"


def test_mathjax_is_served_with_the_site_and_smart_quotes_are_off():
    conf = {"__file__": str(DOCS / "conf.py")}
    exec(compile((DOCS / "conf.py").read_text(encoding="utf-8"), "conf.py", "exec"), conf)
    path = conf["mathjax_path"]
    assert not path.startswith(("http:", "https:", "//"))
    assert (DOCS / "_static" / path).is_file()
    assert conf["smartquotes"] is False


def _impactdyn_vv():
    sys.path.insert(0, str(DOCS / "_ext"))
    try:
        import impactdyn_vv
    finally:
        sys.path.remove(str(DOCS / "_ext"))
    return impactdyn_vv


def test_the_included_scores_are_the_packages():
    from impactdyn import ble

    table = _impactdyn_vv().ble_scores_table()
    s = ble.validate("jsc2011").overall
    assert f"| jsc2011 | all shots | {s.shots} | {100 * s.correct / s.shots:.1f} % |" in table
    for page in ("ble.md", "vv/test-shots.md"):
        assert "_generated/ble-scores.md" in (DOCS / page).read_text(encoding="utf-8")


@pytest.mark.parametrize("page", ["verification-and-validation.md", "getting-started.md", "whipple.md"])
def test_the_pages_before_the_verdict_open_with_its_limit(page):
    text = (DOCS / page).read_text(encoding="utf-8")
    included = text.find("```{include} vv/_generated/limit.md")
    assert included >= 0, f"{page} does not include the limit"
    assert "\n## " not in text[:included] and "{toctree}" not in text[:included], f"{page}: the limit is not at its top"


def test_the_limit_paragraph_is_the_records():
    from impactdyn.whipple import limit_statement

    assert limit_statement() in _impactdyn_vv().limit_paragraph()


def test_the_validation_shots_table_fills_every_cell_from_the_database():
    from impactdyn.whipple import validation_record

    table = _impactdyn_vv().validation_shots_table()
    sets = validation_record().sets
    rows = [line for line in table.splitlines() if line.startswith("| ") and not line.startswith(("| ---", "| line "))]
    assert len(rows) == sum(s.shots for s in sets)
    assert all(f"(rule {s.name})" in table for s in sets)  # one table per set, named
    for row in rows:
        cells = [c.strip() for c in row.strip("|").split("|")]
        assert len(cells) == 8 and all(cells), row
        source, _, shot_id = cells[1].partition(", ")
        assert source and shot_id, row  # the report and the shot, never a shot ID alone
        assert len(cells[6].split(" / ")) == 3, row
    assert "**bold**" in table  # the legend says what bold marks
    assert "_generated/validation-shots.md" in (DOCS / "vv" / "test-shots.md").read_text(encoding="utf-8")
