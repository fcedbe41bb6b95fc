"""Input checks shared by the ballistic limit equations.

Every check raises :class:`impactdyn.InputError` with a message that names the
parameter and the offending value, before any arithmetic is done.
"""

from __future__ import annotations

import numbers
import sys

import numpy as np

from impactdyn._errors import InputError


def positive(name: str, value: object) -> float:
    """A finite real number > 0, returned as ``float``; a subnormal one (below 2.2e-308) is refused: the
    equations' powers and logarithms underflow it to 0."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise InputError(f"{name} = {value!r}: must be a number")
    v = float(value)
    if not np.isfinite(v) or v < sys.float_info.min:
        raise InputError(f"{name} = {v!r}: must be a finite number > 0"
                         + (" and a normal float (at least 2.2e-308)" if v > 0.0 else ""))
    return v


def _as_float_array(name: str, value: object) -> np.ndarray:
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name} = {value!r}: must be a number or an array of numbers") from None
    if np.asarray(value).dtype == bool:
        raise InputError(f"{name} = {value!r}: must be a number, not a boolean")
    return arr


def positive_array(name: str, value: object) -> np.ndarray:
    """Finite values > 0 (scalar or array-like), as a float array."""
    arr = _as_float_array(name, value)
    bad = ~(np.isfinite(arr) & (arr >= sys.float_info.min))
    if bad.any():
        raise InputError(f"{name} = {float(arr[bad].flat[0])!r}: must be a finite number > 0 and a normal float "
                         "(at least 2.2e-308)")
    return arr


def obliquity(value: object) -> np.ndarray:
    """``obliquity_deg``: angles from the target normal, 0 ≤ θ < 90 (scalar or array-like)."""
    arr = _as_float_array("obliquity_deg", value)
    bad = ~(np.isfinite(arr) & (arr >= 0.0) & (arr < 90.0))
    if bad.any():
        raise InputError(f"obliquity_deg = {float(arr[bad].flat[0])!r}: obliquity must be in [0, 90) degrees "
                         "from the target normal")
    return arr


def scalar_obliquity(value: object) -> float:
    """One angle (a curve is drawn at a single obliquity)."""
    arr = obliquity(value)
    if arr.ndim != 0:
        raise InputError(f"obliquity_deg: one angle is expected here, got an array of shape {arr.shape}")
    return float(arr)


def result(values: np.ndarray, *inputs: np.ndarray) -> float | np.ndarray:
    """``float`` when every input was a scalar, else the (broadcast) array."""
    return float(values) if all(np.ndim(x) == 0 for x in inputs) else values
