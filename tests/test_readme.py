"""The README's Python blocks run as written (from the repository root)."""

import os
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_readme_python_blocks(capsys):
    text = (ROOT / "README.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert blocks
    cwd = os.getcwd()
    os.chdir(ROOT)
    try:
        for code in blocks:
            exec(compile(code, "README.md", "exec"), {})
    finally:
        os.chdir(cwd)
    out = capsys.readouterr().out
    assert "first impact at 0.78108" in out
    assert "7a: d = 0.575 cm, JSC d_c = 0.519 cm -> perforation" in out  # jsc2011, the default (issue 12)
    # the debris example's whole cloud lands on the wall: deposited = incoming momentum
    m = re.search(r"(\d+) particles arrived; momentum deposited ([\d.]+) g·cm/µs of ([\d.]+)", out)
    assert m and int(m[1]) > 100 and m[2] == m[3]
