"""Bad input is an InputError naming the key; a breakdown is a WallSolverError naming the element."""

import dataclasses

import numpy as np
import pytest

from impactdyn._errors import InputError
from impactdyn import wall
from impactdyn.materials import AL_6061_T6_MAT13
from impactdyn.wallgrid import WallDeposition, WallGrid

from .conftest import SMALL_WALL, two_records

GRID = SMALL_WALL
DEP = two_records()


@pytest.mark.parametrize("key, kwargs", [
    ("refinement_thickness", {"refinement_thickness": 0}),
    ("refinement_thickness", {"refinement_thickness": -1}),
    ("refinement_plane", {"refinement_plane": 0}),
    ("refinement_plane", {"refinement_plane": 2.0}),
    ("material_model", {"material_model": "elastic_rubber"}),
    ("hourglass", {"hourglass": "none"}),
    ("hourglass_coefficient", {"hourglass_coefficient": -0.1}),
    ("q1", {"q1": float("nan")}),
    ("courant", {"courant": 1.5}),
    ("courant", {"courant": 0.0}),
    ("end_time_us", {"end_time_us": -1.0}),
    ("max_time_us", {"max_time_us": 0.0}),
    ("spread", {"spread": "everywhere"}),
    ("supports", {"supports": "welded"}),
    ("output_interval_us", {"output_interval_us": 0.0}),
    ("decay_fraction", {"decay_fraction": 0.0}),
    ("settle", {"settle": "yes"}),
    ("settle_tolerance", {"settle_tolerance": 0.0}),
    ("max_settle_steps", {"max_settle_steps": 0}),
    ("deposition_depth_cm", {"deposition_depth_cm": -0.1}),
    ("deposition_depth_cm", {"deposition_depth_cm": float("inf")}),
])
def test_bad_option_names_the_key(key, kwargs):
    with pytest.raises(InputError, match=key):
        wall.WallOptions(**kwargs)


def test_end_time_before_the_last_arrival():
    with pytest.raises(InputError, match="end_time_us"):
        wall.run_wall(GRID, DEP, "al6061-t6", wall.WallOptions(end_time_us=2.0))
    with pytest.raises(InputError, match="max_time_us"):
        wall.run_wall(GRID, DEP, "al6061-t6", wall.WallOptions(max_time_us=2.0))


def test_non_positive_thickness():
    with pytest.raises(InputError, match="WallGrid.y"):
        WallGrid(GRID.x, np.array([0.3, 0.3]), GRID.z)
    with pytest.raises(InputError, match="WallGrid.y"):
        WallGrid(GRID.x, np.array([0.3, 0.0]), GRID.z)


def test_model_and_material_mismatch():
    with pytest.raises(InputError, match="material_model"):
        wall.run_wall(GRID, DEP, wall.wall_model("mat13"), wall.WallOptions(material_model="johnson_cook"))
    with pytest.raises(InputError, match="model"):
        wall.run_wall(GRID, DEP, 42, wall.WallOptions())
    with pytest.raises(InputError, match="WallDeposition.element"):
        bad = WallDeposition(element=np.array([GRID.n_face_elements]), time=np.array([0.0]),
                             impulse=np.zeros((1, 3)))
        wall.run_wall(GRID, bad, "al6061-t6")


def test_breakdown_raises_a_solver_error():
    # an impulse that drives a corner node through its element in one step, with failure off
    card = dataclasses.replace(AL_6061_T6_MAT13, failure_strain=0.0)
    model = wall.Mat13Model(card)
    crush = WallDeposition(element=np.array([12]), time=np.array([0.0]), impulse=np.array([[0.0, 5.0, 0.0]]))
    with pytest.raises(wall.WallSolverError, match=r"element .*\(i, j, k\)"):
        wall.run_wall(GRID, crush, model, wall.WallOptions(end_time_us=1.0, material_model="mat13"))
