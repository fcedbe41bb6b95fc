"""The end-to-end Whipple pipeline: shield → binning → debris → wall → draws → decks → report (docs/theory/).

Each stage reads the artifacts of the stages before it from the run folder and
writes its own into a subfolder with a ``stage.json`` record (its numbers, its
wall time and the case settings it depends on), so a run restarts from any
stage with exactly the code path of a full run::

    shield/    particles.h5        SPH particles at the hand-off time and the history of totals
               particles.vtu       the same as points (ParaView)
               fragments.h5        the debris's solid fragments, found once here and read by the later stages
               fragments.csv       the same, largest first (mass, size, velocity, spin, shape)
    binning/   handoff_grid.h5     the HydroGrid binned from the particles behind the bumper
    debris/    (an ``impactdyn debris run`` folder: summary.json, config.resolved.toml — a
               runnable debris case —, areal_density.csv, debris.h5, particles_*.vtu,
               wall_deposition.vtu, plots/)
    wall/      wall.json (verdict, evidence, measures, energy balance), wall.pvd + wall_*.vtu (ParaView
               time series), plots/wall_front.png, wall_rear.png, wall_history.png
    draws/     seed<k>/ for each further draw of the fragments' partition (``[shield] fragment_draws``): its
               shield/ (the fragments' record), binning/, debris/ and wall/ stage records, as a lean shot keeps
               them; draws/stage.json holds every draw's verdict and P(perforation) with its interval
    decks/     wall.k, wall_dyna3d.inp   the wall decks with the deposited momentum
    report.html, summary.json, plots/, case.toml   (the report stage)

A run keeps (``keep``, the CLI's ``--keep``) either everything above (``"all"``) or, by default
(``"lean"``), what the report, ParaView and a restart from any stage need — on the Table 2 7a shot
45 MB instead of 533 MB:

* the hand-off grid once, in ``binning/`` (the debris folder's ``config.resolved.toml`` names it);
* ``debris/debris.h5`` with the deposition and the wall only (what the wall and decks stages read),
  not the particles' states at hand-off and arrival (80 MB on 7a), and no particle VTU files
  (40 MB on 7a; ``debris/wall_deposition.vtu`` stays);
* the wall's ParaView series one frame per 10 µs and the last, lighter frames
  (:func:`impactdyn.wall.write_wall_outputs`, ``series="lean"``: 10 frames, 28 MB, instead of 44, 270 MB, on 7a);
* no decks: the LS-DYNA deck's load curves are 90 MB on 7a (a curve point per pulse corner of
  700,000 deposition records) and nothing downstream reads the decks;
  ``impactdyn whipple run CASE -o RUN --from decks --keep all`` writes them into a lean run
  folder in seconds, from the deposition it keeps.

Every stage's numbers, the verdict and the report are the same either way: ``keep`` changes what is
written, never what is computed.  ``summary.json`` records it.

A restart (``start`` = a later stage) stages the run anew: the earlier stages'
subfolders are copied from the existing run folder, their ``stage.json`` must
show the same settings as the case (otherwise they would not belong to it), the
later stages are recomputed, and the whole folder replaces the old one at the end.
"""

from __future__ import annotations

import json
import os
import shutil
import time
from collections.abc import Iterator
from contextlib import ExitStack, contextmanager
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from impactdyn._config import dump_toml
from impactdyn.units import KM_S_PER_CM_US, km_s_to_cm_us
from impactdyn._errors import InputError
from impactdyn._runfolder import FolderWriter, RunFolder, check_target
from impactdyn.whipple._case import WhippleCase
from impactdyn.whipple._stages import (DEPENDS, FAILED_VERDICTS, KEEP, LEAN_OUTPUT, STAGES, Progress, StageContext,
                                      prune_run, read_stage, settings)

def _shield(s: StageContext) -> dict:
    from impactdyn.shield import run, write_particles
    from impactdyn.whipple._case import shield_problem

    problem, options = shield_problem(s.case)
    t_end = s.case.shield.handoff_us
    result = run(problem, t_end, options=options, progress=lambda t, t1: s.report("shield", t, t1))
    out = s.folder.sub("shield")  # particles.h5 (2 MB on 7a) is kept: the binning and the report read it
    write_particles(out.file("particles.h5"), result.state, result.history)
    if s.case.output.vtk:
        _write_points_vtk(out.file("particles.vtu"), result.state)
    h = result.history
    p0 = h.momentum[0]
    e0 = h.total_energy[0]
    return {
        "problem": problem.name,
        "n_particles": len(result.state),
        "t_handoff_us": t_end,
        "steps": result.steps,
        "mass_g": float(h.mass[-1]),
        "momentum_initial_g_cm_us": p0.tolist(),
        "momentum_final_g_cm_us": h.momentum[-1].tolist(),
        "momentum_error_rel": float(np.max(np.linalg.norm(h.momentum[:, 1:] - p0[1:], axis=1))
                                    / np.linalg.norm(p0)),
        "energy_initial": float(e0),
        "energy_error_rel": float(np.max(np.abs(h.total_energy - e0)) / e0),
        "kinetic_final": float(h.kinetic[-1]),
        "internal_final": float(h.internal[-1]),
        "n_failed": int(result.state.failed.sum()),
    } | _write_fragments(s.case, out, result.state, problem)


def _write_fragments(case: WhippleCase, out: FolderWriter, particles, problem) -> dict:
    """The debris's fragments of the shield stage's state (:func:`impactdyn.shield.debris_fragments` with the
    case's fragment options) into ``out`` (``fragments.h5``, ``fragments.csv``); returns their figures and the
    debris's state for the stage record."""
    from impactdyn.shield import debris_fragments, fragment_rows, origin_masses, write_fragments
    from impactdyn.whipple._case import projectile_mass
    from impactdyn.whipple._cloud import debris_state, fragment_figures, projectile_particles

    speed = km_s_to_cm_us(case.projectile.velocity_km_s)
    fragments = debris_fragments(particles, problem, case.fragment_options, speed)
    write_fragments(out.file("fragments.h5"), fragments)
    projectile = projectile_particles(problem)
    from_projectile = origin_masses(fragments, particles.mass, projectile)
    out.write_csv("fragments.csv", *fragment_rows(fragments, from_projectile_g=from_projectile))
    return {"fragments": fragment_figures(fragments, from_projectile, projectile_mass(case)),
            "debris_state": debris_state(particles, projectile, fragments, case.bumper.thickness_cm,
                                         projectile_mass(case))}


def _write_points_vtk(path: Path, particles) -> None:
    import meshio

    from impactdyn.io import write_mesh

    n = len(particles)
    write_mesh(path, meshio.Mesh(particles.position, [("vertex", np.arange(n).reshape(-1, 1))], point_data={
        "velocity_cm_us": particles.velocity, "speed_km_s": KM_S_PER_CM_US * np.linalg.norm(particles.velocity, axis=1),
        "density_g_cm3": particles.density, "pressure_Mbar": particles.pressure,
        "plastic_strain": particles.plastic_strain, "failed": particles.failed.astype(np.int8),
        "material": particles.material.astype(np.int32), "mass_g": particles.mass}))


def _binning(s: StageContext) -> dict:
    from impactdyn.hydrogrid import check_cells
    from impactdyn.io import write_grid
    from impactdyn.shield import bin_to_hydrogrid, compact_particles, read_particles
    from impactdyn.whipple._case import binning_region
    from impactdyn.whipple._cloud import compact_fragments, stage_fragments

    s.report("binning", 0, 1)
    particles, _ = read_particles(s.folder.path / "shield" / "particles.h5")
    # the compact fragments fly to the wall on their own (the debris stage): not binned into the cloud
    compact = compact_particles(compact_fragments(stage_fragments(s.folder.path), s.case), len(particles))
    particles = particles.select(~compact)
    region = binning_region(s.case, particles)
    cell = s.case.binning.cell_size_cm
    check_cells(f"binning.cell_size_cm = {cell:g}", [(hi - lo) / cell for lo, hi in region])
    grid = bin_to_hydrogrid(particles, s.case.binning.cell_size_cm, region=region, method=s.case.binning.method)
    write_grid(s.folder.sub("binning").file("handoff_grid.h5"), grid)
    inside = particles.position[:, 1] >= region[1][0]  # the region holds every particle behind the bumper
    s.report("binning", 1, 1)
    m_particles = float(particles.mass[inside].sum())
    return {
        "cell_size_cm": s.case.binning.cell_size_cm,
        "method": s.case.binning.method,
        "shape": list(grid.shape),
        "n_cells": int(np.prod(grid.shape)),
        "n_cells_with_mass": int(np.count_nonzero(grid.mass)),
        "region_cm": [[float(grid.x[0]), float(grid.x[-1])], [float(grid.y[0]), float(grid.y[-1])],
                      [float(grid.z[0]), float(grid.z[-1])]],
        "n_particles_binned": int(inside.sum()),
        "n_particles_in_compact_fragments": int(compact.sum()),
        "mass_particles_g": m_particles,
        "mass_grid_g": float(grid.mass.sum()),
        "mass_error_rel": abs(float(grid.mass.sum()) - m_particles) / m_particles if m_particles else 0.0,
        "momentum_grid_g_cm_us": grid.total_momentum().tolist(),
    }


def _debris(s: StageContext) -> dict:
    from impactdyn.debris import build, check_seeding, run_debris, with_compact_fragments, write_debris_files
    from impactdyn.io import read_grid
    from impactdyn.whipple._case import debris_case

    case = debris_case(s.case, "../binning/handoff_grid.h5")
    grid = read_grid(s.folder.path / "binning" / "handoff_grid.h5")
    # before any particle is seeded: too many for memory, or debris behind the wall, named by the case's keys
    check_seeding(case, grid, f"binning.cell_size_cm = {s.case.binning.cell_size_cm:g}",
                  "the wall's front face (bumper.thickness_cm + wall.spacing_cm)", "the shield stage's hand-off")
    result = run_debris(**build(case, grid=grid), progress=s.report)
    landing = _landing_fragments(s.case, s.folder.path)
    result, compact = with_compact_fragments(result, *landing, s.case.wall_front_y)
    summary = write_debris_files(s.folder.sub("debris"), result, case, decks=False, lean=s.lean,
                                 extra_summary={"compact_fragments": compact,
                                                "peak_areal_density_mesh": _mesh_scale_peak(s.case, result, *landing)})
    return {key: summary[key] for key in (
        "n_cells_seeded", "n_particles", "n_propagated", "n_arrived", "mass_seeded_g", "mass_arrived_g",
        "momentum_in", "momentum_arrived", "momentum_deposited", "momentum_off_wall", "momentum_added_at_wall",
        "momentum_failed",
        "momentum_outside_window", "momentum_not_reaching", "mass_outside_window_g", "mass_not_reaching_g",
        "arrival_time_us", "peak_areal_density_g_cm_us", "peak_areal_density_mesh", "integrator", "timings_s",
        "compact_fragments")}


def _landing_fragments(case: WhippleCase, folder: Path):
    """The compact fragments of the shield stage's debris (:func:`impactdyn.whipple._cloud.compact_fragments`)
    and which of them land during the wall run (:func:`impactdyn.debris.landing_mask`, the run ending at
    ``wall_solver.end_time_us``, else its ceiling ``max_time_us``): (fragments, inside (F,) bool)."""
    from impactdyn.debris import landing_mask
    from impactdyn.whipple._cloud import compact_fragments, stage_fragments

    fragments = compact_fragments(stage_fragments(folder), case)
    options = case.wall_options
    end = options.max_time_us if options.end_time_us is None else min(options.end_time_us, options.max_time_us)
    return fragments, landing_mask(fragments, case.wall_front_y, case.filter.t_min_us, end)


def _mesh_scale_peak(case: WhippleCase, result, fragments, inside) -> dict:
    """The peak areal impulse |Σ p|/A (g/(cm µs)) of the cloud's points and the landing compact fragments
    deposited on the wall mesh's own face cells, and those cells' smallest in-plane edge (cm): what the
    case's grid, on whose cells the wall is loaded, smooths away (the wall stage shares each case cell's
    impulse among the mesh's face cells it covers by area)."""
    from impactdyn.debris import areal_density, compact_records, element_impulse
    from impactdyn.wall import solver_grid

    if not result.deposition.element.size:
        return {"peak_g_cm_us": 0.0, "cell_cm": None}
    face = solver_grid(result.wall, result.deposition, **case.wall_options.grid_settings())
    impulse = element_impulse(result.deposition_on(face), face)
    if inside.any():
        impulse = impulse + element_impulse(compact_records(face, case.wall_front_y, fragments, inside), face)
    return {"peak_g_cm_us": float(areal_density(impulse, face).max()),
            "cell_cm": float(min(np.diff(face.x).min(), np.diff(face.z).min()))}


def _wall(s: StageContext) -> dict:
    from impactdyn.debris import read_deposition
    from impactdyn.wall import check_end_times, run_wall, write_wall_outputs

    s.report("wall", 0, 1)
    wall, deposition, _ = read_deposition(s.folder.path / "debris" / "debris.h5")
    options = s.case.wall_options
    check_end_times(options, deposition, key_prefix="wall_solver.")     # named as the case spells them
    result = run_wall(wall, deposition, s.case.wall.material, options,
                      progress=lambda t, t_end: s.report("wall", t, t_end),
                      settle_progress=lambda done, total: s.report("settle", done, total))
    out = s.folder.sub("wall")
    series = s.keep if s.case.output.vtk else "none"   # the series is named as keep is: "lean" or "all"
    files = write_wall_outputs(result, out.path, plots=out.path / "plots", series=series, figures=s.case.output.plots)
    s.report("wall", 1, 1)
    return result.summary() | {"files": sorted(f"wall/{p.relative_to(out.path).as_posix()}" for p in files.values())}


def _draws(s: StageContext) -> dict:
    """The partition's draws (``[shield] fragment_draws``): the run's own wall is the first draw; each further
    seed draws the fragments again from the same SPH state and runs the binning, the debris and the wall
    into ``draws/seed<k>/`` (:func:`_run_draw`), which keeps what a lean shot of a family keeps (stage records,
    the wall's measures: :func:`impactdyn.whipple._stages.prune_run`) but draws no figures (:data:`DRAW_OUTPUT`).
    The further draws were started before the run's own binning (:func:`further_draws`); this stage collects
    them, so its ``wall_time_s`` is what they took beyond the run's own chain.  The record: each draw's seed and
    verdict, the perforations k of N (:data:`FAILED_VERDICTS`) and P = k/N with its Wilson 95 % interval."""
    from impactdyn.ble import Proportion

    seeds = s.case.fragment_options.seeds
    further: list = [None] * (len(seeds) - 1)
    s.report("draws", 1, len(seeds))
    for n, (i, outcome) in enumerate(s.further_draws or (), start=2):
        further[i] = outcome
        s.report("draws", n, len(seeds))
    outcomes = [_draw_outcome(s.folder.path)] + further
    p = Proportion.of_counts(sum(o["perforated"] for o in outcomes), len(outcomes))
    return {"n_draws": len(seeds), "draws": [{"seed": seed} | o for seed, o in zip(seeds, outcomes)],
            "perforated": p.count, "probability": p.rate, "wilson_95": [p.low, p.high]}


#: The case's ``[output]`` settings of a further draw besides :data:`LEAN_OUTPUT`: no figures (the debris's and
#: the wall's five PNGs, 4.6 s of a 32-s draw on Table 2's 7a); the report draws every draw's measures in one.
DRAW_OUTPUT = {"plots": False}


@contextmanager
def further_draws(case: WhippleCase, run: Path) -> Iterator[Iterator[tuple[int, dict]]]:
    """The further draws of the fragments' partition (the seeds after the first) into the staging folder
    ``run``, whose ``shield/`` is done, handed to their workers as the block opens: the ``(i, outcome)``
    iterator that collects them.  As processes (:func:`draw_schedule`) they run beside the run's own
    binning, debris and wall, this process holding one thread until the block closes, and as they are
    collected this process runs those no worker has taken yet; in turn, they run here as they are
    collected.  Leaving the block before the last (an error, Ctrl-C) stops them."""
    import numba

    from impactdyn._parallel import hold_threads, tasks_started

    held = numba.get_num_threads()
    seeds = case.fragment_options.seeds
    scheduler, workers, threads = draw_schedule(held, len(seeds) - 1)
    tasks = [Draw(case.model_copy(update={
        "shield": case.shield.model_copy(update={"fragment_seed": seed}),
        "output": case.output.model_copy(update=LEAN_OUTPUT | DRAW_OUTPUT)}), run, threads) for seed in seeds[1:]]
    with tasks_started(_run_draw, tasks, scheduler=scheduler, workers=workers, caller_helps=True) as finished:
        if scheduler == "processes":
            hold_threads(1)
        try:
            yield finished
        finally:
            hold_threads(held)


def draw_schedule(threads: int, n_draws: int) -> tuple[str, int, int]:
    """How ``n_draws`` further draws share a run's ``threads``: (scheduler, workers, threads per draw).  One
    thread, or no further draw, runs them here in turn after the run's own wall; otherwise they run as up
    to ``threads`` processes beside the run's own chain, which keeps one thread: the rest is shared among
    them, one at least each.  (On two cores, two draws of one thread and the run's own chain share the
    cores until its wall ends, when the run takes on draws itself (:func:`further_draws`): a draw's
    kernels on two threads run about 1.5 times as fast as on one, so processes of one thread finish a set
    of draws sooner than draws in turn on every thread.)"""
    if threads <= 1 or n_draws < 1:
        return "serial", 1, max(1, threads)
    workers = min(threads, n_draws)
    return "processes", workers, max(1, (threads - 1) // workers)


@dataclass(frozen=True)
class Draw:
    """One further draw of the fragments' partition: its case (the seed in ``shield.fragment_seed``), the run's
    staging folder (whose ``shield/particles.h5`` holds the SPH state) and the numba threads it may use."""

    case: WhippleCase
    run: Path
    threads: int


def _run_draw(draw: Draw) -> dict:
    """Run one draw into ``draws/seed<k>/`` of its run folder, in this process or a pool's worker: the fragments
    drawn with its seed from the run's SPH state, then the binning, the debris and the wall; returns its
    outcome (:func:`_draw_outcome`)."""
    from impactdyn._parallel import hold_threads
    from impactdyn.shield import read_particles
    from impactdyn.whipple._case import shield_problem

    hold_threads(draw.threads)
    seed = draw.case.shield.fragment_seed
    particles, _ = read_particles(draw.run / "shield" / "particles.h5")
    context = StageContext(draw.case, FolderWriter(draw.run).sub(f"draws/seed{seed}"), None, "lean")
    shield = context.folder.sub("shield")
    shield.write_json("stage.json", {"stage": "shield", "fragment_seed": seed}
                      | _write_fragments(draw.case, shield, particles, shield_problem(draw.case)[0]))
    # the later stages read the SPH state from their run folder's shield/: the run's own, not a copy, linked
    # relative to the link (a run folder given as a relative path would otherwise be read from the link's folder)
    link = shield.path / "particles.h5"
    link.symlink_to(os.path.relpath(draw.run / "shield" / "particles.h5", link.parent))
    for stage in ("binning", "debris", "wall"):
        context.folder.sub(stage).write_json("stage.json", {"stage": stage} | _RUN[stage](context))
    prune_run(context.folder.path)
    return _draw_outcome(context.folder.path)


def _draw_outcome(folder: Path) -> dict:
    """One draw's wall verdict, whether it failed (:data:`FAILED_VERDICTS`), the wall's failed mass and peak rear
    bulge and the compact fragments' mass in the half model, from the stage records of its run ``folder``."""
    wall = read_stage(folder, "wall")
    return {"verdict": wall["verdict"], "perforated": wall["verdict"] in FAILED_VERDICTS,
            "failed_mass_g": wall["measures"]["failed_mass_g"],
            "peak_rear_bulge_cm": wall["measures"]["peak_rear_bulge_cm"],
            "compact_mass_g": read_stage(folder, "debris")["compact_fragments"]["mass_g"]}


def _decks(s: StageContext) -> dict:
    """The decks of the mesh the wall stage runs, loaded as the wall stage loads it: the records on the
    case's grid shared among the mesh's face cells by area (:func:`impactdyn.wall.solver_mesh`)."""
    from impactdyn.debris import element_impulse, element_records, read_deposition, write_decks
    from impactdyn.wall import rebin_deposition, resolve_model, solver_mesh

    s.report("decks", 0, 1)
    wall, deposition, case_impulse = read_deposition(s.folder.path / "debris" / "debris.h5")
    options = s.case.wall_options
    mesh = solver_mesh(wall, deposition, resolve_model(s.case.wall.material, options).density,
                       **options.mesh_settings())
    # the DYNA3D deck's DCPOST cards: each element's total, the case cells' totals shared by area
    impulse = element_impulse(rebin_deposition(element_records(case_impulse), wall, mesh.grid), mesh.grid)
    options = deck_options(s.case)
    if s.lean:  # the decks on request only (module docstring)
        options = replace(options, lsdyna=False, dyna3d=False)
    files = write_decks(s.folder.sub("decks"), mesh.grid, deposition, impulse, options, deposition_grid=wall)
    s.report("decks", 1, 1)
    return {"files": [f"decks/{name}" for name in files], "mesh": mesh.describe(),
            "n_records": int(deposition.element.size),
            "n_loaded_elements": int(np.count_nonzero(np.abs(impulse).sum(axis=-1)))}


def deck_options(case: WhippleCase):
    """The decks of the wall stage's model: its material model (MAT_013 card, or MAT_015 and
    its EOS for ``johnson_cook``), hourglass type and bulk viscosity, besides the case's
    output table (:meth:`impactdyn.debris.DeckOptions.of`)."""
    from impactdyn.debris import DeckOptions
    from impactdyn.wall import resolve_model

    options = case.wall_options
    model = resolve_model(case.wall.material, options)
    return replace(DeckOptions.of(case), material=model.deck_material, hourglass=options.lsdyna_hourglass,
                   bulk_viscosity=(options.q1, options.q2), failure_strain_floor=model.deck_failure_strain_floor,
                   erode_failed=model.erodes)


def _report(s: StageContext) -> dict:
    from impactdyn.whipple._report import write_report

    s.report("report", 0, 1)
    record = write_report(s.folder, s.case, s.keep)
    s.report("report", 1, 1)
    return record


_RUN = {"shield": _shield, "binning": _binning, "debris": _debris, "wall": _wall, "draws": _draws, "decks": _decks,
        "report": _report}


def run_whipple(case: WhippleCase, outdir: str | Path, *, start: str = "shield", force: bool = False,
                progress: Progress | None = None, keep: str = "lean") -> dict:
    """Run the stages from ``start`` on into the run folder ``outdir``; returns the summary.

    ``start`` other than "shield" restarts an existing run folder (module docstring);
    ``force`` lets a full run replace an existing folder; ``keep`` "lean" or "all" (module docstring:
    a restart keeps the copied stages' files as they are and writes the later ones as ``keep`` says).
    """
    if start not in STAGES:
        raise InputError(f"--from {start!r}: choose one of {', '.join(STAGES)}")
    if keep not in KEEP:
        raise InputError(f"--keep {keep!r}: choose one of {', '.join(KEEP)}")
    outdir = Path(outdir)
    first = STAGES.index(start)
    if first == 0:
        check_target(outdir, force)
    else:
        if not outdir.is_dir():
            raise InputError(f"{outdir}: no run folder to restart from (--from {start} reuses its earlier stages)")
        for stage in STAGES[:first]:
            if read_stage(outdir, stage).get("settings") != settings(case, stage):
                raise InputError(f"{outdir}: its {stage} stage was run with other settings than this case "
                                 f"({', '.join(DEPENDS[stage])}); run from {stage} or earlier")
    with RunFolder(outdir, force=True if first else force) as rf, ExitStack() as beside:
        for stage in STAGES[:first]:
            shutil.copytree(outdir / stage, rf.path / stage)
        rf.write_text("case.toml", dump_toml(case))
        draws = None
        for stage in STAGES[first:]:
            if draws is None and stage != "shield" and "draws" in STAGES[first:]:
                draws = beside.enter_context(further_draws(case, rf.path))
            tick = time.perf_counter()
            record = _RUN[stage](StageContext(case, rf, progress, keep, draws))
            record = {"stage": stage, "wall_time_s": time.perf_counter() - tick, "settings": settings(case, stage)
                      } | record
            rf.sub(stage).write_json("stage.json", record)
        summary = json.loads((rf.path / "summary.json").read_text())
    return summary
