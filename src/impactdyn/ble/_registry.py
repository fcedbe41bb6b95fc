"""The Whipple-shield ballistic limit equations by name.

Each equation module registers its :class:`~impactdyn.ble._equation.WhippleEquation` with
a call to :func:`register` at its bottom; :func:`get_equation` selects one by name.
"""

from __future__ import annotations

from impactdyn._errors import InputError
from impactdyn.ble._equation import WhippleEquation

#: Registered equations by name, in registration order.
EQUATIONS: dict[str, WhippleEquation] = {}

#: The equation used when none is named: the 2011 form, chosen on the 1135-shot test
#: database because it calls more shots right and, above all, far fewer perforations safe
#: (docs/ble.md, and ``impactdyn ble validate``).
DEFAULT_EQUATION = "jsc2011"


def register(equation: WhippleEquation) -> WhippleEquation:
    """Add ``equation`` under its name (a second equation of the same name is an error)."""
    if equation.name in EQUATIONS:
        raise ValueError(f"a Whipple equation named {equation.name!r} is registered already")
    EQUATIONS[equation.name] = equation
    return equation


def get_equation(name: str | None = None) -> WhippleEquation:
    """The registered equation ``name`` (``None``: :data:`DEFAULT_EQUATION`)."""
    key = DEFAULT_EQUATION if name is None else name
    if not isinstance(key, str) or key not in EQUATIONS:
        raise InputError(f"equation = {name!r}: unknown; choose one of {', '.join(EQUATIONS)}")
    return EQUATIONS[key]
