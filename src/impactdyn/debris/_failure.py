"""Per-particle failure codes of the integrators, and the check of a state (docs/theory/debris.md)."""

from __future__ import annotations

import math
from enum import IntEnum

from impactdyn.debris._particle import F_ROWS, STATE_ROWS, det3, inline_kernel


class Failure(IntEnum):
    """Per-particle outcome of an integration."""

    OK = 0
    STEP_UNDERFLOW = 1   # adaptive step fell below its minimum
    NAN = 2              # a state component is NaN or infinite
    INVERTED = 3         # det F ≤ 0: the tetrahedron turned inside out
    STEP_BUDGET = 4      # max_steps reached before t_end


# The codes as plain ints, compile-time constants in the kernels.
OK, UNDERFLOW, NAN, INVERTED, BUDGET = (int(c) for c in Failure)


@inline_kernel
def state_failure(Y):
    """Failure code of a state ``Y (11, 3)``: NAN if a component is not finite, INVERTED if det F ≤ 0."""
    for r in range(STATE_ROWS):
        for k in range(3):
            if not math.isfinite(Y[r, k]):
                return NAN
    if det3(Y[F_ROWS]) <= 0.0:
        return INVERTED
    return OK
