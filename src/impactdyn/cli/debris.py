"""``impactdyn debris``: DC3D debris-cloud propagation, deposition and wall decks."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from impactdyn.cli._progress import progress_bars

app = typer.Typer(help="Debris cloud → rear wall (DC3D, DCPOST, DCMPLT).", no_args_is_help=True)

#: dc3din's (itype, jtype) → what `debris legacy` does, for the help text.
LEGACY_HELP = ("2/1 propagate, deposit, write both wall decks; 2/2 and 2/3 write the wall deck only on the old or "
               "new wall grid; 1/1 propagate 0.2 µs and write CTH rezone packages")


def _report(summary: dict, out: Path) -> None:
    from impactdyn.units import AREAL_MOMENTUM_UNIT, N_S_PER_G_CM_US

    p_in, p_dep = summary["momentum_in"], summary["momentum_deposited"]
    typer.echo(f"{summary['n_particles']} particles from {summary['n_cells_seeded']} cells; "
               f"{summary['n_arrived']} arrived; momentum in {p_in[1]:.6g} (y), deposited {p_dep[1]:.6g} (y) g·cm/µs; "
               f"peak areal momentum {N_S_PER_G_CM_US * summary['peak_areal_density_g_cm_us']:.4g} "
               f"{AREAL_MOMENTUM_UNIT}; "
               f"{summary['wall_time_s']:.2f} s wall; results in {out}")
    if summary["integrator"]["n_failed"]:
        typer.echo(f"warning: {summary['integrator']['n_failed']} particles failed to integrate: "
                   f"{summary['integrator']['failures']}", err=True)


@app.command()
def run(
    case: Path = typer.Argument(..., help="Debris case file (TOML)."),
    out: Path = typer.Option(..., "-o", "--out", help="Run folder to create."),
    force: bool = typer.Option(False, "--force", help="Overwrite an existing run folder."),
):
    """Seed particles from the hand-off grid, carry them to the wall, deposit, write the run folder."""
    import time

    from impactdyn._runfolder import check_target
    from impactdyn.debris import build, load_debris_case, remap_grid, run_debris, write_debris_run

    check_target(out, force)
    c = load_debris_case(case)
    args = build(c, str(case))
    start = time.perf_counter()
    bar, update = progress_bars()
    with bar:
        result = run_debris(**args, progress=update)
    summary = write_debris_run(result, c, out, force=force, remap=remap_grid(c),
                               extra_summary={"title": c.title, "wall_time_s": time.perf_counter() - start})
    _report(summary, out)


@app.command(help=f"Run the 1994 workflow from dc3din (+ avsout): {LEGACY_HELP}.")
def legacy(
    dc3din: Path = typer.Argument(..., help="DC3D input file (App. C layout)."),
    avsout: Optional[Path] = typer.Argument(None, help="CTH dump read by RDAVS (needed unless the run type "
                                                       "only writes the wall deck)."),
    out: Path = typer.Option(..., "-o", "--out", help="Run folder to create."),
    force: bool = typer.Option(False, "--force", help="Overwrite an existing run folder."),
    listing: bool = typer.Option(False, "--listing", help="Reproduce the listing's deviations from the model too "
                                                          "(every legacy flag and its RK4 step doubling)."),
):
    from impactdyn.debris import run_legacy

    run_legacy(dc3din, avsout, out, force=force, listing=listing, progress_factory=progress_bars,
               echo=typer.echo, report=_report)
