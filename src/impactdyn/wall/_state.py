"""Column layout of the solver's per-element state arrays.

Element state lives in a few contiguous arrays, one row per element (the element kernel
reads and writes one row at a time):

* ``S`` (n_elements, 6) — deviatoric stress, components (xx, yy, zz, xy, yz, zx), Mbar;
* ``es`` (n_elements, N_ES) float64 — the scalars below;
* ``flags`` (n_elements, 2) uint8 — FAILED, ERODED;
* ``Lbuf`` (n_elements, 3, 3) — the midstep velocity gradient ∂v_i/∂x_j, 1/µs;
* ``Qhg`` (n_elements, 4, 3) — generalised hourglass forces Q_αi of the last step.
"""

#: Columns of ``es``: pressure p (Mbar), bulk viscosity q (Mbar), specific internal energy e
#: (cm²/µs²), effective plastic strain εₚ, damage D (Johnson–Cook D, or εₚ/ε_f for mat13),
#: equivalent deviatoric strain rate (1/µs), sound speed c (cm/µs), volume V (cm³), and the
#: work accumulated by the element's stress (σ = S − pI), bulk viscosity, hourglass forces and
#: plastic flow (g·cm²/µs²), its stable time step Δt_e (µs), and the powers f·v^{n−½} of its
#: current stress, bulk-viscosity and hourglass forces on the velocities they were computed with
#: (g·cm²/µs³, the first half of the next work increment, :mod:`._step`).
(P, Q, IE, EPS_P, DAMAGE, RATE, C, VOL, W_SIGMA, W_Q, W_HG, W_PLASTIC, DT_E, P1_SIGMA, P1_Q, P1_HG) = range(16)
N_ES = 16

#: Columns of ``flags``.
FAILED, ERODED = 0, 1
