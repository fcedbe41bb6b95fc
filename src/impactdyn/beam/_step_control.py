"""Step-size control of the beam's Rosenbrock steps (``_integrator``).

The error of a step is the RMS norm of the embedded estimate over the dynamic state,
each component scaled by atol + rtol·max(|y₀|, |y₁|); a step with err ≤ 1 is accepted.
Either way the next step is the elementary controller's (Hairer, Nørsett & Wanner,
*Solving ODEs I*, §II.4, eq. (4.13))::

    h_new = h · min(max_factor, max(min_factor, safety · err^exponent)),

exponent = −1/(q + 1) with q = 3, the order of the embedded estimate (the step's error
is O(h^(q+1))). safety = 0.9 lies in the range 0.8–0.9 suggested there, and a step grows
at most five-fold (their facmax is 1.5–5) and shrinks at most five-fold; these are the
values the integrator was tuned and its benchmarks timed with. An error below 1e-10
counts as 1e-10, so that a step that happens to make no error grows by max_factor
instead of dividing by zero.
"""

from __future__ import annotations

from typing import NamedTuple

from numba import njit


class StepControl(NamedTuple):
    """The step control of one run: the error norm's tolerances ``rtol``, ``atol`` and the
    budget ``max_steps`` of accepted steps in the whole run (the case's ``solver`` table),
    and the controller's constants (module docstring); a rejected step shrunk below :func:`least_step`, or a
    step that would not advance the time, is a failure."""

    rtol: float
    atol: float
    max_steps: int
    safety: float = 0.9
    min_factor: float = 0.2
    max_factor: float = 5.0
    exponent: float = -0.25
    error_floor: float = 1e-10
    underflow: float = 1e-15


@njit(cache=True, inline="always")
def next_step(control, h, err):
    """The step after one of size h whose scaled error was ``err`` (module docstring)."""
    return h * min(control.max_factor, max(control.min_factor, control.safety * max(err, control.error_floor)
                                           ** control.exponent))


@njit(cache=True, inline="always")
def least_step(control, t):
    """The least step the control shrinks a rejected step to at time t, ``underflow`` · max(|t|, 1): at
    least four units in the last place of t (2.2e-16 |t|), so that the step still advances the time."""
    return control.underflow * max(abs(t), 1.0)
