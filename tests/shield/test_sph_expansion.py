"""Free homologous expansion of failed material: the continuity density follows ρ₀/(1 + kt)³ down to
the floor ρ₀/h_max_factor³, and stays positive however fast the debris expands (the linear density
update went negative in the fast case; issue 4)."""

import numpy as np
import pytest

from impactdyn.materials import get_material
from impactdyn.shield import Problem, run
from impactdyn.shield._problems import _particles

AL = get_material("al6061-t6")


def expanding_cube(k: float, n: int = 10, dx: float = 0.02) -> Problem:
    """n³ failed particles (no tension, no shear) with v = k x about the cube's centre."""
    g = dx * (np.arange(n) - (n - 1) / 2)
    x = np.stack(np.meshgrid(g, g, g, indexing="ij"), axis=-1).reshape(-1, 3)
    p = _particles(x, k * x, np.full(len(x), AL.rho0 * dx**3), np.zeros(len(x), dtype=np.int64), (AL,))
    return Problem(particles=p.replace(failed=np.ones(len(x), dtype=bool)), materials=(AL,), spacing_cm=dx)


def test_density_follows_a_homologous_expansion():
    k, t = 5.0, 0.1  # to ρ₀/3.4, above the floor ρ₀/8
    state = run(expanding_cube(k), t).state
    centre = np.argsort(np.linalg.norm(state.position, axis=1))[:8]
    assert state.density[centre].mean() == pytest.approx(AL.rho0 / (1.0 + k * t) ** 3, rel=0.03)


def test_density_stays_positive_in_a_violent_expansion():
    result = run(expanding_cube(60.0), 0.05)  # v up to 27 km/s at the corners; ρ₀/64 in the exact flow
    assert np.all(result.state.density > 0) and np.all(np.isfinite(result.state.density))
