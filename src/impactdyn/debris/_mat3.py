"""3×3 matrix algebra on 9-tuples (row-major), for compiled kernels.

A matrix is a tuple ``(A00, A01, A02, A10, …, A22)`` of floats. Tuples live in
registers: a kernel written with them compiles to straight-line arithmetic with
no memory traffic and no reference counting, and a loop over particles whose
body uses only these functions is vectorised by LLVM (one particle per SIMD
lane, see :mod:`._splitting`). Every function is inlined into its caller.
"""

from __future__ import annotations

from functools import partial

from numba import njit

inline = partial(njit, cache=True, error_model="numpy", inline="always")


@inline
def mat(A):
    """The 9-tuple of a ``(3, 3)`` array."""
    return (A[0, 0], A[0, 1], A[0, 2], A[1, 0], A[1, 1], A[1, 2], A[2, 0], A[2, 1], A[2, 2])


@inline
def det(A):
    """det A."""
    return (A[0] * (A[4] * A[8] - A[5] * A[7])
            - A[1] * (A[3] * A[8] - A[5] * A[6])
            + A[2] * (A[3] * A[7] - A[4] * A[6]))


@inline
def adjugate(A):
    """adj A = det(A) A⁻¹, the transposed cofactor matrix."""
    return ((A[4] * A[8] - A[5] * A[7]), (A[2] * A[7] - A[1] * A[8]), (A[1] * A[5] - A[2] * A[4]),
            (A[5] * A[6] - A[3] * A[8]), (A[0] * A[8] - A[2] * A[6]), (A[2] * A[3] - A[0] * A[5]),
            (A[3] * A[7] - A[4] * A[6]), (A[1] * A[6] - A[0] * A[7]), (A[0] * A[4] - A[1] * A[3]))


@inline
def inv(A):
    """A⁻¹ = adj(A)/det A (inf/NaN entries when A is singular)."""
    return scale(1.0 / det(A), adjugate(A))


@inline
def mm(A, B):
    """A B."""
    return (A[0] * B[0] + A[1] * B[3] + A[2] * B[6], A[0] * B[1] + A[1] * B[4] + A[2] * B[7],
            A[0] * B[2] + A[1] * B[5] + A[2] * B[8],
            A[3] * B[0] + A[4] * B[3] + A[5] * B[6], A[3] * B[1] + A[4] * B[4] + A[5] * B[7],
            A[3] * B[2] + A[4] * B[5] + A[5] * B[8],
            A[6] * B[0] + A[7] * B[3] + A[8] * B[6], A[6] * B[1] + A[7] * B[4] + A[8] * B[7],
            A[6] * B[2] + A[7] * B[5] + A[8] * B[8])


@inline
def mtm(A, B):
    """Aᵀ B."""
    return (A[0] * B[0] + A[3] * B[3] + A[6] * B[6], A[0] * B[1] + A[3] * B[4] + A[6] * B[7],
            A[0] * B[2] + A[3] * B[5] + A[6] * B[8],
            A[1] * B[0] + A[4] * B[3] + A[7] * B[6], A[1] * B[1] + A[4] * B[4] + A[7] * B[7],
            A[1] * B[2] + A[4] * B[5] + A[7] * B[8],
            A[2] * B[0] + A[5] * B[3] + A[8] * B[6], A[2] * B[1] + A[5] * B[4] + A[8] * B[7],
            A[2] * B[2] + A[5] * B[5] + A[8] * B[8])


@inline
def transpose(A):
    """Aᵀ."""
    return (A[0], A[3], A[6], A[1], A[4], A[7], A[2], A[5], A[8])


@inline
def add(A, B):
    """A + B."""
    return (A[0] + B[0], A[1] + B[1], A[2] + B[2], A[3] + B[3], A[4] + B[4], A[5] + B[5],
            A[6] + B[6], A[7] + B[7], A[8] + B[8])


@inline
def sub(A, B):
    """A − B."""
    return (A[0] - B[0], A[1] - B[1], A[2] - B[2], A[3] - B[3], A[4] - B[4], A[5] - B[5],
            A[6] - B[6], A[7] - B[7], A[8] - B[8])


@inline
def scale(a, A):
    """a A."""
    return (a * A[0], a * A[1], a * A[2], a * A[3], a * A[4], a * A[5], a * A[6], a * A[7], a * A[8])


@inline
def axpy(a, X, Y):
    """Y + a X."""
    return (Y[0] + a * X[0], Y[1] + a * X[1], Y[2] + a * X[2], Y[3] + a * X[3], Y[4] + a * X[4],
            Y[5] + a * X[5], Y[6] + a * X[6], Y[7] + a * X[7], Y[8] + a * X[8])


@inline
def trace(A):
    """tr A."""
    return A[0] + A[4] + A[8]


@inline
def trace_of_product(A, B):
    """tr(A B) = Σᵢⱼ Aᵢⱼ Bⱼᵢ."""
    return (A[0] * B[0] + A[1] * B[3] + A[2] * B[6] + A[3] * B[1] + A[4] * B[4] + A[5] * B[7]
            + A[6] * B[2] + A[7] * B[5] + A[8] * B[8])


@inline
def deviator_half(C):
    """½(C − ⅓ tr C I): with C = FᵀF this is E' = E − ⅓ tr(E) I, E = ½(C − I)."""
    t = trace(C) / 3.0
    return (0.5 * (C[0] - t), 0.5 * C[1], 0.5 * C[2], 0.5 * C[3], 0.5 * (C[4] - t), 0.5 * C[5],
            0.5 * C[6], 0.5 * C[7], 0.5 * (C[8] - t))


@inline
def select(condition, A, B):
    """A where condition holds, else B (a per-lane blend in vectorised loops)."""
    return (A[0] if condition else B[0], A[1] if condition else B[1], A[2] if condition else B[2],
            A[3] if condition else B[3], A[4] if condition else B[4], A[5] if condition else B[5],
            A[6] if condition else B[6], A[7] if condition else B[7], A[8] if condition else B[8])
