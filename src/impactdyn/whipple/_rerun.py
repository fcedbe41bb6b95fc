"""The wall stage of a finished run again, under changed settings, with nothing written.

How a verdict depends on the wall's mesh, solver options and material model is asked of a run
folder that holds a finished debris stage (``debris/debris.h5``): the mesh study
(``verification/wall_convergence.py``) and the validation sets rescored under another wall model
(``validation/run_validation_shots.py``) both rerun the wall this way.  To keep a rerun's files,
change the case and restart the run from its wall stage instead (:func:`run_whipple`, ``start="wall"``).
"""

from __future__ import annotations

from pathlib import Path


def rerun_wall(run: str | Path, model_changes: dict | None = None, **changes):
    """The wall stage of the finished run folder ``run`` again, on its deposition and its case's wall.

    ``changes``: :class:`impactdyn.wall.WallOptions` fields to replace (``refinement_thickness=2``,
    ``material_model="johnson_cook"``); ``model_changes``: keywords of the material model
    (:func:`impactdyn.wall.wall_model`, e.g. ``{"damage": None}``), the model being the options'
    ``material_model`` built from the case's wall material.  Nothing is written and no time series is
    kept (``output_interval_us`` None): the solver's steps no longer stop at the frames' times, so even
    unchanged the measures differ from the run's at the level of the time stepping (a bulge by 3e-4 on
    the coarse test shot), and reruns compare with each other, not with the run.  Returns the
    :class:`impactdyn.wall.WallResult`.
    """
    from impactdyn.debris import read_deposition
    from impactdyn.wall import run_wall, wall_model
    from impactdyn.whipple._case import load_whipple_case

    run = Path(run)
    case = load_whipple_case(run / "case.toml")
    wall, deposition, _ = read_deposition(run / "debris" / "debris.h5")
    options = case.wall_options.replaced(output_interval_us=None, **changes)
    model = (wall_model(options.material_model, case.wall.material, **model_changes) if model_changes
             else case.wall.material)
    return run_wall(wall, deposition, model, options)
