"""``legacy``: the listing's IVDCRK, classical RK4 with step doubling (DC3D; docs/theory/debris.md).

One step of h against two of h/2, the two half steps kept; the error norm, the
step control and where this departs from the listing are stated in
:mod:`._integrators` (with the other integrators); the interface it implements is
:mod:`._registry`'s.
"""

from __future__ import annotations

import numpy as np
from numba import prange

from impactdyn.debris._adaptive import next_step, start_particle
from impactdyn.debris._failure import OK, UNDERFLOW, state_failure
from impactdyn.debris._particle import N_WORK, STATE_ROWS, STATE_SIZE, kernel
from impactdyn.debris._registry import ParticleBatch, StepControl, body_rates, register_integrator

_OK, _UNDERFLOW = OK, UNDERFLOW  # failure codes as compile-time constants


@kernel
def _rk4_step(y, f_y, h, out, body, K, tmp, w):
    """out = classical RK4 step of size h from y, given f_y = f(y).

    Flat ``(33,)`` arrays y, f_y, out, tmp; K ``(3, 33)`` stage rates; w scratch.
    """
    Kr, Tmp = K.reshape((3, STATE_ROWS, 3)), tmp.reshape((STATE_ROWS, 3))
    for i in range(STATE_SIZE):
        tmp[i] = y[i] + 0.5 * h * f_y[i]
    body_rates(Tmp, body, Kr[0], w)
    for i in range(STATE_SIZE):
        tmp[i] = y[i] + 0.5 * h * K[0, i]
    body_rates(Tmp, body, Kr[1], w)
    for i in range(STATE_SIZE):
        tmp[i] = y[i] + h * K[1, i]
    body_rates(Tmp, body, Kr[2], w)
    for i in range(STATE_SIZE):
        out[i] = y[i] + h / 6.0 * (f_y[i] + 2.0 * K[0, i] + 2.0 * K[1, i] + K[2, i])


@kernel
def _legacy_particle(y, body, t_end, eps, ymxref, max_steps, K, W, w):
    # W rows: f(y), f(y_half), y_full, y_half, y_two, ymax, tmp
    f_y, f_half, y_full, y_half, y_two, ymax, tmp = W[0], W[1], W[2], W[3], W[4], W[5], W[6]
    Y, Wr = y.reshape((STATE_ROWS, 3)), W.reshape((7, STATE_ROWS, 3))
    stays, code = start_particle(Y, body, t_end, Wr[0], w)
    if stays:
        return 0.0, 0, 0, code
    for i in range(STATE_SIZE):
        ymax[i] = max(ymxref, abs(y[i]))
    h = t_end / 1.0e6
    h_min = h / 10.0
    t, steps, rejected = 0.0, 0, 0
    while True:
        code, final, h = next_step(t, h, t_end, steps + rejected, max_steps)
        if code != _OK:
            break
        _rk4_step(y, f_y, h, y_full, body, K, tmp, w)
        _rk4_step(y, f_y, 0.5 * h, y_half, body, K, tmp, w)
        body_rates(Wr[3], body, Wr[1], w)
        _rk4_step(y_half, f_half, 0.5 * h, y_two, body, K, tmp, w)
        err = 0.0
        for i in range(STATE_SIZE):
            err = max(err, abs(y_two[i] - y_full[i]) / (eps * ymax[i]))
        if err > 1.0:
            rejected += 1
            h *= 0.5
            if h < h_min:
                code = _UNDERFLOW
                break
            continue
        h_used = h
        h = 2.0 * h if err <= 0.0 else 0.99 * h * err ** -0.2
        y[:] = y_two
        for i in range(STATE_SIZE):
            ymax[i] = max(ymax[i], abs(y[i]))
        steps += 1
        t = t_end if final else t + h_used
        code = state_failure(Y)
        if code != _OK or final:
            break
        if h < h_min:
            code = _UNDERFLOW
            break
        body_rates(Y, body, Wr[0], w)
    return t, steps, rejected, code


@kernel(parallel=True)
def _legacy_all(y, Jinv, m, V0, t_end, eps, ymxref, params, max_steps, t_out, counts):
    for n in prange(y.shape[0]):
        K = np.empty((3, STATE_SIZE))
        W = np.empty((7, STATE_SIZE))
        w = np.empty((N_WORK, 3, 3))
        t_out[n], counts[n, 0], counts[n, 1], counts[n, 2] = _legacy_particle(
            y[n], (Jinv[n], m[n], V0[n], params), t_end[n], eps, ymxref, max_steps, K, W, w)


@register_integrator("legacy")
def legacy(batch: ParticleBatch, control: StepControl):
    """The listing's RK4 with step doubling (module docstring)."""
    y, t_out, counts = batch.outputs()
    _legacy_all(y, batch.Jinv, batch.m, batch.V0, batch.t_end, control.eps, control.ymxref,
                batch.params, control.max_steps, t_out, counts)
    return y, t_out, counts
