"""TOML case files -> validated pydantic models.

Every case model derives from :class:`Section`: unknown keys are errors, NaN and
infinities are rejected, numbers are not silently converted from strings. A
failure becomes one :class:`~impactdyn._errors.InputError` naming the file and the
dotted key, e.g. ``case.toml: beam.EI_N_m2: must be > 0``.
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path
from typing import Annotated, Any, TypeVar

import tomli_w
from pydantic import BaseModel, ConfigDict, Field, ValidationError

from impactdyn._errors import InputError, reading

M = TypeVar("M", bound=BaseModel)

Positive = Annotated[float, Field(gt=0)]
NonNegative = Annotated[float, Field(ge=0)]


class Section(BaseModel):
    """Base of every config table: strict keys, finite numbers, frozen."""

    model_config = ConfigDict(extra="forbid", allow_inf_nan=False, frozen=True, strict=True)


def _key_path(loc: tuple, data: Any) -> str:
    """Dotted key of an error location, without the tags pydantic inserts for unions."""
    parts, node = [], data
    for i, p in enumerate(loc):
        if isinstance(node, dict) and p not in node and not isinstance(p, int) and parts and i < len(loc) - 1:
            continue  # a union member's name, not a key of the file
        parts.append(f"[{p}]" if isinstance(p, int) else str(p))
        node = node.get(p) if isinstance(node, dict) else (
            node[p] if isinstance(node, list) and isinstance(p, int) and p < len(node) else None)
    return ".".join(parts).replace(".[", "[")


def _format_error(source: str, err: ValidationError, data: Any) -> str:
    lines = []
    for e in err.errors():
        key = _key_path(e["loc"], data)
        msg = e["msg"]
        if e["type"] == "extra_forbidden":
            msg = "unknown key"
        elif e["type"] == "missing":
            msg = "missing key"
        msg = msg.replace("Input should be", "must be").replace("Value error, ", "")
        lines.append(f"{source}: {key}: {msg}" if key else f"{source}: {msg}")
    return "\n".join(lines)


def validate(model: type[M], data: dict[str, Any], source: str = "<case>") -> M:
    """Build ``model`` from a plain dict, raising :class:`InputError` on failure."""
    try:
        return model.model_validate(data)
    except ValidationError as err:
        raise InputError(_format_error(source, err, data)) from None


def load_toml(path: str | Path) -> dict[str, Any]:
    """Read a TOML file; unreadable or malformed files raise :class:`InputError`."""
    p = Path(path)
    try:
        with reading(p, "case file"), p.open("rb") as fh:
            return tomllib.load(fh)
    except UnicodeDecodeError:
        raise InputError(f"{p}: not a UTF-8 text file") from None
    except tomllib.TOMLDecodeError as err:
        raise InputError(f"{p}: invalid TOML: {err}") from None


def load_case(model: type[M], path: str | Path) -> M:
    """Load and validate a TOML case file."""
    return validate(model, load_toml(path), source=str(path))


def set_dotted(data: dict[str, Any], key: str, value: Any) -> dict[str, Any]:
    """Return a copy of ``data`` with ``a.b.c = value`` (tables created as needed)."""
    out = _deepcopy(data)
    parts = key.split(".")
    node = out
    for p in parts[:-1]:
        node = node.setdefault(p, {})
        if not isinstance(node, dict):
            raise InputError(f"{key}: '{p}' is not a table")
    node[parts[-1]] = value
    return out


def parse_range(option: str, spec: str, example: str) -> list[float]:
    """``START:STOP:N`` → N values from START to STOP inclusive; ``option`` and ``example`` go into the error."""
    import numpy as np

    from impactdyn._limits import CASE_BYTES, check_fits

    try:
        start, stop, n = spec.split(":")
        count, lo, hi = int(n), float(start), float(stop)
    except ValueError:
        raise InputError(f"{option} {spec!r}: expected START:STOP:N, e.g. {example}") from None
    if count >= 1:
        check_fits(f"{option} {spec!r}: N", count, CASE_BYTES, "cases")
    with np.errstate(over="ignore", invalid="ignore"):
        values = np.linspace(lo, hi, max(count, 0))
    if count < 1 or not np.all(np.isfinite(values)):
        raise InputError(f"{option} {spec!r}: N must be at least 1 and the bounds finite")
    return values.tolist()


def _deepcopy(d: Any) -> Any:
    if isinstance(d, dict):
        return {k: _deepcopy(v) for k, v in d.items()}
    if isinstance(d, list):
        return [_deepcopy(v) for v in d]
    return d


def dump_toml(model: BaseModel) -> str:
    """Every parameter actually used, defaults included, as TOML."""
    return tomli_w.dumps(_drop_none(model.model_dump(mode="json")))


def _drop_none(d: Any) -> Any:
    if isinstance(d, dict):
        return {k: _drop_none(v) for k, v in d.items() if v is not None}
    if isinstance(d, list):
        return [_drop_none(v) for v in d]
    if isinstance(d, float) and not math.isfinite(d):
        raise ValueError("non-finite value in resolved config")
    return d
