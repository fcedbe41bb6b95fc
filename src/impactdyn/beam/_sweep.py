"""Parameter sweeps of beam cases, in parallel on local cores or on Dask."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from impactdyn._config import load_toml, parse_range
from impactdyn._errors import InputError
from impactdyn._family import FamilyFolder, run_members
from impactdyn._sweep import case_variants

SWEEP_HEADER = ["index", "value", "n_impacts", "first_impact_t_s", "v_approach_m_s", "v_separation_m_s",
                "restitution", "peak_force_N", "final_theta_rad", "final_theta_dot_rad_s", "wall_time_s"]


def parse_vary(spec: str) -> tuple[str, np.ndarray]:
    """``KEY=START:STOP:N`` → (dotted key, N values from START to STOP inclusive)."""
    example = "torque.amplitude_N_m=-0.3:-0.1:5"
    key, sep, rng = spec.partition("=")
    if not sep:
        raise InputError(f"--vary {spec!r}: expected KEY=START:STOP:N, e.g. {example}")
    return key.strip(), np.array(parse_range(f"--vary {key.strip()}=", rng, example))


def sweep_cases(case_path: str | Path, key: str, values: np.ndarray) -> list:
    """Validate every case of the sweep before any work (the key must exist in the schema)."""
    from impactdyn.beam._case import BeamCase

    cast = (lambda v: int(round(v))) if key.endswith("n_modes") else float
    return case_variants(BeamCase, load_toml(case_path), [{key: cast(v)} for v in values], source=str(case_path))


def _run_one(case) -> dict:
    from impactdyn.beam._simulate import simulate

    return simulate(case).summary()


def _row(index: int, value: float, s: dict) -> list:
    first = s["impacts"][0] if s["impacts"] else None
    pick = lambda k: "" if first is None or first[k] is None else first[k]
    return [index, value, s["n_impacts"], pick("t_start"), pick("v_approach"), pick("v_separation"),
            pick("restitution"), pick("peak_force"), s["final_state"]["theta"], s["final_state"]["theta_dot"],
            s["wall_time_s"]]


def run_sweep(case_path, vary: str, outdir, force=False, resume: bool = False, workers: int | None = None,
              dask_address: str | None = None, progress=None) -> Path:
    """Run the sweep and write ``sweep.csv``, ``sweep.png`` and ``cases/NNN/summary.json``.

    ``dask_address``: ``"local"`` starts a LocalCluster, any other value connects to
    an existing scheduler; ``None`` uses a local process pool.  The folder is a family folder
    (:mod:`impactdyn._family`): ``sweep.csv`` is rewritten after each case, so an interrupted
    sweep leaves it with the cases it finished, and ``resume`` runs only the cases it lacks.
    """
    key, values = parse_vary(vary)
    cases = sweep_cases(case_path, key, values)
    settings = {"case": cases[0].model_dump(mode="json"), "vary": key, "values": [float(v) for v in values]}
    rows: list = [None] * len(cases)
    with FamilyFolder(outdir, "beam sweep", settings, table="sweep.csv", member="case", force=force,
                      resume=resume) as family:
        summaries = [family.path / "cases" / f"{i:03d}" / "summary.json" for i in range(len(cases))]

        def record(i: int, summary: dict) -> None:
            if not summaries[i].exists():  # a case runs in a worker; its summary is written here
                family.write_json(summaries[i].relative_to(family.path).as_posix(), summary)
            rows[i] = _row(i, float(values[i]), summary)
            family.finished += 1
            family.write_csv("sweep.csv", SWEEP_HEADER, [r for r in rows if r is not None])
            if progress:
                progress()

        run_members(_run_one, summaries, lambda pending: [cases[i] for i in pending], record,
                    scheduler="dask" if dask_address else "processes", workers=workers, address=dask_address)
        _plot(rows, key, family.path / "sweep.png")
    return Path(outdir)


def _plot(rows, key, path):
    from impactdyn._plotting import pyplot, save_figure

    plt = pyplot()

    x = [r[1] for r in rows]
    fig, axes = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
    v = [np.nan if r[4] == "" else r[4] for r in rows]
    f = [np.nan if r[7] == "" else r[7] for r in rows]
    axes[0].plot(x, v, "o-")
    axes[0].set_ylabel("first-impact approach velocity (m/s)")
    axes[1].plot(x, f, "o-")
    axes[1].set_ylabel("first-impact peak force (N)")
    for ax in axes:
        ax.set_xlabel(key)
        ax.grid(alpha=0.3)
    save_figure(fig, path, dpi=110)
