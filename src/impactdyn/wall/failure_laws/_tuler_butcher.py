"""Failure law ``"tuler_butcher"``: Tuler–Butcher cumulative spall damage of the mean tension (the default).

Tuler & Butcher, Int. J. Fract. Mech. 4 (1968) 431 (:func:`impactdyn.constitutive.tuler_butcher_increment`)::

    ∫ max(0, σ_t − σ₀)^λ dt ≥ K,   σ_t = −p (the mean tension)

integrated by the trapezoidal rule over each step from the pressures at its start and end, in the
element's column ``SPALL_DAMAGE``; the element fails (cause ``"spall_damage"``) when the integral
reaches K.  Constants: :attr:`impactdyn.materials.Material.tuler_butcher` (σ₀, λ, K; the library's are a
documented fallback scaled from the spall strengths, not published Tuler–Butcher constants: uncertain).
Why the mean tension and not the largest principal stress: :mod:`impactdyn.wall._johnson_cook`.
"""

from numba import njit

from impactdyn.constitutive import tuler_butcher_increment
from impactdyn.wall._failure_law import FAILURE_LAWS, J_LAW, FailureLaw
from impactdyn.wall._state import SPALL_DAMAGE

#: The law's constants in the model's parameter vector: σ₀ (Mbar), λ, K (Mbar^λ·µs).
J_SIGMA0, J_LAMBDA, J_K = J_LAW, J_LAW + 1, J_LAW + 2


@njit(cache=True, inline="always")
def accumulate(e, p_old, p_new, dt, es, table, prm):
    """The damage integral's increment over the step, σ_t = −p."""
    es[e, SPALL_DAMAGE] += tuler_butcher_increment(-p_old, -p_new, prm[J_SIGMA0], prm[J_LAMBDA], dt)


@njit(cache=True, inline="always")
def fails(e, p_new, es, table, prm):
    """The integral has reached K."""
    return es[e, SPALL_DAMAGE] >= prm[J_K]


def _describe(tb):
    return {"sigma0_Mbar": tb.sigma0, "lambda": tb.lam, "K_Mbar_lambda_us": tb.K, "source": tb.source}


TULER_BUTCHER = FailureLaw(
    name="tuler_butcher",
    description="Tuler-Butcher cumulative damage of the mean tension over a threshold (Tuler & Butcher 1968)",
    cause="spall_damage", accumulate=accumulate, fails=fails,
    library_constants=lambda material: material.tuler_butcher,
    kernel_constants=lambda tb: (tb.sigma0, tb.lam, tb.K),
    describe=_describe, describe_key="tuler_butcher", required=True, needs="Tuler-Butcher constants")

FAILURE_LAWS.register(TULER_BUTCHER.name, TULER_BUTCHER)
