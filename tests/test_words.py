"""The product speaks to its users: no project-internal words in ``src/``, the README or ``docs/``.

"issue 31", "session 16", "seed 000" and "DESIGN §9" mean something in the project's notes and
commits, nothing to a user; a docstring that points outside the repository (``../shared/…``) points
nowhere for them.  Say what was meant instead: the reason, the docs or theory page, the
benchmark's section name.  The lab notebook (``benchmarks/``, ``verification/``, ``validation/``,
``studies/``) and the generated site (``docs/_build``) are not checked.
"""

from __future__ import annotations

import pathlib
import re

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]

#: What may not come back, each with what to write instead.
INTERNAL = {
    r"\bissues? #?\d+": "the reason, or nothing",
    r"\bsessions? \d+": "what was found, or nothing",
    r"\bseed 0\d\d\b": "the case or benchmark section by name",
    r"\bDESIGN ?§": "the docs/theory page",
    r"\.\./shared/|/work/shared\b": "a page inside the repository",
    r"\bthis week\b": "nothing (git has the date)",
}
PATTERN = re.compile("|".join(f"(?:{p})" for p in INTERNAL), re.IGNORECASE)
SUFFIXES = {".py", ".md", ".rst", ".toml", ".txt", ".css", ".html", ".cfg", ".ini", ".yaml", ".yml"}


def _checked_files() -> list[pathlib.Path]:
    files = [ROOT / "README.md"]
    for top in ("src", "docs"):
        for path in sorted((ROOT / top).rglob("*")):
            rel = path.relative_to(ROOT)
            if path.is_file() and path.suffix in SUFFIXES and "_build" not in rel.parts \
                    and "__pycache__" not in rel.parts:
                files.append(path)
    return files


def _hits(text: str) -> list[tuple[int, str]]:
    return [(n, m.group(0)) for n, line in enumerate(text.splitlines(), 1) for m in PATTERN.finditer(line)]


def test_checked_files_are_found():
    files = _checked_files()
    assert ROOT / "README.md" in files
    assert any(p.suffix == ".py" and "src" in p.parts for p in files)
    assert any(p.suffix == ".md" and "docs" in p.parts for p in files)


def test_no_internal_words_in_the_product():
    bad = [f"{path.relative_to(ROOT)}:{n}: {word!r}"
           for path in _checked_files() for n, word in _hits(path.read_text(encoding="utf-8"))]
    assert bad == [], "project-internal words (say what they meant for a user instead):\n" + "\n".join(bad)


@pytest.mark.parametrize("text", [
    "as decided in issue 31", "(issues 2, 14)", "Issue #7", "found in session 16", "Session 3's run",
    "the seed 000 run", "see DESIGN §9", "DESIGN§ 4", "../shared/DESIGN.md", "this week's change",
])
def test_the_pattern_catches(text):
    assert _hits(text)


@pytest.mark.parametrize("text", [
    "NASA/TM-2009-214785 §4", "Hairer & Wanner §IV.7", "seed = 12345", "the issue of scale",
    "a session of the CLI", "shared memory", "the design of the shield", "seed 1",
])
def test_the_pattern_spares(text):
    assert _hits(text) == []
