"""The reused (Verlet) neighbour list: it always holds every interacting pair, and a run that reuses it
gives the state of a run that searches at every step, to round-off."""

import numpy as np
import pytest

from impactdyn import shield
from impactdyn.materials import AL_2024_T4, AL_6061_T6
from impactdyn.shield import Domain, SPHOptions
from impactdyn.shield._integrate import _Solver
from impactdyn.shield._neighbours import NeighbourList, neighbour_pairs


def listed_pairs(nl: NeighbourList) -> set[tuple[int, int, int]]:
    """The (i, j, image) pairs the list stands for: a half list's pair of real particles in both orders."""
    rows = [(i, int(nl.neighbours[i, k]), int(nl.image[i, k])) for i in range(nl.count.size)
            for k in range(nl.count[i])]
    pairs = set(rows)
    assert len(pairs) == len(rows)
    if nl.half:
        mirrored = {(j, i, 0) for i, j, t in rows if t == 0}
        assert not pairs & mirrored  # a pair of real particles is listed once
        pairs |= mirrored
    return pairs


@pytest.mark.parametrize("half", [False, True])
@pytest.mark.parametrize("domain", [Domain(), Domain(mirror=((0, 0.0),))])
def test_reused_list_holds_every_interacting_pair(domain, half):
    rng = np.random.default_rng(7)
    n = 400
    x = rng.uniform(0.0, 1.0, (n, 3))
    h = rng.uniform(0.05, 0.08, n)
    nl = NeighbourList(n, domain, capacity=8, skin=0.3, half=half)
    assert nl.update(x, h) and nl.builds == 1
    reused = 0
    for step in range(60):  # random motion and growth of h, each step well inside the skin
        x = x + rng.normal(0.0, 0.002, (n, 3))
        h = h * rng.uniform(0.995, 1.003, n)
        if step == 30:  # a renumbering of the particles, as the solver's spatial reordering does
            order = rng.permutation(n)
            x, h = x[order], h[order]
            nl.permute(order)
        reused += not nl.update(x, h)
        exact = {tuple(row) for row in neighbour_pairs(x, h, domain)}
        assert exact <= listed_pairs(nl)
    assert reused > 0 and nl.builds > 1  # both branches were taken


def test_reuse_and_search_every_step_give_the_same_state():
    """A sphere-on-plate impact (mirror plane, failure, artificial stress) for 40 steps, with the list reused
    within a skin of 0.15 h and 0.3 h and with a search at every step (skin 0): equal to round-off."""
    problem = shield.sphere_on_plate(AL_2024_T4, AL_6061_T6, diameter_cm=0.2, velocity_km_s=5.0, obliquity_deg=30.0,
                                     plate_thickness_cm=0.05, spacing_cm=0.025, plate_radius_cm=0.3)
    states = {}
    for skin in (0.0, 0.15, 0.3):
        solver = _Solver(problem, SPHOptions(neighbour_skin=skin))
        for _ in range(40):
            solver.step(solver.dt)
        back = np.argsort(solver.ids)
        state = solver.state
        states[skin] = (state.x[back], state.v[back], state.rho[back], state.e[back], solver.neighbours.builds)
    assert states[0.0][4] == 41  # searched at every force evaluation
    for skin in (0.15, 0.3):
        assert states[skin][4] < 30  # the list was reused
        for a, b in zip(states[0.0][:4], states[skin][:4]):
            assert np.abs(a - b).max() <= 1e-12 * np.abs(a).max()
