"""The onset of the projectile's break-up against Reimerdes' V_LV (issue 38, check 1 of
validation/shield-mechanism-decision.md), on the check's own set-up at its coarser spacing d/20.

The model does not meet it yet: the projectile is already broken below V_LV − 0.5 km/s (onset
1.75 km/s at t/D 0.1 against V_LV = 3.31 km/s; docs/vv/test-shots.md, "Mechanism checks").  The
test states the published behaviour and is expected to fail (strict), so a model that meets it is
noticed; it is not loosened to pass.
"""

import math

import numpy as np
import pytest

from impactdyn import shield

D = 0.3175           # cm, the checks' sphere
SPACING = D / 20
RATIO = 0.1
V_LV = 1.853 + 0.397 * RATIO ** -0.565   # km/s, NASA/TM-2009-214789 eq. 54: 3.31 at t/D 0.1
CANDIDATE = shield.SPHOptions(failure_model="fragmentation", flow_stress="johnson_cook", viscosity_switch="balsara")


def largest_projectile_piece(speed_km_s):
    """The heaviest intact fragment made mostly of projectile particles at 3 µs, over the projectile."""
    problem = shield.sphere_on_plate("al6061-t6", "al6061-t6", D, speed_km_s, 0.0, RATIO * D, SPACING,
                                     plate_radius_cm=1.5 * D)
    projectile = problem.particles.velocity[:, 1] > 0
    state = shield.run(problem, 3.0, options=CANDIDATE).state
    fragments = shield.fragments_of(state, link_length_cm=1.5 * SPACING)
    both = np.concatenate([projectile, projectile])          # the images follow the particles
    m_proj = 2.703 * math.pi * D ** 3 / 6
    heaviest = next((fragments.mass[f] for f in range(len(fragments)) if both[fragments.indices(f)].mean() > 0.5),
                    0.0)
    return heaviest / m_proj


@pytest.mark.xfail(strict=True, reason="break-up begins 1.5 km/s below V_LV (issue 38, check 1 fails)")
def test_the_projectile_stays_whole_below_the_onset_and_breaks_above_it():
    assert largest_projectile_piece(V_LV - 0.5) >= 0.5
    assert largest_projectile_piece(V_LV + 0.5) < 0.5
