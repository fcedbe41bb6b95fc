"""The end-to-end Whipple-shield pipeline (docs/theory/).

A case file (:class:`WhippleCase`) describes a shot: sphere, bumper, rear wall and
the numerics of each stage. :func:`run_whipple` runs the SPH shield impact to the
hand-off time, bins the particles behind the bumper into a HydroGrid, carries the
debris to the wall with DC3D, writes the wall decks and a report with the NASA JSC
ballistic-limit verdict beside the simulated deposition::

    from impactdyn.whipple import load_whipple_case, run_whipple
    summary = run_whipple(load_whipple_case("examples/whipple/table2_7a.toml"), "runs/7a")
"""

from impactdyn.whipple._case import WhippleCase, load_whipple_case, shield_problem
from impactdyn.whipple._campaign import run_campaign
from impactdyn.whipple._cloud import cloud_figures
from impactdyn.whipple._limit import run_limit
from impactdyn.whipple._pipeline import run_whipple
from impactdyn.whipple._rerun import rerun_wall
from impactdyn.whipple._stages import STAGES, read_stage
from impactdyn.whipple._database_shot import (ALLOYS, DatabaseShot, alloy_substitutions, database_shot, database_shot_case,
                                          database_shot_case_text)
from impactdyn.whipple._report import ble_verdict, draws_statement, wall_ending, wall_permanent_bulge
from impactdyn.whipple._selection import SelectionRule, fix_rule, load_rule, rule_hash, select_shots
from impactdyn.whipple._validate import run_validation, score_validation
from impactdyn.whipple._validation_record import (ValidationRecord, limit_statement, record_validation,
                                                   validation_record)

__all__ = ["ALLOYS", "STAGES", "DatabaseShot", "SelectionRule", "WhippleCase", "ble_verdict", "cloud_figures",
           "database_shot", "database_shot_case", "fix_rule", "load_rule", "load_whipple_case", "read_stage",
           "rerun_wall", "rule_hash", "run_campaign", "run_limit", "run_validation", "run_whipple", "score_validation",
           "draws_statement", "select_shots", "shield_problem", "wall_ending", "wall_permanent_bulge", "ValidationRecord",
           "limit_statement", "record_validation", "validation_record", "alloy_substitutions",
           "database_shot_case_text"]
