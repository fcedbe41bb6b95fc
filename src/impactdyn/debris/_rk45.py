"""``rk45``: adaptive Dormand–Prince 5(4) with FSAL, local extrapolation and PI step control.

The method, its error norm and its step control are stated in :mod:`._integrators`
(with the other integrators and the choice of default); the interface it
implements is :mod:`._registry`'s.
"""

from __future__ import annotations

import math

import numpy as np
from numba import prange

from impactdyn.debris._adaptive import next_step, start_particle
from impactdyn.debris._failure import OK, UNDERFLOW, state_failure
from impactdyn.debris._particle import EP_SLICE, H_SLICE, N_WORK, STATE_ROWS, STATE_SIZE, kernel
from impactdyn.debris._registry import ParticleBatch, StepControl, body_rates, register_integrator

_OK, _UNDERFLOW = OK, UNDERFLOW  # failure codes as compile-time constants

_DP_A = np.array([
    [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [1 / 5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3 / 40, 9 / 40, 0.0, 0.0, 0.0, 0.0, 0.0],
    [44 / 45, -56 / 15, 32 / 9, 0.0, 0.0, 0.0, 0.0],
    [19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729, 0.0, 0.0, 0.0],
    [9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656, 0.0, 0.0],
    [35 / 384, 0.0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84, 0.0],
])
"""Stage coefficients; the last row is the fifth-order solution (FSAL)."""
_DP_E = np.array([71 / 57600, 0.0, -71 / 16695, 71 / 1920, -17253 / 339200, 22 / 525, -1 / 40])
"""b − b̂: fifth- minus fourth-order weights, the local error estimate."""

_N_CONTROLLED = EP_SLICE.stop  # H, F, Eₚ enter the error norm; p, c are exact
_N_H = H_SLICE.stop


@kernel
def _rk45_particle(y, body, t_end, h0, h_floor, eps, max_steps, K, ytrial, w):
    Y, Ytrial = y.reshape((STATE_ROWS, 3)), ytrial.reshape((STATE_ROWS, 3))
    Kr = K.reshape((7, STATE_ROWS, 3))
    stays, code = start_particle(Y, body, t_end, Kr[0], w)
    if stays:
        return 0.0, 0, 0, code
    t, h, h_min = 0.0, min(h0, t_end), 1e-10 * h0
    steps, rejected, after_rejection, err_old = 0, 0, False, 1e-4
    while True:
        code, final, h = next_step(t, h, t_end, steps + rejected, max_steps)
        if code != _OK:
            break
        for s in range(1, 7):
            for i in range(STATE_SIZE):
                acc = 0.0
                for j in range(s):
                    acc += _DP_A[s, j] * K[j, i]
                ytrial[i] = y[i] + h * acc
            body_rates(Ytrial, body, Kr[s], w)
        err = 0.0
        for i in range(_N_CONTROLLED):
            local = 0.0
            for j in range(7):
                local += _DP_E[j] * K[j, i]
            floor = h_floor if i < _N_H else 1.0
            err = max(err, abs(h * local) / (eps * max(abs(y[i]), abs(ytrial[i]), floor)))
        if state_failure(Ytrial) != _OK:
            err = math.inf
        if err <= 1.0:
            y[:] = ytrial
            K[0, :] = K[6]
            steps += 1
            if final:
                t = t_end
                break
            t += h
            factor = 5.0 if err == 0.0 else min(5.0, 0.9 * err ** -0.17 * err_old ** 0.04)
            err_old = max(err, 1e-4)  # DOPRI5's floor: a tiny error must not stall growth
            if after_rejection:
                factor = min(factor, 1.0)
            after_rejection = False
        else:
            rejected += 1
            after_rejection = True
            factor = max(0.2, 0.9 * err ** -0.2) if err < math.inf else 0.2
        h *= factor
        if h < h_min:
            code = _UNDERFLOW
            break
    return t, steps, rejected, code


@kernel(parallel=True)
def _rk45_all(y, Jinv, m, V0, t_end, h0, h_floor, eps, params, max_steps, t_out, counts):
    for n in prange(y.shape[0]):
        K = np.empty((7, STATE_SIZE))
        ytrial = np.empty(STATE_SIZE)
        w = np.empty((N_WORK, 3, 3))
        t_out[n], counts[n, 0], counts[n, 1], counts[n, 2] = _rk45_particle(
            y[n], (Jinv[n], m[n], V0[n], params), t_end[n], h0[n], h_floor[n], eps, max_steps,
            K, ytrial, w)


@register_integrator("rk45")
def rk45(batch: ParticleBatch, control: StepControl):
    """Adaptive Dormand–Prince 5(4) (module docstring)."""
    h0 = 0.1 / batch.omega_hat if control.dt is None else batch.per_particle(control.dt)
    y, t_out, counts = batch.outputs()
    _rk45_all(y, batch.Jinv, batch.m, batch.V0, batch.t_end, h0, batch.j_max * batch.omega_hat,
              control.eps, batch.params, control.max_steps, t_out, counts)
    return y, t_out, counts
