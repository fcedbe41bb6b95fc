"""Failure law ``"cutoff"``: the instantaneous pressure cut-off.

p < −p_spall fails the element at once (cause ``"tensile_pressure"``), with no time scale; p_spall is the
material's spall strength (:attr:`impactdyn.materials.Material.spall_strength`; Kanel et al. 2004), read
from the packed material table.  A material without a spall strength runs without a spall criterion.
The Tuler–Butcher law (:mod:`._tuler_butcher`) tends to this one as K → 0 with σ₀ = p_spall.
"""

from numba import njit

from impactdyn.constitutive import P_SPALL
from impactdyn.wall._failure_law import FAILURE_LAWS, FailureLaw


@njit(cache=True, inline="always")
def accumulate(e, p_old, p_new, dt, es, table, prm):
    """No state: the law looks at the step's end only."""


@njit(cache=True, inline="always")
def fails(e, p_new, es, table, prm):
    """The mean tension exceeds the spall strength."""
    return p_new < -table[0, P_SPALL]


CUTOFF = FailureLaw(
    name="cutoff",
    description="instantaneous pressure cut-off p < -p_spall (the material's spall strength)",
    cause="tensile_pressure", accumulate=accumulate, fails=fails,
    library_constants=lambda material: material.spall_strength,
    kernel_constants=lambda spall_strength: (),
    describe=lambda spall_strength: spall_strength, describe_key="spall_strength_Mbar", required=False,
    needs="a spall strength")

FAILURE_LAWS.register(CUTOFF.name, CUTOFF)
