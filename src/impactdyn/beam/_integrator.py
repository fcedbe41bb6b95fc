"""Compiled stiff integration of one smooth segment, with event scanning.

**Method.** A linearly implicit Rosenbrock method of order 4 with an embedded
order-3 error estimate, Shampine's A-stable parameter set (γ = ½; L. F. Shampine,
"Implementation of Rosenbrock methods", ACM TOMS 8, 1982; the Kaps–Rentrop form
of Hairer & Wanner, *Solving ODEs II*, §IV.7). Each step solves four linear systems
with the one matrix (I/(γh) − ∂f/∂y), LU-factorised once::

    (I/(γh) − J) gᵢ = f(y + Σⱼ aᵢⱼ gⱼ) + Σⱼ cᵢⱼ gⱼ / h,
    y₁ = y₀ + Σ bᵢ gᵢ,   err = Σ eᵢ gᵢ.

The Jacobian is the model's analytic one (:func:`jacobian_kernel`). Its structure
makes the linear algebra small: with y = [p, v, w] (p = [θ, q] and v = ṗ, m = n + 1
each, then the running integrals w, which do not feed back),
J = [[0, I, 0], [A_p, A_v, 0], [W_p, W_v, 0]], so (I/(γh) − J) g = r reduces to one
m × m system for the velocity part (substitute g_p = γh (r_p + g_v))::

    (I − γh A_v − (γh)² A_p) g_v = γh (r_v + γh A_p r_p),
    g_p = γh (r_p + g_v),   g_w = γh (r_w + W_p g_p + W_v g_v),

an LU of (n + 1)² instead of (2n + 7)², identical in exact arithmetic. Dense output is
the cubic Hermite interpolant of (y, f) at the step ends, which every path —
this one and the SciPy solvers — uses for events, outputs and force peaks, so the
three share one piece of step processing, :func:`process_step`.

The integrator is A-stable, costs no Python per step and allocates nothing per
step (the hot loop works in buffers made once per segment, through views that
numba does not reference-count, :func:`_borrow`): a 1-s sample run takes about
50,000 steps of 2–3 µs each.

The kernels take their data as records (NamedTuples, which numba passes like their
fields): the model of the segment (:class:`._model.SegmentModel`, with the coupled
model's :class:`._model.CoupledTerms` or None beside it), the step control
(:class:`._step_control.StepControl`), an accepted step with its dense output
(:class:`Step`), the event scan (:class:`EventScan`) and the run's output buffers
(:class:`Outputs`).

The step loop compiles the kernels of ``_model`` and ``_step_control`` into itself; its
cached machine code is stamped with a digest of all the package's sources
(:mod:`impactdyn._jitcache`), so an edit of any of them recompiles it.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import carray, njit, types
from numba.extending import intrinsic, overload

from impactdyn.beam._model import IN_CONTACT, contact_force_kernel, event_kernel, jacobian_kernel, rhs_into
from impactdyn.beam._step_control import least_step, next_step

# Shampine (1982) parameters
_GAM = 0.5
_A21, _A31, _A32 = 2.0, 48.0 / 25.0, 6.0 / 25.0
_C21, _C31, _C32 = -8.0, 372.0 / 25.0, 12.0 / 5.0
_C41, _C42, _C43 = -112.0 / 125.0, -54.0 / 125.0, -2.0 / 5.0
_B1, _B2, _B3, _B4 = 19.0 / 9.0, 0.5, 25.0 / 108.0, 125.0 / 108.0
_E1, _E2, _E3, _E4 = 17.0 / 54.0, 7.0 / 36.0, 0.0, 125.0 / 108.0
SAMPLES_PER_STEP = 8

# status codes of rosenbrock_segment
REACHED_END, EVENT, STEP_UNDERFLOW, TOO_MANY_STEPS = 0, 1, 2, 3


class Step(NamedTuple):
    """An accepted step from (ta, ya) to (tb, yb), with the slopes fa = f(ta, ya) and
    fb = f(tb, yb) that its dense output interpolates (:func:`hermite_into`)."""

    ta: float
    ya: np.ndarray
    fa: np.ndarray
    tb: float
    yb: np.ndarray
    fb: np.ndarray


class EventScan(NamedTuple):
    """The event scan of one segment: the crossing directions ``dirs`` (2,) and the arming
    ``armed`` (2,) of the two event slots (:func:`first_crossing`), and the scratch of
    :func:`process_step`: ``values`` (SAMPLES_PER_STEP + 1, 2) of the sampled event
    functions and ``state`` (2n + 7,) of the interpolated state. Made by :func:`event_scan`."""

    dirs: np.ndarray
    armed: np.ndarray
    values: np.ndarray
    state: np.ndarray


def event_scan(dirs: np.ndarray, n_state: int) -> EventScan:
    """A fresh :class:`EventScan` for the crossing directions ``dirs``, nothing armed."""
    return EventScan(dirs=dirs, armed=np.zeros(2, dtype=np.bool_), values=np.empty((SAMPLES_PER_STEP + 1, 2)),
                     state=np.empty(n_state))


class Outputs(NamedTuple):
    """The run's output buffers: times ``t`` (k,) and the states ``y`` (k, 2n + 7) and
    contact ``force`` (k,) at them, written in order by :func:`record_outputs`."""

    t: np.ndarray
    y: np.ndarray
    force: np.ndarray


@njit(cache=True, inline="always")
def hermite_into(step, t, out):
    """Cubic Hermite interpolant of the :class:`Step` at t ∈ [ta, tb], written into ``out``.
    Inlined (like :func:`._model.event_kernel`): a call would count references to the step's arrays."""
    ta, ya, fa, tb, yb, fb = step
    h = tb - ta
    s = (t - ta) / h
    s2 = s * s
    s3 = s2 * s
    c0, c1, c2, c3 = 2 * s3 - 3 * s2 + 1, (s3 - 2 * s2 + s) * h, -2 * s3 + 3 * s2, (s3 - s2) * h
    for i in range(ya.shape[0]):
        out[i] = c0 * ya[i] + c1 * fa[i] + c2 * yb[i] + c3 * fb[i]
    return out


@njit(cache=True)
def hermite(step, t):
    """Cubic Hermite interpolant of the :class:`Step` at t ∈ [ta, tb]; shape of ``ya``."""
    return hermite_into(step, t, np.empty_like(step.ya))


@njit(cache=True)
def _lu_factor(a, piv):
    """In-place LU with partial pivoting (Doolittle); ``a`` (n, n), ``piv`` (n,)."""
    n = a.shape[0]
    for k in range(n):
        p = k
        big = abs(a[k, k])
        for i in range(k + 1, n):
            if abs(a[i, k]) > big:
                big = abs(a[i, k])
                p = i
        piv[k] = p
        if p != k:
            for j in range(n):
                a[k, j], a[p, j] = a[p, j], a[k, j]
        inv = 1.0 / a[k, k]
        for i in range(k + 1, n):
            a[i, k] *= inv
            lik = a[i, k]
            if lik != 0.0:
                for j in range(k + 1, n):
                    a[i, j] -= lik * a[k, j]


@njit(cache=True)
def _lu_solve(a, piv, b):
    """Solve in place with the factors of :func:`_lu_factor`."""
    n = a.shape[0]
    for k in range(n):
        p = piv[k]
        if p != k:
            b[k], b[p] = b[p], b[k]
    for i in range(n):
        s = b[i]
        for j in range(i):
            s -= a[i, j] * b[j]
        b[i] = s
    for i in range(n - 1, -1, -1):
        s = b[i]
        for j in range(i + 1, n):
            s -= a[i, j] * b[j]
        b[i] = s / a[i, i]


@njit(cache=True)
def first_crossing(vals, dirs, armed):
    """Earliest sign change among the event functions sampled over one step.

    ``vals`` (k, 2) event values at k increasing instants; ``dirs`` (2,) −1 for a
    crossing from positive to non-positive, +1 from negative to non-negative, 0 for
    an unused slot; ``armed`` (2,) is set once a value lies strictly on the start
    side (an event that starts on its boundary, just after firing, is not re-fired).
    Returns (j, e): the crossing lies in [instant j−1, instant j] of event e, or (−1, −1).
    """
    best_j, best_e = -1, -1
    for e in range(2):
        d = dirs[e]
        if d == 0:
            continue
        for j in range(vals.shape[0]):
            v = vals[j, e]
            start_side = v > 0.0 if d < 0 else v < 0.0
            if start_side:
                armed[e] = True
            elif armed[e] and j > 0:
                if best_j < 0 or j < best_j:
                    best_j, best_e = j, e
                break
    return best_j, best_e


@njit(cache=True)
def record_outputs(step, t_hi, model, coupled, out, k_out):
    """Fill the rows of the :class:`Outputs` ``out`` from row ``k_out`` whose times lie in
    (ta, t_hi] with the step's interpolant and the contact force of the segment ``model``
    (and ``coupled``, :mod:`._model`); returns the next row."""
    times, states, force = out.t, out.y, out.force  # read once: each read of a field is a reference count
    while k_out < times.shape[0] and times[k_out] <= t_hi + 1e-13 * abs(t_hi):
        if times[k_out] > step.ta or k_out == 0:
            y = hermite_into(step, min(times[k_out], step.tb), states[k_out])
            f_c = contact_force_kernel(y, model, coupled)
            force[k_out] = f_c
        k_out += 1
    return k_out


@njit(cache=True)
def track_peak(step, t_hi, model, coupled, peak):
    """Raise ``peak`` (2,) = (F_max, t at F_max) with the contact force over [ta, t_hi].

    Samples the interpolant and refines the largest sample by a parabola through it
    and its neighbours (the force is smooth inside a contact phase).
    """
    k = SAMPLES_PER_STEP
    ta = step.ta
    ts = np.empty(k + 1)
    fs = np.empty(k + 1)
    yt = np.empty_like(step.ya)
    for j in range(k + 1):
        ts[j] = ta + (t_hi - ta) * j / k
        f_c = contact_force_kernel(hermite_into(step, ts[j], yt), model, coupled)
        fs[j] = f_c
    j = np.argmax(fs)
    f_best, t_best = fs[j], ts[j]
    if 0 < j < k:
        denom = fs[j - 1] - 2.0 * fs[j] + fs[j + 1]
        if denom < 0.0:
            off = 0.5 * (fs[j - 1] - fs[j + 1]) / denom
            t_try = ts[j] + off * (ts[1] - ts[0])
            f_try = contact_force_kernel(hermite_into(step, t_try, yt), model, coupled)
            if f_try > f_best:
                f_best, t_best = f_try, t_try
    if f_best > peak[0]:
        peak[0] = f_best
        peak[1] = t_best


@njit(cache=True)
def process_step(step, model, coupled, events, out, k_out, peak):
    """Scan an accepted :class:`Step` for events; without one, write its outputs and force peak.

    Returns (j, e, k_out): the event bracket of :func:`first_crossing` (−1, −1 if none).
    """
    k = SAMPLES_PER_STEP
    ta, tb = step.ta, step.tb
    vals, state = events.values, events.state
    for j in range(k + 1):
        t = ta + (tb - ta) * j / k
        vals[j, 0], vals[j, 1] = event_kernel(hermite_into(step, t, state), model, coupled)
    j, e = first_crossing(vals, events.dirs, events.armed)
    if j < 0:
        k_out = record_outputs(step, tb, model, coupled, out, k_out)
        if model.sc[IN_CONTACT] == 1.0:
            track_peak(step, tb, model, coupled, peak)
    return j, e, k_out


@njit(cache=True)
def _stage_solve(lu, piv, jac, gh, m, g, gv):
    """g ← (I/(γh) − J)⁻¹ g by the reduction of the module docstring; ``lu``, ``piv``
    the factors of I − γh A_v − (γh)² A_p, ``gv`` (m,) scratch, gh = γh."""
    for i in range(m):
        s = g[m + i]
        for c in range(m):
            s += gh * jac[m + i, c] * g[c]
        gv[i] = gh * s
    _lu_solve(lu, piv, gv)
    for i in range(m):
        g[i] = gh * (g[i] + gv[i])
        g[m + i] = gv[i]
    for r in range(2 * m, g.shape[0]):
        s = g[r]
        for c in range(2 * m):
            s += jac[r, c] * g[c]
        g[r] = gh * s


@intrinsic
def _data_pointer(typingctx, arr):
    """The data pointer of a C-contiguous array (for :func:`_borrow`; other layouts do not type)."""
    if not isinstance(arr, types.Array) or arr.layout != "C":
        return None

    def codegen(context, builder, signature, args):
        return context.make_array(signature.args[0])(context, builder, args[0]).data

    return types.CPointer(arr.dtype)(arr), codegen


@njit(cache=True)
def _borrow(a):
    """A view of the C-contiguous array ``a`` that carries no reference count.

    numba counts references to every array passed to a call, atomically; with a
    dozen arrays per kernel call that was most of the time of a step. Views made by
    ``carray`` have no count, so the step loop works on borrowed views of arrays
    that its caller keeps alive.
    """
    return carray(_data_pointer(a), a.shape)


def _borrowed(value):
    """A copy of the record ``value`` whose arrays are :func:`_borrow`-ed views, nested
    records too; None and scalars as they are. For compiled callers only (:func:`_borrowed_of`)."""


@overload(_borrowed)
def _borrowed_of(value):
    """:func:`_borrowed` for the type of ``value``; a record's is written out field by field,
    record(_borrowed(value[0]), _borrowed(value[1]), …), so that no list of fields is kept by hand."""
    if isinstance(value, types.Array):
        return lambda value: _borrow(value)
    if isinstance(value, types.BaseNamedTuple):
        fields = ", ".join(f"_borrowed(value[{i}])" for i in range(len(value)))
        scope = {"record": value.instance_class, "_borrowed": _borrowed}
        exec(f"def borrowed_record(value):\n    return record({fields})", scope)
        return scope["borrowed_record"]
    return lambda value: value


class _StepBuffers(NamedTuple):
    """The step loop's buffers, made once per segment: ``ends`` (4, n) ya, fa, y, f of the
    last step, ``stages`` (9, n) g₁…g₄, f, the stage state, y₁, f(y₁) and the velocity part
    of a stage solve, the Jacobian ``jac`` (n, n), and the factors ``lu`` (m, m), ``piv`` (m,)."""

    ends: np.ndarray
    stages: np.ndarray
    jac: np.ndarray
    lu: np.ndarray
    piv: np.ndarray


@njit(cache=True)
def rosenbrock_segment(t, y0, t_end, h_try, control, model, coupled, events, out, k_out, peak, stats):
    """Integrate from t toward ``t_end`` until an event (Rosenbrock 4(3), module docstring).

    ``control`` a :class:`._step_control.StepControl`, ``model`` the segment's
    :class:`._model.SegmentModel` and ``coupled`` its :class:`._model.CoupledTerms` or None,
    ``events`` its :class:`EventScan`, ``out`` the run's
    :class:`Outputs` (filled from row ``k_out``), ``peak`` as in :func:`track_peak`;
    ``stats`` (4,) accumulates steps, rejected steps, rhs and Jacobian evaluations.
    The leading 2m = 2n + 2 components [p, v] are the dynamic state (error-controlled).
    Returns (status, k_out, h_next, j, e, step): on ``EVENT`` the :class:`Step` holds the
    crossing in its sample bracket j of event e; on ``REACHED_END`` (tb, yb) is the state
    at t_end.
    """
    n = y0.shape[0]
    m = model.m0.shape[0] + 1
    buffers = _StepBuffers(np.empty((4, n)), np.empty((9, n)), np.empty((n, n)), np.empty((m, m)),
                           np.empty(m, dtype=np.int64))
    buffers.ends[2] = y0
    status, k_out, h, j, e, ta, tb = _rosenbrock_steps(t, t_end, h_try, control, model, coupled, events, out, k_out,
                                                       peak, stats, buffers)
    ends = buffers.ends
    return status, k_out, h, j, e, Step(ta, ends[0], ends[1], tb, ends[2], ends[3])


@njit(cache=True)
def _rosenbrock_steps(t, t_end, h, control, model, coupled, events, out, k_out, peak, stats, buffers):
    """The step loop of :func:`rosenbrock_segment`, on borrowed views of its arrays,
    which the caller keeps alive. The state starts in ``buffers.ends[2]``; the last
    step's end values are left in ``buffers.ends``. Returns (status, k_out, h_next, j, e, ta, tb)."""
    model, coupled, events = _borrowed(model), _borrowed(coupled), _borrowed(events)
    out, buffers = _borrowed(out), _borrowed(buffers)
    peak, stats = _borrow(peak), _borrow(stats)
    ends, stages, jac, lu, piv = buffers.ends, buffers.stages, buffers.jac, buffers.lu, buffers.piv
    n = ends.shape[1]
    m = lu.shape[0]
    n_dyn = 2 * m
    rtol, atol = control.rtol, control.atol
    ya, fa, y, f0 = ends[0], ends[1], ends[2], ends[3]
    g1, g2, g3, g4 = stages[0], stages[1], stages[2], stages[3]
    f, yt, y_new, f_new = stages[4], stages[5], stages[6], stages[7]
    gv = stages[8][:m]

    rhs_into(t, y, f0, model, coupled)
    ya[:] = y
    fa[:] = f0
    stats[2] += 1
    h = min(h, t_end - t)
    ta = t
    while t < t_end:
        if stats[0] >= control.max_steps:
            return TOO_MANY_STEPS, k_out, h, -1, -1, ta, t
        last = t + h >= t_end
        if last:
            h = t_end - t
        elif t + h == t:  # a restart asked for less than the time resolves: a step of no length
            return STEP_UNDERFLOW, k_out, h, -1, -1, ta, t
        jacobian_kernel(t, y, model, coupled, jac)
        stats[3] += 1
        gh = _GAM * h
        for r in range(m):
            for c in range(m):
                lu[r, c] = -gh * jac[m + r, m + c] - gh * gh * jac[m + r, c]
            lu[r, r] += 1.0
        _lu_factor(lu, piv)
        g1[:] = f0
        _stage_solve(lu, piv, jac, gh, m, g1, gv)
        for i in range(n):
            yt[i] = y[i] + _A21 * g1[i]
        rhs_into(t + h, yt, f, model, coupled)
        for i in range(n):
            g2[i] = f[i] + _C21 * g1[i] / h
        _stage_solve(lu, piv, jac, gh, m, g2, gv)
        for i in range(n):
            yt[i] = y[i] + _A31 * g1[i] + _A32 * g2[i]
        rhs_into(t + h, yt, f, model, coupled)
        for i in range(n):
            g3[i] = f[i] + (_C31 * g1[i] + _C32 * g2[i]) / h
        _stage_solve(lu, piv, jac, gh, m, g3, gv)
        for i in range(n):
            g4[i] = f[i] + (_C41 * g1[i] + _C42 * g2[i] + _C43 * g3[i]) / h
        _stage_solve(lu, piv, jac, gh, m, g4, gv)
        stats[2] += 2
        for i in range(n):
            y_new[i] = y[i] + _B1 * g1[i] + _B2 * g2[i] + _B3 * g3[i] + _B4 * g4[i]
        err = 0.0
        for i in range(n_dyn):
            sk = atol + rtol * max(abs(y[i]), abs(y_new[i]))
            ei = (_E1 * g1[i] + _E2 * g2[i] + _E3 * g3[i] + _E4 * g4[i]) / sk
            err += ei * ei
        err = np.sqrt(err / n_dyn)
        if not np.isfinite(err):
            err = 1e10
        if err <= 1.0:
            t_new = t_end if last else t + h
            rhs_into(t_new, y_new, f_new, model, coupled)
            stats[0] += 1
            stats[2] += 1
            j, e, k_out = process_step(Step(t, y, f0, t_new, y_new, f_new), model, coupled, events, out, k_out, peak)
            ta = t
            ya[:] = y
            fa[:] = f0
            t = t_new
            y[:] = y_new
            f0[:] = f_new
            h_next = next_step(control, h, err)
            if j >= 0:
                return EVENT, k_out, h_next, j, e, ta, t
            if not last:
                h = h_next
        else:
            stats[1] += 1
            h = next_step(control, h, err)
            if h < least_step(control, t):
                return STEP_UNDERFLOW, k_out, h, -1, -1, ta, t
    return REACHED_END, k_out, h, -1, -1, ta, t
