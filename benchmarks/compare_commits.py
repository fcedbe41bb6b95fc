"""Time one hot path at two commits in one run, and print their ratio.

Each commit is checked out into a temporary git worktree (``git worktree add --detach``,
removed afterwards); ``.`` stands for the working tree as it is. Every timing runs in a
fresh subprocess whose PYTHONPATH is that tree's ``src``, so the two commits' code never
share an interpreter or a numba cache; the rounds alternate between the commits (and
swap which goes first), so a machine that slows down mid-run slows both alike. Each
subprocess makes one untimed call first (numba compiles or loads its cache there), then
times ``--inner`` calls; the reported figure is the median over ``--rounds`` rounds of
each subprocess's median, in CPU time of the process (what the code costs: on a shared
machine other jobs stretch the wall-clock time of whichever side they overlap) and in
wall-clock time beside it.

A timing may name a reference (the beam's: the plain SciPy LSODA port of
``bench_beam.baseline``), timed in the same rounds with the second commit's code, and
each commit's speed-up over it is printed too.

    python benchmarks/compare_commits.py BASE HEAD [--bench beam] [--rounds 5] [--inner 3]

To add a hot path, register a :class:`Timing` in ``TIMINGS``: ``setup(root)`` runs in
the subprocess (with the commit's ``impactdyn`` importable, ``root`` its checkout) and
returns the function to time.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from contextlib import ExitStack, contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from _machine import describe_machine

HERE = Path(__file__).resolve().parent
REPO = HERE.parent


@dataclass(frozen=True)
class Timing:
    """A named hot path. ``setup`` imports what it needs itself: only the subprocesses may
    import ``impactdyn``, each from its own commit's tree."""

    what: str
    setup: Callable[[Path], Callable[[], object]]
    reference: str | None = None
    """Name of another timing, run with the second commit's code, to print speed-ups against."""


def _beam_sample(root: Path):
    from impactdyn.beam import load_case, simulate

    case = load_case(root / "examples" / "beam" / "impactb_sample.toml")
    return lambda: simulate(case)


def _beam_lsoda(root: Path):
    from bench_beam import baseline  # this checkout's port, on the commit's model coefficients
    from impactdyn.beam import load_case

    case = load_case(root / "examples" / "beam" / "impactb_sample.toml")
    return lambda: baseline(case)


def _wall_report_mesh(root: Path):
    """The Johnson–Cook wall with the commit's default failure model on the report's 50 × 4 × 100 mesh
    (``mesh = "report"`` where the commit has that key; before it, the only mesh) under
    bench_wall's synthetic 7-km/s-like load, 10 µs from the first arrival: the element pass and
    the material update, the wall's hot path."""
    from bench_wall import report_wall, synthetic_deposition  # this checkout's copies
    from impactdyn import wall

    grid = report_wall()
    deposition = synthetic_deposition(grid)
    settings = dict(material_model="johnson_cook", end_time_us=float(deposition.time.min()) + 10.0,
                    output_interval_us=None)
    try:
        options = wall.WallOptions(mesh="report", **settings)
    except (TypeError, ValueError):  # a commit before the graded mesh (its options take no "mesh")
        options = wall.WallOptions(**settings)
    return lambda: wall.run_wall(grid, deposition, "al6061-t6", options)


def _sph_sphere_on_plate(root: Path):
    """The SPH shield stage with the commit's default failure model: a 0.3175-cm Al sphere on a
    0.0635-cm Al bumper at 6 km/s, Δ = d/10 (1,524 particles), 2 µs: the pair loop, the predictor
    and the corrector with its failure update, the shield's hot path."""
    from impactdyn import shield

    problem = shield.sphere_on_plate("al6061-t6", "al6061-t6", 0.3175, 6.0, 0.0, 0.0635, 0.03175)
    return lambda: shield.run(problem, 2.0)


def _fragment_rate(root: Path):
    """The own-size stretching rate of a failed body (``shield.own_size_strain_rates``): 20³ = 8,000
    particles at Δ = 0.008 cm (d/40 of the gate's sphere), stretching at 0.3 µs⁻¹ with a 5 % jitter of the
    velocity, Grady's size of 6061-T6 (about 0.1 cm: fits over 7 Δ, on the first coarser point grid), the radius
    and size iterated to the 12-pass cap (the jitter keeps some radii moving by more than 1 %); runs once a
    shot with the fragments of failed material, after the SPH."""
    from functools import partial

    import numpy as np
    from impactdyn import shield
    from impactdyn import materials
    from impactdyn.materials import AL_6061_T6

    spacing = 0.008
    g = (np.arange(20) + 0.5) * spacing
    x = np.stack(np.meshgrid(g, g, g, indexing="ij"), axis=-1).reshape(-1, 3)
    velocity = 0.3 * x * (1.0 + 0.05 * np.random.default_rng(1).standard_normal(x.shape))
    # older commits (this script runs against them) kept K_Ic in a table by name, newer ones in the record
    toughness = (AL_6061_T6.fracture_toughness.K_Ic if hasattr(AL_6061_T6, "fracture_toughness")
                 else materials.FRACTURE_TOUGHNESS["al6061-t6"])
    size_of_rate = partial(shield.grady_fragment_size, toughness, AL_6061_T6.rho0,
                           AL_6061_T6.young_modulus)
    return lambda: shield.own_size_strain_rates(x, velocity, np.full(len(x), spacing), size_of_rate)


TIMINGS = {
    "fragment-rate": Timing("own-size stretching rate, 8,000 failed particles (own_size_strain_rates)",
                            _fragment_rate),
    "sph": Timing("SPH sphere on plate, 1,524 particles, 6 km/s, 2 us (shield.run)", _sph_sphere_on_plate),
    "wall": Timing("Johnson-Cook wall, report mesh, synthetic load, 10 us (run_wall)", _wall_report_mesh),
    "beam": Timing("IMPACTB sample, simulate() in process", _beam_sample, reference="beam-lsoda"),
    "beam-lsoda": Timing("IMPACTB sample, plain SciPy LSODA port (bench_beam.baseline)", _beam_lsoda),
}


CLOCKS = {"cpu": time.process_time, "wall": time.perf_counter}


def worker(name: str, root: Path, inner: int) -> None:
    """Subprocess side: time ``inner`` calls after a warm one; print the medians per clock as JSON."""
    import impactdyn

    loaded = Path(impactdyn.__file__).resolve()
    if root.resolve() not in loaded.parents:
        sys.exit(f"impactdyn loaded from {loaded}, not from {root}: check PYTHONPATH")
    fn = TIMINGS[name].setup(root)
    fn()
    times: dict[str, list[float]] = {clock: [] for clock in CLOCKS}
    for _ in range(inner):
        start = {clock: read() for clock, read in CLOCKS.items()}
        fn()
        for clock, read in CLOCKS.items():
            times[clock].append(read() - start[clock])
    print(json.dumps({clock: statistics.median(ts) for clock, ts in times.items()}))


def run_worker(name: str, root: Path, inner: int) -> dict[str, float]:
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(root / "src"), str(HERE)]))
    out = subprocess.run([sys.executable, str(Path(__file__).resolve()), "--worker", name, "--root", str(root),
                          "--inner", str(inner)], env=env, capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(f"{name} at {root} failed:\n{out.stderr}")
    return json.loads(out.stdout.strip().splitlines()[-1])


@contextmanager
def checkout(rev: str):
    """A tree holding ``rev``: the working tree itself for ".", else a temporary worktree."""
    if rev == ".":
        yield REPO
        return
    with tempfile.TemporaryDirectory(prefix="impactdyn-compare-") as tmp:
        path = Path(tmp) / "tree"
        subprocess.run(["git", "-C", str(REPO), "worktree", "add", "--detach", "--quiet", str(path), rev], check=True)
        try:
            yield path
        finally:
            subprocess.run(["git", "-C", str(REPO), "worktree", "remove", "--force", str(path)], check=True)


def describe_rev(rev: str) -> str:
    if rev == ".":
        return "working tree"
    sha = subprocess.run(["git", "-C", str(REPO), "rev-parse", "--short", rev], capture_output=True, text=True,
                         check=True).stdout.strip()
    return rev if rev == sha else f"{rev} ({sha})"


def compare(base: str, head: str, bench: str, rounds: int, inner: int) -> None:
    timing = TIMINGS[bench]
    with ExitStack() as stack:
        trees = {base: stack.enter_context(checkout(base)), head: stack.enter_context(checkout(head))}
        runs = [(base, bench), (head, bench)] + ([(head, timing.reference)] if timing.reference else [])
        for rev, name in runs:  # compile and fill each tree's numba cache outside the rounds
            run_worker(name, trees[rev], 1)
        samples: dict[tuple[str, str], list[dict[str, float]]] = {run: [] for run in runs}
        for r in range(rounds):
            for rev, name in (runs if r % 2 == 0 else runs[1::-1] + runs[2:]):
                samples[rev, name].append(run_worker(name, trees[rev], inner))
    print(f"machine: {describe_machine()}")
    print(f"{timing.what}: median of {rounds} alternating rounds, each the median of {inner} warm calls")
    for clock in CLOCKS:
        med = {run: statistics.median(s[clock] for s in ss) for run, ss in samples.items()}
        print(f"{clock} time:")
        for rev, name in runs[:2]:
            line = f"  {describe_rev(rev):>24}: {med[rev, name]:.4f} s"
            if timing.reference:
                line += f"  ({med[head, timing.reference] / med[rev, name]:.1f}x {timing.reference})"
            print(line)
        if timing.reference:
            print(f"  {timing.reference:>24}: {med[head, timing.reference]:.4f} s  ({TIMINGS[timing.reference].what})")
        print(f"  {describe_rev(head)} is {med[base, bench] / med[head, bench]:.2f}x as fast as {describe_rev(base)}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("base", nargs="?", help='a commit, or "." for the working tree')
    ap.add_argument("head", nargs="?", help='a commit, or "." for the working tree')
    ap.add_argument("--bench", choices=sorted(TIMINGS), default="beam", help="the timing to run (TIMINGS)")
    ap.add_argument("--rounds", type=int, default=5, help="alternating rounds, one subprocess per commit each")
    ap.add_argument("--inner", type=int, default=3, help="timed calls per subprocess, after a warm one")
    ap.add_argument("--worker", help=argparse.SUPPRESS)
    ap.add_argument("--root", type=Path, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker:
        worker(args.worker, args.root, args.inner)
    elif args.base and args.head and args.base != args.head:
        compare(args.base, args.head, args.bench, args.rounds, args.inner)
    else:
        ap.error("give two different commits, BASE and HEAD")


if __name__ == "__main__":
    main()
