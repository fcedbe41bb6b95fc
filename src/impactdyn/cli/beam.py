"""``impactdyn beam``: rotating flexible beam with impact (IMPACTC/IMPACTB, ROOTM/INTEG)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Optional

import typer

app = typer.Typer(help="Rotating flexible beam striking a stop (IMPACTC, IMPACTB, ROOTM, INTEG).",
                  no_args_is_help=True)


@app.command()
def modes(
    n: int = typer.Argument(..., help="Number of modes (1..50)."),
    hub_radius: float = typer.Option(0.0, "--hub-radius", help="Hub radius A (m), for the dimensional M₀ᵢ."),
    length: float = typer.Option(1.0, "--length", help="Beam length L (m)."),
    as_json: bool = typer.Option(False, "--json", help="Print JSON instead of a table."),
):
    """Cantilever eigenvalues βᵢ, σᵢ and modal integrals aᵢ, bᵢ, k, h (ROOTM + INTEG)."""
    from impactdyn._errors import InputError
    from impactdyn.beam import modal_integrals

    if not 1 <= n <= 50:
        raise InputError(f"N = {n}: the number of modes must be in 1..50")
    if length <= 0 or hub_radius < 0:
        raise InputError("--length must be > 0 and --hub-radius >= 0")
    mi = modal_integrals(n)
    # coupling per unit mass-per-length: M₀ᵢ/ρ = L² aᵢ + A L bᵢ
    m0_per_rho = length**2 * mi.a + hub_radius * length * mi.b
    if as_json:
        out = mi.as_dict() | {"m0_per_rho_m2": m0_per_rho.tolist(), "hub_radius_m": hub_radius, "length_m": length}
        typer.echo(json.dumps(out, indent=2))
        return
    from rich.console import Console
    from rich.table import Table

    t = Table(title=f"Clamped–free cantilever, {n} modes (L = {length:g} m, A = {hub_radius:g} m)")
    for col in ("i", "βᵢ", "σᵢ", "aᵢ = ∫ξφ", "bᵢ = ∫φ", "kᵢᵢ", "hᵢᵢ", "M₀ᵢ/ρ (m²)"):
        t.add_column(col, justify="right")
    for i in range(n):
        t.add_row(str(i + 1), f"{mi.beta[i]:.12f}", f"{mi.sigma[i]:.12f}", f"{mi.a[i]:.9f}", f"{mi.b[i]:.9f}",
                  f"{mi.k[i, i]:.6f}", f"{mi.h[i, i]:.6f}", f"{m0_per_rho[i]:.6g}")
    Console(width=max(Console().width, 130)).print(t)


@app.command()
def run(
    case: Path = typer.Argument(..., help="Beam case file (TOML)."),
    out: Path = typer.Option(..., "-o", "--out", help="Run folder to create."),
    force: bool = typer.Option(False, "--force", help="Overwrite an existing run folder."),
):
    """Simulate a case and write its run folder (summary, tables, plots)."""
    from impactdyn._config import load_case
    from impactdyn._runfolder import check_target
    from impactdyn.beam import BeamCase, simulate, write_run

    check_target(out, force)
    c = load_case(BeamCase, case)
    result = simulate(c)
    write_run(result, out, force=force)
    s = result.summary()
    typer.echo(f"{s['n_impacts']} impacts; first at "
               + (f"{s['impacts'][0]['t_start']:.9f} s, v = {s['impacts'][0]['v_approach']:.6f} m/s, "
                  f"e = {s['impacts'][0]['restitution']:.6f}" if s["impacts"] else "—")
               + f"; {result.wall_time_s:.3f} s wall; results in {out}")


@app.command()
def sweep(
    case: Path = typer.Argument(..., help="Base case file (TOML)."),
    vary: str = typer.Option(..., "--vary", help="KEY=START:STOP:N, e.g. torque.amplitude_N_m=-0.3:-0.1:5"),
    out: Path = typer.Option(..., "-o", "--out", help="Sweep folder to create."),
    force: bool = typer.Option(False, "--force", help="Overwrite an existing folder."),
    resume: bool = typer.Option(False, "--resume", help="Go on in the folder an interrupted sweep left: its "
                                                        "finished cases are kept, the others run (same case "
                                                        "and --vary)."),
    workers: Optional[int] = typer.Option(None, "--workers", help="Parallel workers (default: all cores)."),
    dask: Optional[str] = typer.Option(None, "--dask", help="'local' for a LocalCluster, or a scheduler address."),
):
    """Run a case over a range of one parameter in parallel; table and plot of the results."""
    from rich.progress import Progress

    from impactdyn._runfolder import check_target
    from impactdyn.beam import parse_vary, run_sweep

    check_target(out, force or resume)
    _, values = parse_vary(vary)
    with Progress(transient=True) as progress:
        task = progress.add_task("cases", total=len(values))
        run_sweep(case, vary, out, force=force, resume=resume, workers=workers, dask_address=dask,
                  progress=lambda: progress.advance(task))
    typer.echo(f"{len(values)} cases; table in {out / 'sweep.csv'}")
