"""What the two step-size-controlled integrators share (``rk45``, :mod:`._rk45`; ``legacy``,
:mod:`._rk4_doubling`): the start of a particle's integration and the opening of each step.

Both are inlined into the integrators' particle kernels, so the arithmetic is theirs, in their order.
"""

from __future__ import annotations

from impactdyn.debris._failure import BUDGET, OK, state_failure
from impactdyn.debris._particle import inline_kernel
from impactdyn.debris._registry import body_rates

_OK, _BUDGET = OK, BUDGET  # failure codes as compile-time constants


@inline_kernel
def start_particle(Y, body, t_end, rates, w):
    """(stays, code) for the particle ``Y (11, 3)``: code the failure code of its initial state; it
    stays where it is if that failed or it has no time to go (t_end ≤ 0), else its rates f(Y) are
    written into ``rates (11, 3)``, the first step's."""
    code = state_failure(Y)
    stays = code != _OK or t_end <= 0.0
    if not stays:
        body_rates(Y, body, rates, w)
    return stays, code


@inline_kernel
def next_step(t, h, t_end, attempts, max_steps):
    """(code, final, h) of the step to try from t after ``attempts`` (accepted and rejected): code
    BUDGET once they reach max_steps, else OK with h, or t_end − t where t + h reaches t_end (final:
    the last step lands on t_end exactly)."""
    if attempts >= max_steps:
        return _BUDGET, False, h
    final = t + h >= t_end
    return _OK, final, (t_end - t if final else h)
