"""Each shot's stage times, steps and verdict in two ``whipple validate`` folders, side by side.

The folders are runs of the same selection at two commits on one machine (a baseline and a
change); the table is Markdown, one row per shot, and a last row with the sums and each
folder's total wall-clock time when the command's ``/usr/bin/time -v`` log lies beside it
(``FOLDER.log``).

    python benchmarks/validation_times.py runs/before/set-2 runs/after/set-2
"""

from __future__ import annotations

import argparse
import json
import re
from pathlib import Path


def shots(folder: Path) -> dict[str, dict]:
    """{run name: summary} of the shots of a validation folder."""
    return {p.parent.name: json.loads(p.read_text()) for p in sorted((folder / "runs").glob("*/summary.json"))}


def elapsed_s(folder: Path) -> float | None:
    """The command's wall-clock time from ``FOLDER.log`` (GNU time's "Elapsed" line), if there."""
    log = folder.with_name(folder.name + ".log")
    found = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): ([\d:.]+)", log.read_text()) \
        if log.is_file() else None
    if found is None:
        return None
    seconds = 0.0
    for part in found.group(1).split(":"):
        seconds = 60.0 * seconds + float(part)
    return seconds


def row(summary: dict) -> tuple[float, float, int, str, str]:
    """(shield s, wall s, wall steps, how the wall run ended, verdict) of one shot."""
    t, wall = summary["timings_s"], summary["wall"]
    return t["shield"], t["wall"], wall.get("steps", 0), wall.get("ended_by", "?"), wall["verdict"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("before", type=Path)
    parser.add_argument("after", type=Path)
    args = parser.parse_args()
    before, after = shots(args.before), shots(args.after)
    print("| shot | shield s, before / after | wall s, before / after | wall steps, before / after "
          "| ended by, before / after | verdict, before / after |")
    print("| --- | --- | --- | --- | --- | --- |")
    sums = [0.0] * 4
    for name in sorted(before.keys() | after.keys(), key=lambda n: int(re.sub(r"\D", "", n) or 0)):
        b, a = before.get(name), after.get(name)
        rb = row(b) if b else (float("nan"),) * 3 + ("–", "–")
        ra = row(a) if a else (float("nan"),) * 3 + ("–", "–")
        print(f"| {name} | {rb[0]:.0f} / {ra[0]:.0f} | {rb[1]:.0f} / {ra[1]:.0f} | {rb[2]} / {ra[2]} "
              f"| {rb[3]} / {ra[3]} | {rb[4]} / {ra[4]} |")
        for i, v in enumerate((rb[0], ra[0], rb[1], ra[1])):
            sums[i] += v if v == v else 0.0
    total = [elapsed_s(args.before), elapsed_s(args.after)]
    total_text = " / ".join(f"{t / 60:.1f} min" if t is not None else "?" for t in total)
    print(f"| sum (command's wall clock {total_text}) | {sums[0]:.0f} / {sums[1]:.0f} | {sums[2]:.0f} / {sums[3]:.0f} "
          "| | | |")


if __name__ == "__main__":
    main()
