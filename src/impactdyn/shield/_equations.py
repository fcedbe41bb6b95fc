"""SPH equations of motion and their time integration (updated Lagrangian, 3-D): the compiled kernels.

The solver that calls them step by step is :mod:`._integrate`; the coefficients
(α, β, ε, n, κ, C_cfl, C_f, …) are :class:`._options.SPHOptions`, where their defaults live.

Discrete equations (Libersky & Petschek 1991, 1993; Monaghan 1992, 2005; Gray,
Monaghan & Swift 2001), with σ = −pI + S, ∇ᵢWᵢⱼ = ∇ᵢW(xᵢ − xⱼ, hᵢⱼ),
hᵢⱼ = (hᵢ + hⱼ)/2, vᵢⱼ = vᵢ − vⱼ and the pair tensor::

    Tᵢⱼ = σᵢ/ρᵢ² + σⱼ/ρⱼ² − Πᵢⱼ I + (Rᵢ + Rⱼ) fᵢⱼⁿ

    dρᵢ/dt      = Σⱼ mⱼ vᵢⱼ · ∇ᵢWᵢⱼ                    (continuity)
    dvᵢ/dt      = Σⱼ mⱼ Tᵢⱼ · ∇ᵢWᵢⱼ                     (momentum)
    deᵢ/dt      = −½ Σⱼ mⱼ vᵢⱼ · Tᵢⱼ · ∇ᵢWᵢⱼ            (energy)
    ∂vᵢ^α/∂x^β  = −Σⱼ (mⱼ/ρⱼ) vᵢⱼ^α ∂_βWᵢⱼ               (velocity gradient, for the Jaumann rate)

Tᵢⱼ = Tⱼᵢ and ∇ᵢWᵢⱼ = −∇ⱼWⱼᵢ, so pair forces are equal and opposite (the force
loop :func:`pair_sums` evaluates each pair once and applies it to both): the total
momentum changes only by round-off, and d/dt Σ mᵢ(½vᵢ² + eᵢ) = 0 exactly in the
semi-discrete equations (the energy equation is the compatible one). Boundary
images (:mod:`._neighbours`) enter the sums as neighbours j with the mirrored or
shifted state; the force of i's image on j mirrors the force of j's image on i,
so a symmetry plane x = c conserves the y and z momentum exactly (it exchanges
x-momentum with the mirror half, as it must) and periodic axes conserve all three.

* Artificial viscosity (Monaghan 1992, eq. 4.1), for vᵢⱼ·xᵢⱼ < 0::

      Πᵢⱼ = f̄ᵢⱼ (−α c̄ᵢⱼ μᵢⱼ + β μᵢⱼ²)/ρ̄ᵢⱼ,   μᵢⱼ = hᵢⱼ vᵢⱼ·xᵢⱼ / (|xᵢⱼ|² + 0.01 hᵢⱼ²)

  defaults α = 1, β = 2 (a strong-shock setting; the linear term damps the
  post-shock ringing, the quadratic one prevents interpenetration).  f̄ᵢⱼ = ½(fᵢ + fⱼ): 1 by default;
  with ``viscosity_switch = "balsara"`` the factor of :func:`viscosity_switch` from the previous
  step's velocity gradient (1 before the first), which confines the viscosity's heating to
  converging flow.
* Artificial stress Rᵢ (:mod:`._strength`) with fᵢⱼ = W(rᵢⱼ, hᵢⱼ)/W(hᵢⱼ/κ, hᵢⱼ)
  (the initial spacing Δp = h/κ), defaults ε = 0.3, n = 4 (Gray, Monaghan &
  Swift 2001).
* Density by the continuity equation, not by summation: summation density is
  deficient within 2h of free surfaces and smears the density jump at the
  projectile–plate interface, both of which are everywhere in a thin-plate
  perforation; the continuity form starts from ρ₀ everywhere and needs no
  surface correction (Libersky & Petschek 1993). It is integrated for ln ρ
  (rate ρ̇ᵢ/ρᵢ, exponential update) under a step limit on the relative density
  change (below), which keeps ρ > 0 however fast failed debris expands: the
  linear update ρ + Δt ρ̇ drove a particle of the 10 km/s Table 2 shot to a
  negative density. Below ρ₀/h_max_factor³ (where h stops growing) the rate is
  ρ̇ᵢ/(ρ₀/h_max_factor³): such a particle is failed debris in free flight with
  p = 0, and ρ̇ᵢ/ρᵢ of a nearly empty particle meeting a neighbour collapsed the
  step (Table 2 shot 10b, 2.8 µs).
* Smoothing length hᵢ = κ (mᵢ/ρᵢ)^{1/3} — the exact integral of
  dh/dt = −(h/3)(dρ/dt)/ρ — with ρ floored at ρ₀/h_max_factor³ so that h grows
  at most h_max_factor-fold in expanding debris.
* Failure and damage (``failure_model``): each particle carries a damage D ∈ [0, 1]; it carries
  the tension (1 − D) p for p < 0 and the deviator (1 − D) S, compression whole; D = 1 is failed
  for good (p ≥ 0, S = 0). ``"threshold"``: D jumps to 1 when p < −p_spall or εₚ > εₚ,f (the
  elongation at break, reached by compressive flow as readily as by tension). ``"fragmentation"``
  (:mod:`._damage`): D grows at a bounded rate under tension from Weibull flaws (Grady–Kipp,
  Benz–Asphaug), and Johnson–Cook ductile damage, which does not accumulate in compression, sets
  D = 1 when it reaches 1; intact regions stay cohesive and become the fragments at hand-off.
  Failed material expands freely, and its continuity density falls with the local divergence: in a
  fragment cloud a particle's density is the bulk density of the cloud around it (the binning's
  mass and bulk density (1 − φ)ρ are unaffected by this).

Time integration: kick–drift–kick leapfrog with a predicted state for the force
evaluation, one neighbour-list update (a search only once the particles have
moved through the list's skin, :mod:`._neighbours`) and one force pass per step
(Springel 2005 GADGET-2 §5 form)::

    v^{n+½} = vⁿ + ½Δt aⁿ,    xⁿ⁺¹ = xⁿ + Δt v^{n+½}
    predictor:  v* = v^{n+½} + ½Δt aⁿ,
                (e, S)* = (e, S)ⁿ + Δt (ė, Ṡ)ⁿ, ρ* = ρⁿ exp(Δt (ρ̇/ρ)ⁿ), S* returned to the yield surface
    rates at xⁿ⁺¹ and the predicted state → aⁿ⁺¹, (ρ̇/ρ, ė, Ṡ)ⁿ⁺¹
    corrector:  vⁿ⁺¹ = v^{n+½} + ½Δt aⁿ⁺¹,
                (e, S)ⁿ⁺¹ = (e, S)ⁿ + ½Δt [(ė, Ṡ)ⁿ + (ė, Ṡ)ⁿ⁺¹],
                ρⁿ⁺¹ = ρⁿ exp(½Δt [(ρ̇/ρ)ⁿ + (ρ̇/ρ)ⁿ⁺¹]),
                radial return of Sⁿ⁺¹ (accumulating εₚ), failure check

Each kick adds Σ mᵢ aᵢ Δt/2 = 0, so momentum is conserved to round-off at any Δt.
Time step (Monaghan 1992, eq. 4.12)::

    Δt = min_i min( C_cfl hᵢ / (cᵢ + 1.2 (α cᵢ + β maxⱼ|μᵢⱼ|)),  C_f √(hᵢ/|aᵢ|),  C_cfl ρᵢ/|ρ̇ᵢ| )

the relative velocity of approaching neighbours entering through μᵢⱼ
(defaults C_cfl = 0.3, C_f = 0.25); the last term bounds the density change of
a step (it binds only in fast expansion, where the first two do not see the flow).

The kernels take their data as records (NamedTuples, which numba passes like their fields), made
once by the solver (:class:`._integrate._Solver`): the particles' :class:`ParticleState`; the
:class:`Rates` of a force pass, the step's and the next step's; the :class:`Predicted` state; what
a state gives each particle, :class:`Derived` (p, c, h, R); the pair loop's :class:`PairRows`; the
:class:`Materials` with the constitutive models; and the run's :class:`Coefficients`. Two
properties of numba's parallel loops (numba 0.68) decide how a ``prange`` loop reaches them. Its
dead-code removal drops the loop's writes to an array reached through a record's field inside the
loop, or taken out of a record by a tuple unpacking (``a, b, c, d = r.a, r.b, r.c, r.d``; Python
assigns up to three targets without a tuple): it does not see that such an array is the caller's
(numba's report "Miscompiled parallel access to namedtuple"). And where it finds no aliasing in
the loop, it compiles the loop's body with every array taken to overlap no other, so one array
reached under two names, one of them written, may be read stale. So a parallel kernel takes each
array its loop writes out of its record by attribute before the loop, at most three to a
statement, and the loop and the helpers it calls reach that array by that name alone; a record
reaches into the loop only if the loop writes none of its arrays (:class:`PairRows` where the loop
only reads the rows, :class:`Materials`, :class:`Coefficients`).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import get_thread_id, njit, prange

from impactdyn.constitutive import (C0, DM_GROWTH, DM_K, DM_M, DM_YOUNG, EPS_FAIL, GAMMA0, HAS_JC, JC_RATE0, JC_TMELT,
                                   JC_TROOM, P_SPALL, RHO0, SHEAR, SLOPE, artificial_stress, ductile_damage_increment,
                                   flow_stress, grady_kipp_damage, jaumann_rate, largest_principal_stress, pressure,
                                   radial_return, sound_speed, temperature, von_mises)
from impactdyn.shield._kernel import SIGMA_3D, g_shape, w_shape

#: Failure models of the kernels (:class:`._options.SPHOptions` ``failure`` and ``failure_model``).
NO_FAILURE, THRESHOLD, FRAGMENTATION = 0, 1, 2


class ParticleState(NamedTuple):
    """The particles' state, a row per particle in the solver's order (:class:`._integrate._Solver`).

    x, v (N, 3): position, cm, and velocity, cm/µs; m: mass, g; rho: density ρ, g/cm³; e: specific
    internal energy, cm²/µs²; S (N, 6): deviatoric stress, Mbar; eps_p: equivalent plastic strain εₚ;
    damage: D; ductile: the Johnson–Cook ductile damage sum; flaws (N, N_FLAW): the fragmentation
    model's flaw records (:mod:`._damage`); failure_rate: the stretching rate at failure, µs⁻¹
    (:func:`finish_step`); switch: the viscosity switch fᵢ of the next force pass; mat: the material
    index (int64).
    """

    x: np.ndarray
    v: np.ndarray
    m: np.ndarray
    rho: np.ndarray
    e: np.ndarray
    S: np.ndarray
    eps_p: np.ndarray
    damage: np.ndarray
    ductile: np.ndarray
    flaws: np.ndarray
    failure_rate: np.ndarray
    switch: np.ndarray
    mat: np.ndarray


class Rates(NamedTuple):
    """What a force pass gives for one state (:func:`_particle_rates`): the rates the leapfrog integrates,
    acc (N, 3), cm/µs², dlnrho = ρ̇/ρ, de = ė and dS (N, 6) = Ṡ (Jaumann); the velocity gradient
    grad_v (N, 3, 3) = L and the equivalent strain rate strain_rate = ε̇_eq, µs⁻¹, that they come from;
    and each particle's stable step dt, µs (module docstring)."""

    acc: np.ndarray
    dlnrho: np.ndarray
    de: np.ndarray
    dS: np.ndarray
    grad_v: np.ndarray
    strain_rate: np.ndarray
    dt: np.ndarray

    @classmethod
    def zeros(cls, n: int) -> "Rates":
        return cls(acc=np.zeros((n, 3)), dlnrho=np.zeros(n), de=np.zeros(n), dS=np.zeros((n, 6)),
                   grad_v=np.zeros((n, 3, 3)), strain_rate=np.zeros(n), dt=np.zeros(n))


class Predicted(NamedTuple):
    """The predicted state at the step's end, where the force pass is evaluated (module docstring):
    v (N, 3), rho, e (N,), S (N, 6)."""

    v: np.ndarray
    rho: np.ndarray
    e: np.ndarray
    S: np.ndarray

    @classmethod
    def zeros(cls, n: int) -> "Predicted":
        return cls(v=np.zeros((n, 3)), rho=np.zeros(n), e=np.zeros(n), S=np.zeros((n, 6)))


class Derived(NamedTuple):
    """What a particle's density, energy and deviatoric stress give it (:func:`_particle_eos`):
    pressure p, Mbar, sound speed c, cm/µs, smoothing length h, cm (N,); the artificial stress R (N, 6)
    and tension (N,) bool, whether R ≠ 0; and work_a, work_v (N, 3, 3), the scratch in which
    :func:`~impactdyn.constitutive.artificial_stress` finds σ's principal values and axes."""

    p: np.ndarray
    c: np.ndarray
    h: np.ndarray
    R: np.ndarray
    tension: np.ndarray
    work_a: np.ndarray
    work_v: np.ndarray

    @classmethod
    def zeros(cls, n: int) -> "Derived":
        return cls(p=np.zeros(n), c=np.zeros(n), h=np.zeros(n), R=np.zeros((n, 6)),
                   tension=np.zeros(n, dtype=np.bool_), work_a=np.zeros((n, 3, 3)), work_v=np.zeros((n, 3, 3)))


class PairRows(NamedTuple):
    """The pair loop's particle rows (:func:`_pair_row`): pos (N, 4) and st (N, ST_WIDTH)."""

    pos: np.ndarray
    st: np.ndarray

    @classmethod
    def zeros(cls, n: int) -> "PairRows":
        return cls(pos=np.zeros((n, 4)), st=np.zeros((n, ST_WIDTH)))


class Materials(NamedTuple):
    """The run's material tables and constitutive models: params, the materials' constants
    (:func:`~impactdyn.constitutive.pack_materials`); damage_table, the fragmentation model's
    (:func:`~impactdyn.constitutive.pack_damage`); johnson_cook: the Johnson–Cook flow stress
    (else Y₀); failure: NO_FAILURE, THRESHOLD or FRAGMENTATION."""

    params: np.ndarray
    damage_table: np.ndarray
    johnson_cook: bool
    failure: int


class Coefficients(NamedTuple):
    """The run's coefficients (:class:`._options.SPHOptions`) as the kernels use them: h_factor κ;
    rho_floor = 1/h_max_factor³, the density floor ρ₀/h_max_factor³ over ρ₀ (module docstring);
    the artificial stress's ε (artificial_stress, 0: none), n (artificial_stress_power) and
    1/W(Δp, h) (artificial_stress_norm, the norm of fᵢⱼ); the viscosity's α, β and balsara (the
    switch :func:`viscosity_switch` on); the step factors cfl = C_cfl and force_cfl = C_f."""

    h_factor: float
    rho_floor: float
    artificial_stress: float
    artificial_stress_power: int
    artificial_stress_norm: float
    alpha: float
    beta: float
    balsara: bool
    cfl: float
    force_cfl: float


# inline: a call passing this many arrays per particle costs more than the work (:mod:`._strength`)
@njit(cache=True, inline="always")
def _particle_eos(i, m, rho, e, S, damage, mat, materials, coefficients, R, work_a, work_v):
    """Pressure p, sound speed c and smoothing length h of particle i, and its artificial stress R[i];
    returns (p, c, h, whether R[i] ≠ 0).

    Damage D scales the tension a particle carries: p < 0 becomes (1 − D) p (compression is kept whole).
    """
    params = materials.params
    k = mat[i]
    rho0 = params[k, RHO0]
    p = pressure(rho[i], e[i], rho0, params[k, C0], params[k, SLOPE], params[k, GAMMA0])
    if p < 0.0:
        p *= 1.0 - damage[i]
    c = sound_speed(rho[i], p, rho0, params[k, C0], params[k, SLOPE], params[k, GAMMA0])
    h = coefficients.h_factor * (m[i] / max(rho[i], rho0 * coefficients.rho_floor)) ** (1.0 / 3.0)
    tension = False
    if coefficients.artificial_stress > 0.0:
        tension = artificial_stress(S, p, rho[i], coefficients.artificial_stress, i, R, work_a, work_v)
    return p, c, h, tension


@njit(parallel=True, cache=True)
def update_particles(state, derived, materials, coefficients):
    """The :class:`Derived` p, c, h and R of every particle of the state (:func:`_particle_eos`)."""
    p, c, h = derived.p, derived.c, derived.h
    R, tension = derived.R, derived.tension
    work_a, work_v = derived.work_a, derived.work_v
    m, rho, e, S, damage, mat = state.m, state.rho, state.e, state.S, state.damage, state.mat
    for i in prange(m.size):
        p[i], c[i], h[i], tension[i] = _particle_eos(i, m, rho, e, S, damage, mat, materials, coefficients, R,
                                                     work_a, work_v)


#: Columns of the pair-loop rows ``st`` (:func:`pair_rows`).
ST_V, ST_C, ST_RHO, ST_M, ST_VOL, ST_SWITCH, ST_SR, ST_WIDTH = 0, 3, 4, 5, 6, 7, 8, 16


@njit(cache=True, inline="always")
def _pair_row(i, x, h, v, c, rho, m, S, p, damage, switch, pos, st):
    """Row i of the pair loop's particle data (σ = −pI + (1 − D) S: damage D weakens the deviator).

    pos (N, 4): (x, y, z, h), what the support test reads for every listed pair;
    st (N, 16): v (3), c, ρ, m, m/ρ, the viscosity switch fᵢ, σ/ρ² (6; σ = −pI + S) in the columns
    ``ST_*`` (14, 15 unused), what an interacting pair reads. A neighbour j
    costs the pair loop a 32-byte and a 128-byte row instead of a cache line in
    each of nine per-quantity arrays, and σ/ρ² and m/ρ are formed once per
    particle, not once per pair.
    """
    for a in range(3):
        pos[i, a] = x[i, a]
        st[i, ST_V + a] = v[i, a]
    pos[i, 3] = h[i]
    st[i, ST_C] = c[i]
    st[i, ST_RHO] = rho[i]
    st[i, ST_M] = m[i]
    st[i, ST_VOL] = m[i] / rho[i]
    st[i, ST_SWITCH] = switch[i]
    q = 1.0 / (rho[i] * rho[i])
    intact = 1.0 - damage[i]
    for d in range(6):
        st[i, ST_SR + d] = (intact * S[i, d] - p[i] * (d < 3)) * q


@njit(parallel=True, cache=True)
def pair_rows(state, v, rho, S, derived, rows):
    """The pair loop's rows of every particle (:func:`_pair_row`), with the velocity v, density rho and
    deviatoric stress S given: the state's own, or the predicted ones."""
    pos, st = rows.pos, rows.st
    x, m, damage, switch = state.x, state.m, state.damage, state.switch
    p, c, h = derived.p, derived.c, derived.h
    for i in prange(m.size):
        _pair_row(i, x, h, v, c, rho, m, S, p, damage, switch, pos, st)


#: Columns of the per-thread pair sums (:func:`pair_sums`): Σ mⱼTᵢⱼ·∇ᵢWᵢⱼ (3), Σ mⱼvᵢⱼ·∇ᵢWᵢⱼ, ė,
#: L (9, row-major), max μ.
PS_A, PS_RHO, PS_E, PS_L, PS_MU, PS_WIDTH = 0, 3, 4, 5, 14, 16


# fastmath "contract" only: a·b + c may be fused into one rounding (FMA), nothing reordered (results move by round-off)
@njit(parallel=True, cache=True, fastmath={"contract"})
def pair_sums(rows, derived, nbr, img, count, signs, offsets, coefficients, sums):
    """The neighbour sums of the rates (module docstring), each pair of real particles evaluated once.

    rows: the :class:`PairRows` of :func:`pair_rows`; the artificial stress R (N, 6) and tension (N,)
    of ``derived``; nbr, img (N, cap), count (N,): the half neighbour list
    (:class:`NeighbourList` with ``half``), whose pairs beyond the support 2hᵢⱼ
    (its skin) are skipped; α, β and the artificial stress's n and norm of ``coefficients``.
    A pair of real particles (image 0) is listed once;
    its terms for j follow from those for i, since ∇ⱼWⱼᵢ = −∇ᵢWᵢⱼ, vⱼᵢ = −vᵢⱼ,
    Tⱼᵢ = Tᵢⱼ and μⱼᵢ = μᵢⱼ::

        aⱼ −= mᵢ Tᵢⱼ·∇ᵢWᵢⱼ,   ρ̇ⱼ += mᵢ vᵢⱼ·∇ᵢWᵢⱼ,   ėⱼ −= ½ mᵢ vᵢⱼ·Tᵢⱼ·∇ᵢWᵢⱼ,   Lⱼ −= (mᵢ/ρᵢ) vᵢⱼ ⊗ ∇ᵢWᵢⱼ

    An image pair (i, T(j)) is listed in i's row and its partner (j, T⁻¹(i)) in
    j's, each adding to its own particle only.

    sums (T, N, 16): per-thread partial sums (columns ``PS_*``), zero on entry;
    :func:`_particle_rates` adds them up and zeroes them again. Thread t adds to sums[t] only, so
    the scattered additions to j need no locks; prange gives each thread one
    contiguous range of i, so the result is the same for the same thread count.
    """
    pos, st = rows.pos, rows.st
    R, tension = derived.R, derived.tension
    alpha, beta = coefficients.alpha, coefficients.beta
    as_power, as_norm = coefficients.artificial_stress_power, coefficients.artificial_stress_norm
    for i in prange(pos.shape[0]):
        tid = get_thread_id()
        xi0, xi1, xi2, hi = pos[i, 0], pos[i, 1], pos[i, 2], pos[i, 3]
        vi0, vi1, vi2 = st[i, ST_V], st[i, ST_V + 1], st[i, ST_V + 2]
        ci, rhoi, mi, voli, fi = st[i, ST_C], st[i, ST_RHO], st[i, ST_M], st[i, ST_VOL], st[i, ST_SWITCH]
        axx, ayy, azz = st[i, ST_SR], st[i, ST_SR + 1], st[i, ST_SR + 2]
        axy, ayz, azx = st[i, ST_SR + 3], st[i, ST_SR + 4], st[i, ST_SR + 5]
        tension_i = tension[i]
        a0 = a1 = a2 = 0.0
        dr = du = 0.0
        l00 = l01 = l02 = l10 = l11 = l12 = l20 = l21 = l22 = 0.0
        mu_max = 0.0
        for k in range(count[i]):
            j = nbr[i, k]
            t = img[i, k]
            xj0, xj1, xj2 = pos[j, 0], pos[j, 1], pos[j, 2]
            if t != 0:  # the image T(xⱼ) = s ⊙ xⱼ + o
                xj0 = signs[t, 0] * xj0 + offsets[t, 0]
                xj1 = signs[t, 1] * xj1 + offsets[t, 1]
                xj2 = signs[t, 2] * xj2 + offsets[t, 2]
            dx0, dx1, dx2 = xi0 - xj0, xi1 - xj1, xi2 - xj2
            r2 = dx0 * dx0 + dx1 * dx1 + dx2 * dx2
            hij = 0.5 * (hi + pos[j, 3])
            if r2 >= 4.0 * hij * hij:
                continue
            # ∇ᵢWᵢⱼ = σ/h⁵ g(q) xᵢⱼ (:mod:`._kernel`), one division for 1/h
            ih = 1.0 / hij
            q = math.sqrt(r2) * ih
            ih2 = ih * ih
            f = SIGMA_3D * ih2 * ih2 * ih * g_shape(q)
            g0, g1, g2 = f * dx0, f * dx1, f * dx2
            vj0, vj1, vj2 = st[j, ST_V], st[j, ST_V + 1], st[j, ST_V + 2]
            bxx, byy, bzz = st[j, ST_SR], st[j, ST_SR + 1], st[j, ST_SR + 2]
            bxy, byz, bzx = st[j, ST_SR + 3], st[j, ST_SR + 4], st[j, ST_SR + 5]
            s01 = s12 = s20 = 1.0
            if t != 0:  # the image's velocity s ⊙ vⱼ and σⱼ/ρⱼ², whose components (α, β) pick up s_α s_β
                vj0, vj1, vj2 = signs[t, 0] * vj0, signs[t, 1] * vj1, signs[t, 2] * vj2
                s01, s12, s20 = signs[t, 0] * signs[t, 1], signs[t, 1] * signs[t, 2], signs[t, 2] * signs[t, 0]
                bxy, byz, bzx = s01 * bxy, s12 * byz, s20 * bzx
            dv0, dv1, dv2 = vi0 - vj0, vi1 - vj1, vi2 - vj2
            vr = dv0 * dx0 + dv1 * dx1 + dv2 * dx2
            visc = mu = 0.0
            if vr < 0.0:
                mu = hij * vr / (r2 + 0.01 * hij * hij)
                visc = ((-alpha * 0.5 * (ci + st[j, ST_C]) * mu + beta * mu * mu) * 0.5 * (fi + st[j, ST_SWITCH])
                        / (0.5 * (rhoi + st[j, ST_RHO])))
                mu_max = max(mu_max, -mu)
            txx = axx + bxx - visc
            tyy = ayy + byy - visc
            tzz = azz + bzz - visc
            txy = axy + bxy
            tyz = ayz + byz
            tzx = azx + bzx
            if tension_i or tension[j]:
                fn = 1.0
                fij = w_shape(q) * as_norm
                for _ in range(as_power):
                    fn *= fij
                txx += (R[i, 0] + R[j, 0]) * fn
                tyy += (R[i, 1] + R[j, 1]) * fn
                tzz += (R[i, 2] + R[j, 2]) * fn
                txy += (R[i, 3] + s01 * R[j, 3]) * fn
                tyz += (R[i, 4] + s12 * R[j, 4]) * fn
                tzx += (R[i, 5] + s20 * R[j, 5]) * fn
            tg0 = txx * g0 + txy * g1 + tzx * g2
            tg1 = txy * g0 + tyy * g1 + tyz * g2
            tg2 = tzx * g0 + tyz * g1 + tzz * g2
            vtg = dv0 * tg0 + dv1 * tg1 + dv2 * tg2
            vg = dv0 * g0 + dv1 * g1 + dv2 * g2
            mj, volj = st[j, ST_M], st[j, ST_VOL]
            a0 += mj * tg0
            a1 += mj * tg1
            a2 += mj * tg2
            du -= 0.5 * mj * vtg
            dr += mj * vg
            l00 -= volj * dv0 * g0
            l01 -= volj * dv0 * g1
            l02 -= volj * dv0 * g2
            l10 -= volj * dv1 * g0
            l11 -= volj * dv1 * g1
            l12 -= volj * dv1 * g2
            l20 -= volj * dv2 * g0
            l21 -= volj * dv2 * g1
            l22 -= volj * dv2 * g2
            if t == 0:  # the pair's terms for j
                sums[tid, j, PS_A] -= mi * tg0
                sums[tid, j, PS_A + 1] -= mi * tg1
                sums[tid, j, PS_A + 2] -= mi * tg2
                sums[tid, j, PS_RHO] += mi * vg
                sums[tid, j, PS_E] -= 0.5 * mi * vtg
                sums[tid, j, PS_L] -= voli * dv0 * g0
                sums[tid, j, PS_L + 1] -= voli * dv0 * g1
                sums[tid, j, PS_L + 2] -= voli * dv0 * g2
                sums[tid, j, PS_L + 3] -= voli * dv1 * g0
                sums[tid, j, PS_L + 4] -= voli * dv1 * g1
                sums[tid, j, PS_L + 5] -= voli * dv1 * g2
                sums[tid, j, PS_L + 6] -= voli * dv2 * g0
                sums[tid, j, PS_L + 7] -= voli * dv2 * g1
                sums[tid, j, PS_L + 8] -= voli * dv2 * g2
                sums[tid, j, PS_MU] = max(sums[tid, j, PS_MU], -mu)
        sums[tid, i, PS_A] += a0
        sums[tid, i, PS_A + 1] += a1
        sums[tid, i, PS_A + 2] += a2
        sums[tid, i, PS_RHO] += dr
        sums[tid, i, PS_E] += du
        sums[tid, i, PS_L] += l00
        sums[tid, i, PS_L + 1] += l01
        sums[tid, i, PS_L + 2] += l02
        sums[tid, i, PS_L + 3] += l10
        sums[tid, i, PS_L + 4] += l11
        sums[tid, i, PS_L + 5] += l12
        sums[tid, i, PS_L + 6] += l20
        sums[tid, i, PS_L + 7] += l21
        sums[tid, i, PS_L + 8] += l22
        sums[tid, i, PS_MU] = max(sums[tid, i, PS_MU], mu_max)


@njit(cache=True, inline="always")
def _particle_rates(i, rows, S, damage, mat, materials, coefficients, sums, grad_v, acc, dS, switch):
    """The rates of particle i from the pair sums (T, N, 16) of :func:`pair_sums`, whose rows of i it zeroes.

    Writes acc[i] (3), grad_v[i] = L (3, 3), dS[i] = Ṡ (6, Jaumann) and, with ``balsara``, the viscosity
    switch switch[i] of the next force pass (:func:`viscosity_switch`); returns (ρ̇/ρ, ė, ε̇_eq, the stable
    step Δtᵢ (module docstring)), the :class:`Rates` its caller writes.
    """
    for t in range(1, sums.shape[0]):  # the other threads' partial sums into sums[0, i]
        for c in range(PS_MU):
            sums[0, i, c] += sums[t, i, c]
            sums[t, i, c] = 0.0
        sums[0, i, PS_MU] = max(sums[0, i, PS_MU], sums[t, i, PS_MU])
        sums[t, i, PS_MU] = 0.0
    params = materials.params
    hi, ci, rhoi = rows.pos[i, 3], rows.st[i, ST_C], rows.st[i, ST_RHO]
    a0, a1, a2 = sums[0, i, PS_A], sums[0, i, PS_A + 1], sums[0, i, PS_A + 2]
    acc[i, 0], acc[i, 1], acc[i, 2] = a0, a1, a2
    dlnrho = sums[0, i, PS_RHO] / max(rhoi, params[mat[i], RHO0] * coefficients.rho_floor)
    de = sums[0, i, PS_E]
    for r in range(3):
        for c in range(3):
            grad_v[i, r, c] = sums[0, i, PS_L + 3 * r + c]
    mu_max = sums[0, i, PS_MU]
    for c in range(PS_WIDTH):
        sums[0, i, c] = 0.0
    if coefficients.balsara:
        switch[i] = viscosity_switch(grad_v, i, ci, hi)
    ds, strain_rate = jaumann_rate(S[i, 0], S[i, 1], S[i, 2], S[i, 3], S[i, 4], S[i, 5], grad_v, i,
                                   params[mat[i], SHEAR])
    for k in range(6):
        dS[i, k] = 0.0 if damage[i] >= 1.0 else ds[k]
    amag = math.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
    cfl = coefficients.cfl
    dt_i = cfl * hi / (ci + 1.2 * (coefficients.alpha * ci + coefficients.beta * mu_max))
    if amag > 0.0:
        dt_i = min(dt_i, coefficients.force_cfl * math.sqrt(hi / amag))
    if dlnrho != 0.0:
        dt_i = min(dt_i, cfl / abs(dlnrho))
    return dlnrho, de, strain_rate, dt_i


@njit(parallel=True, cache=True)
def particle_rates(state, rows, materials, coefficients, sums, rates):
    """The :class:`Rates` of every particle of the state from the pair sums (:func:`_particle_rates`)."""
    acc, dlnrho, de = rates.acc, rates.dlnrho, rates.de
    dS, grad_v = rates.dS, rates.grad_v
    strain_rate, dt = rates.strain_rate, rates.dt
    switch = state.switch
    S, damage, mat = state.S, state.damage, state.mat
    for i in prange(mat.size):
        dlnrho[i], de[i], strain_rate[i], dt[i] = _particle_rates(i, rows, S, damage, mat, materials, coefficients,
                                                                  sums, grad_v, acc, dS, switch)


@njit(parallel=True, cache=True)
def kick_drift_predict(state, rates, predicted, derived, rows, materials, coefficients, dt):
    """Half kick v ← v + ½Δt a, drift x ← x + Δt v, and the predicted state at the step's end.

    Predicted: v_p = v + ½Δt a, (e, S)_p = (e, S) + Δt (ė, Ṡ), ρ_p = ρ exp(Δt ρ̇/ρ), S_p returned to the
    yield surface; then its p, c, h and R (:func:`_particle_eos`) and its pair-loop rows (:func:`_pair_row`).
    """
    x, v = state.x, state.v
    v_p, rho_p, e_p = predicted.v, predicted.rho, predicted.e
    S_p = predicted.S
    p, c, h = derived.p, derived.c, derived.h
    R, tension = derived.R, derived.tension
    work_a, work_v = derived.work_a, derived.work_v
    pos, st = rows.pos, rows.st
    m, rho, e, S, eps_p, damage, switch, mat = (state.m, state.rho, state.e, state.S, state.eps_p, state.damage,
                                                state.switch, state.mat)
    acc, dlnrho, de, dS, rate = rates.acc, rates.dlnrho, rates.de, rates.dS, rates.strain_rate
    params, johnson_cook = materials.params, materials.johnson_cook
    for i in prange(m.size):
        k = mat[i]
        for d in range(3):
            v[i, d] += 0.5 * dt * acc[i, d]
            x[i, d] += dt * v[i, d]
            v_p[i, d] = v[i, d] + 0.5 * dt * acc[i, d]
        rho_p[i] = rho[i] * math.exp(dt * dlnrho[i])
        e_p[i] = e[i] + dt * de[i]
        for d in range(6):
            S_p[i, d] = S[i, d] + dt * dS[i, d]
        Y = flow_stress(params, k, johnson_cook, eps_p[i], rate[i], temperature(rho_p[i], e_p[i], params, k))
        radial_return(S_p, i, Y, params[k, SHEAR])
        p[i], c[i], h[i], tension[i] = _particle_eos(i, m, rho_p, e_p, S_p, damage, mat, materials, coefficients, R,
                                                     work_a, work_v)
        _pair_row(i, x, h, v_p, c, rho_p, m, S_p, p, damage, switch, pos, st)


@njit(parallel=True, cache=True)
def finish_step(state, rates, new_rates, predicted, rows, sums, materials, coefficients, dt):
    """The :class:`Rates` at the step's end (:func:`_particle_rates` of the predicted state) into
    ``new_rates``, then the corrector.

    Corrector: second half kick with the new acceleration, trapezoidal ln ρ, e, S of the old and new rates,
    radial return (εₚ), failure (the criteria judge the corrected stress undamaged: ``THRESHOLD`` fails a
    particle, D = 1, once p < −p_spall or εₚ > εₚ,f, the material's elongation at break;
    ``FRAGMENTATION``: :func:`_fragmentation_damage`); a failed particle records its largest stretching rate
    (:func:`largest_stretching_rate`) in failure_rate on the first step it is failed and expanded beyond its
    reference density (at failure for one that failed in tension; when it expands for one that failed
    compressed).
    """
    v, rho, e = state.v, state.rho, state.e
    S, eps_p, damage = state.S, state.eps_p, state.damage
    ductile, flaws, failure_rate = state.ductile, state.flaws, state.failure_rate
    switch = state.switch
    acc_new, dlnrho_new, de_new = new_rates.acc, new_rates.dlnrho, new_rates.de
    dS_new, grad_v = new_rates.dS, new_rates.grad_v
    rate, dt_i = new_rates.strain_rate, new_rates.dt
    m, mat, S_p, dlnrho, de, dS = state.m, state.mat, predicted.S, rates.dlnrho, rates.de, rates.dS
    params, johnson_cook, failure = materials.params, materials.johnson_cook, materials.failure
    for i in prange(m.size):
        dlnrho_new[i], de_new[i], rate[i], dt_i[i] = _particle_rates(i, rows, S_p, damage, mat, materials,
                                                                     coefficients, sums, grad_v, acc_new, dS_new,
                                                                     switch)
        k = mat[i]
        for d in range(3):
            v[i, d] += 0.5 * dt * acc_new[i, d]
        rho[i] *= math.exp(0.5 * dt * (dlnrho[i] + dlnrho_new[i]))
        e[i] += 0.5 * dt * (de[i] + de_new[i])
        for d in range(6):
            S[i, d] += 0.5 * dt * (dS[i, d] + dS_new[i, d])
        T = temperature(rho[i], e[i], params, k)
        Y = flow_stress(params, k, johnson_cook, eps_p[i], rate[i], T)
        plastic = radial_return(S, i, Y, params[k, SHEAR])
        eps_p[i] += plastic
        if failure != NO_FAILURE and damage[i] < 1.0:
            pi = pressure(rho[i], e[i], params[k, RHO0], params[k, C0], params[k, SLOPE], params[k, GAMMA0])
            if failure == THRESHOLD:
                if pi < -params[k, P_SPALL] or eps_p[i] > params[k, EPS_FAIL]:
                    damage[i] = 1.0
            else:
                _fragmentation_damage(i, k, pi, plastic, T, S, rate, materials, flaws, ductile, damage, dt)
        if damage[i] >= 1.0 and failure_rate[i] == 0.0 and rho[i] < params[k, RHO0]:
            failure_rate[i] = largest_stretching_rate(grad_v, i)
        if damage[i] >= 1.0:
            for d in range(6):
                S[i, d] = 0.0


@njit(cache=True, inline="always")
def viscosity_switch(L, i, c, h):
    """Balsara's factor restricted to converging flow, of particle i from its velocity gradient L[i]::

        fᵢ = max(−∇·v, 0) / (|∇·v| + |∇×v| + 10⁻⁴ cᵢ/hᵢ)

    1 in a shock (compression without rotation), → 0 in shear (|∇×v| ≫ |∇·v|; Balsara, J. Comput. Phys.
    121 (1995) 357) and 0 where the flow expands (∇·v ≥ 0: a rarefaction, failed debris flying apart),
    where a shock cannot be, as Cullen & Dehnen's shock indicator (MNRAS 408 (2010) 669) is zero there.
    Monaghan's Πᵢⱼ already vanishes for receding pairs; what this takes away is the heat it made in
    approaching pairs of a shearing or expanding flow.
    """
    div = L[i, 0, 0] + L[i, 1, 1] + L[i, 2, 2]
    wx, wy, wz = L[i, 2, 1] - L[i, 1, 2], L[i, 0, 2] - L[i, 2, 0], L[i, 1, 0] - L[i, 0, 1]
    return max(-div, 0.0) / (abs(div) + math.sqrt(wx * wx + wy * wy + wz * wz) + 1.0e-4 * c / h)


@njit(cache=True, inline="always")
def largest_stretching_rate(L, i):
    """max(0, d₁), d₁ the largest principal value of the rate of deformation d = ½(L + Lᵀ) of particle i
    (µs⁻¹): how fast the material stretches where it opens; 0 where it is compressed in every direction."""
    dxx, dyy, dzz = L[i, 0, 0], L[i, 1, 1], L[i, 2, 2]
    mean = (dxx + dyy + dzz) / 3.0
    d1 = largest_principal_stress(-mean, dxx - mean, dyy - mean, dzz - mean, 0.5 * (L[i, 0, 1] + L[i, 1, 0]),
                                  0.5 * (L[i, 1, 2] + L[i, 2, 1]), 0.5 * (L[i, 2, 0] + L[i, 0, 2]))
    return max(d1, 0.0)


@njit(cache=True, inline="always")
def _fragmentation_damage(i, k, p, plastic, T, S, rate, materials, flaws, ductile, damage, dt):
    """``FRAGMENTATION`` (:mod:`._damage`): the damage D of particle i (material k) at the step's end, from
    its corrected (undamaged) stress — pressure p and deviator S[i] — its plastic strain increment, temperature
    T and equivalent strain rate rate[i].

    Tensile damage (:func:`~impactdyn.constitutive.grady_kipp_damage`) under the strain ε = σ₁/E of the
    largest principal stress σ₁, and ductile damage (:func:`~impactdyn.constitutive.ductile_damage_increment`,
    none below σ* = −1/3) whose sum reaching 1 sets D = 1.
    """
    params, dtable = materials.params, materials.damage_table
    sigma1 = largest_principal_stress(p, S[i, 0], S[i, 1], S[i, 2], S[i, 3], S[i, 4], S[i, 5])
    tensile = grady_kipp_damage(flaws, i, sigma1 / dtable[k, DM_YOUNG], dtable[k, DM_K], dtable[k, DM_M],
                                dtable[k, DM_GROWTH], dt)
    damage[i] = max(damage[i], tensile)
    sigma_eq = von_mises(S, i)
    if plastic > 0.0 and sigma_eq > 0.0:  # yielding; σ_eq = Y is 0 at melt (Johnson–Cook), where σ* is undefined
        rate_ratio, tstar = 1.0, 0.0
        if params[k, HAS_JC] != 0.0:
            rate_ratio = rate[i] / params[k, JC_RATE0]
            tstar = min(max((T - params[k, JC_TROOM]) / (params[k, JC_TMELT] - params[k, JC_TROOM]), 0.0), 1.0)
        ductile[i] += ductile_damage_increment(dtable, k, plastic, -p / sigma_eq, rate_ratio, tstar)
        if ductile[i] >= 1.0:
            damage[i] = 1.0


@njit(parallel=True, cache=True)
def temperatures(rho, e, mat, params):
    """Temperature estimate of every particle (:func:`impactdyn.constitutive.temperature`), K."""
    T = np.empty(rho.size)
    for i in prange(rho.size):
        T[i] = temperature(rho[i], e[i], params, mat[i])
    return T


@njit(parallel=True, cache=True)
def totals(state):
    """(Σm, Σm vₓ, Σm v_y, Σm v_z, Σ ½m|v|², Σ m e) of the state."""
    m, v, e = state.m, state.v, state.e
    mass = px = py = pz = kin = internal = 0.0
    for i in prange(m.size):
        mass += m[i]
        px += m[i] * v[i, 0]
        py += m[i] * v[i, 1]
        pz += m[i] * v[i, 2]
        kin += 0.5 * m[i] * (v[i, 0] ** 2 + v[i, 1] ** 2 + v[i, 2] ** 2)
        internal += m[i] * e[i]
    return mass, px, py, pz, kin, internal
