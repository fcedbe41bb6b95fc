"""Column layout of the solver's per-element state arrays.

Element state lives in a few contiguous arrays, one row per element (the element kernel
reads and writes one row at a time):

* ``S`` (n_elements, 6) — deviatoric stress, components (xx, yy, zz, xy, yz, zx), Mbar;
* ``es`` (n_elements, N_ES) float64 — the scalars below;
* ``flags`` (n_elements, 2) uint8 — FAILED (0 intact, else the code of the criterion that failed
  the element, :data:`FAILURE_CAUSES`), ERODED;
* ``Lbuf`` (n_elements, 3, 3) — the midstep velocity gradient ∂v_i/∂x_j, 1/µs;
* ``Qhg`` (n_elements, 4, 3) — generalised hourglass forces Q_αi of the last step;
* ``Shg`` (n_blocks, N_SHG, BLOCK), element e at [e // BLOCK, :, e % BLOCK] (blocked like the element
  pass, :func:`impactdyn.wall._blocks.hourglass_stress_array`) — the assumed-strain form's hourglass
  stresses (Mbar), columns
  SHG_PLANE + 6k … SHG_PLANE + 6k + 5: the plane-stress tensor σ_k of group k = 0, 1, 2 in
  global axes (xx, yy, zz, xy, yz, zx), SHG_MODE4 + k: the uniaxial stress s_k of mode ξηζ
  along j_k (:func:`impactdyn.wall._hourglass.assumed_strain_forces`); no blocks with the other
  hourglass forms, which keep no stress.

The kernels take the state grouped in records (NamedTuples of arrays, which numba passes and
caches like arrays): :class:`Nodes`, :class:`Elements`, the model's :class:`MaterialConstants`,
the run's :class:`Controls` and the loads still to come (:class:`._load.NodalLoad`); and
:func:`stress_power`, the rates the material models' energy updates share.
"""

from typing import NamedTuple

import numpy as np
from numba import njit

#: Columns of ``es``: pressure p (Mbar), bulk viscosity q (Mbar), specific internal energy e
#: (cm²/µs²), effective plastic strain εₚ, damage D (Johnson–Cook D, or εₚ/ε_f for mat13),
#: equivalent deviatoric strain rate (1/µs), sound speed c (cm/µs), volume V (cm³), and the
#: work accumulated by the element's stress (σ = S − pI), bulk viscosity, hourglass forces and
#: plastic flow (g·cm²/µs²), its stable time step Δt_e (µs), and the powers f·v^{n−½} of its
#: current stress, bulk-viscosity and hourglass forces on the velocities they were computed with
#: (g·cm²/µs³, the first half of the next work increment, :mod:`._step`), and the spall damage
#: integral ∫ max(0, σ_t − σ₀)^λ dt of the Tuler–Butcher law (Mbar^λ·µs, :mod:`._johnson_cook`).
(P, Q, IE, EPS_P, DAMAGE, RATE, C, VOL, W_SIGMA, W_Q, W_HG, W_PLASTIC, DT_E, P1_SIGMA, P1_Q, P1_HG,
 SPALL_DAMAGE) = range(17)
N_ES = 17

#: Columns of ``Shg``: σ_k at SHG_PLANE + 6k (6 components each), s_k at SHG_MODE4 + k.
SHG_PLANE, SHG_MODE4 = 0, 18
N_SHG = 21

#: Columns of ``flags``.
FAILED, ERODED = 0, 1

#: The criteria that fail an element: ``flags[e, FAILED]`` = 1 + their index here.
#: ``ductile_damage``: Johnson–Cook damage reached 1; ``ductile_damage_at_floor``: the same, on a
#: step where the fit's fracture strain D1 + D2 exp(D3 σ*) was at or below the numerical floor
#: ε_f,min (a triaxiality beyond the fit's data: the floor of the material library, or with the
#: unbounded option the numerical 1e-6, where any plastic increment fails the element);
#: ``tensile_pressure``: p below the model's tensile limit (Johnson–Cook's cut-off spall law:
#: −p_spall; type 13: the card's failure pressure); ``plastic_strain``: εₚ reached the type-13
#: card's failure strain; ``spall_damage``: the Tuler–Butcher spall integral reached K.
FAILURE_CAUSES = ("ductile_damage", "ductile_damage_at_floor", "tensile_pressure", "plastic_strain", "spall_damage")
FAIL_DAMAGE, FAIL_DAMAGE_FLOOR, FAIL_TENSION, FAIL_STRAIN, FAIL_SPALL = (1 + i for i in range(len(FAILURE_CAUSES)))


@njit(cache=True, inline="always")
def stress_power(L, e, S, s0, s1, s2, s3, s4, s5):
    """tr d, S_old : d and S_new : d of element ``e``, d = ½(L + Lᵀ) its midstep rate of deformation.

    ``S_old`` = (s0 … s5) and ``S[e]`` (the updated deviatoric stress) in the order (xx, yy, zz,
    xy, yz, zx); the shear terms count twice (S : d = Σ_ij S_ij d_ij).  The trapezoidal mean of
    the two powers is the deviatoric work rate of the energy equation (Wilkins 1964).
    """
    dxx, dyy, dzz = L[e, 0, 0], L[e, 1, 1], L[e, 2, 2]
    dxy = 0.5 * (L[e, 0, 1] + L[e, 1, 0])
    dyz = 0.5 * (L[e, 1, 2] + L[e, 2, 1])
    dzx = 0.5 * (L[e, 2, 0] + L[e, 0, 2])
    sd_old = s0 * dxx + s1 * dyy + s2 * dzz + 2.0 * (s3 * dxy + s4 * dyz + s5 * dzx)
    sd_new = (S[e, 0] * dxx + S[e, 1] * dyy + S[e, 2] * dzz
              + 2.0 * (S[e, 3] * dxy + S[e, 4] * dyz + S[e, 5] * dzx))
    return dxx + dyy + dzz, sd_old, sd_new


class Nodes(NamedTuple):
    """The nodes: positions x and velocities v (n_nodes, 3), cm and cm/µs; lumped mass (n_nodes,), g;
    free (n_nodes, 3) 1.0 on free and 0.0 on fixed translations and fixed, the same as bool; pext
    (n_nodes, 3) the impulses due now, g·cm/µs; rear (n_nodes,) uint8, 1 on the rear face; category
    (n_nodes,) int8, the verdict's node categories (:mod:`._verdict`: 0 wall, 2 orphan)."""

    x: np.ndarray
    v: np.ndarray
    mass: np.ndarray
    free: np.ndarray
    fixed: np.ndarray
    pext: np.ndarray
    rear: np.ndarray
    category: np.ndarray


class Elements(NamedTuple):
    """The elements: connectivity conn (n_elements, 8), undeformed volume vol0 (cm³) and mass (g)
    (n_elements,); the state S, es, flags, Lbuf, Qhg, Shg (module docstring) and the breakdown
    marks ``bad`` (n_elements,) int8; the corner forces F (n_elements, 8, 3) and the same memory
    as F_flat (8 n_elements, 3), which the node → (element, corner) CSR map ``node_ptr`` /
    ``node_entry`` indexes: node n's corners are F_flat[node_entry[node_ptr[n]:node_ptr[n + 1]]]."""

    conn: np.ndarray
    vol0: np.ndarray
    mass: np.ndarray
    S: np.ndarray
    es: np.ndarray
    flags: np.ndarray
    bad: np.ndarray
    Lbuf: np.ndarray
    Qhg: np.ndarray
    Shg: np.ndarray
    F: np.ndarray
    F_flat: np.ndarray
    node_ptr: np.ndarray
    node_entry: np.ndarray


class MaterialConstants(NamedTuple):
    """The wall model's constants as its update kernel reads them (``params``, ``table``:
    :meth:`impactdyn.wall.WallModel.kernel_params`, ``kernel_table``) and the reference elastic
    moduli of the assumed-strain hourglass form, K₀ and G, Mbar
    (:meth:`~impactdyn.wall.WallModel.reference_moduli`)."""

    params: np.ndarray
    table: np.ndarray
    bulk: float
    shear: float


class Controls(NamedTuple):
    """The run's numerical settings: hourglass form code ``hg_form`` (:mod:`._hourglass`) and QH
    ``qh``; bulk-viscosity coefficients q1, q2; Courant factor; whether failed elements are eroded
    at once (``erode_failed``), the step below which a failed element is eroded (``erode_dt``) and
    below which a live one is a breakdown (``min_dt``), µs."""

    hg_form: int
    qh: float
    q1: float
    q2: float
    courant: float
    erode_failed: bool
    erode_dt: float
    min_dt: float
