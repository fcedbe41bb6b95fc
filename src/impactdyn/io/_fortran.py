"""Fixed-format Fortran records: the one reader and writer the legacy formats share.

The DC3D programs (Fahrenthold 1994, App. F and G) read and write formatted
records such as ``7e11.3``, ``2i10``, ``i8,i5,3e20.8``.  Reading is tolerant, as
a person editing these files by hand expects: a record is first split on
whitespace; only when that does not give the expected number of fields is it cut
into fixed-width columns (``e10.3`` fields of negative numbers touch, e.g.
``-0.123E+05-0.456E+05``).  Numbers may carry Fortran exponents: ``1.0D+03``, or
no exponent letter at all when the exponent has three digits (``0.123-104``, the
way ``Ew.d`` output writes |exponent| > 99).  Every failure raises
:class:`InputError` naming the file and line.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from impactdyn._errors import InputError, reading

_REAL = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eEdD][+-]?\d+|[+-]\d+)?")
_INT = re.compile(r"[+-]?\d+")
_BARE_EXPONENT = re.compile(r"^(.*[\d.])([+-]\d+)$")


def read_lines(path: str | Path) -> list[str]:
    """The lines of a text file (newline characters removed)."""
    p = Path(path)
    with reading(p):
        return p.read_text(encoding="latin-1").splitlines()


def parse_real(token: str) -> float:
    """One Fortran real; ``ValueError`` if it is not one (NaN and infinity are not)."""
    t = token.strip()
    if not _REAL.fullmatch(t):
        raise ValueError(f"not a number: {token!r}")
    t = t.replace("D", "E").replace("d", "e")
    m = _BARE_EXPONENT.match(t)
    if m and "e" not in t.lower():
        t = f"{m.group(1)}e{m.group(2)}"
    value = float(t)
    if not math.isfinite(value):
        raise ValueError(f"out of range: {token!r}")
    return value


def parse_int(token: str) -> int:
    t = token.strip()
    if not _INT.fullmatch(t):
        raise ValueError(f"not an integer: {token!r}")
    return int(t)


def record_fields(line: str, n: int, width: int) -> list[str]:
    """The ``n`` fields of a record: whitespace-separated, else ``width``-column fields.

    Fixed columns are used only when the line reaches into the last field, so a
    short (truncated) line is not silently padded with zeros; a blank field
    inside the line reads as zero and text after the last field is ignored, as
    Fortran reads them.
    """
    tokens = line.split()
    if len(tokens) == n:
        return tokens
    if len(line.rstrip()) > width * (n - 1):
        fields = [line[width * m : width * (m + 1)].strip() or "0" for m in range(n)]
        if all(fields) and not any(" " in f for f in fields):
            return fields
    raise ValueError(f"expected {n} fields, found {len(tokens)}")


def read_record(line: str, kinds: str, width: int, where: str) -> list[float | int]:
    """Parse one record of ``len(kinds)`` fields (``'i'`` integer, ``'e'`` real).

    ``where`` is ``"file:line"`` for the error message.
    """
    try:
        fields = record_fields(line, len(kinds), width)
        return [parse_int(f) if k == "i" else parse_real(f) for k, f in zip(kinds, fields)]
    except ValueError as err:
        raise InputError(f"{where}: {err} in {line.strip()!r}") from None


def format_e(values: Sequence[float] | np.ndarray, width: int, digits: int) -> str:
    """Fortran ``Ew.d`` output of ``values``, concatenated (no separators).

    ``0.ddddE+ee``; three-digit exponents drop the ``E`` (``0.123-104``) as
    Fortran does.  A value that does not fit ``width`` is an error, not ``****``.
    """
    a = np.asarray(values, dtype=float).ravel()
    if not np.all(np.isfinite(a)):
        raise ValueError(f"cannot write {a[~np.isfinite(a)][0]} in E{width}.{digits}")
    spec, zero = f"#.{digits - 1}e", "0." + "0" * digits + "E+00"  # '#': keep the point when digits = 1
    out = []
    for v in a.tolist():
        if v == 0.0:
            field = zero
        else:
            s = format(abs(v), spec)  # d.dd…e±xx, correctly rounded
            exp = int(s[digits + 2:]) + 1
            ex = f"E{exp:+03d}" if -99 <= exp <= 99 else f"{exp:+04d}"
            field = ("-0." if v < 0 else "0.") + s[0] + s[2:digits + 1] + ex
        if len(field) > width:
            raise ValueError(f"{v} does not fit E{width}.{digits}")
        out.append(field.rjust(width))
    return "".join(out)


def format_i(values: Sequence[int] | np.ndarray, width: int) -> str:
    """Fortran ``Iw`` output of ``values``, concatenated."""
    out = []
    for v in np.asarray(values).ravel():
        field = str(int(v))
        if len(field) > width:
            raise ValueError(f"{v} does not fit I{width}")
        out.append(field.rjust(width))
    return "".join(out)
