"""The Whipple-shield ballistic limit equations by name.

Each equation module registers its :class:`~impactdyn.ble._equation.WhippleEquation` with
a call to :func:`register` at its bottom (``EQUATIONS.register``, :class:`impactdyn._registry.Registry`,
the package's one plug-in idiom); :func:`get_equation` selects one by name.
"""

from __future__ import annotations

from impactdyn._registry import Registry
from impactdyn.ble._equation import WhippleEquation

#: Registered equations by name, in registration order (the key ``equation``).
EQUATIONS: Registry[WhippleEquation] = Registry("Whipple equation", "equation")

#: The equation used when none is named: the 2011 form, chosen on the 1135-shot test
#: database because it calls more shots right and, above all, far fewer perforations safe
#: (docs/ble.md, and ``impactdyn ble validate``).
DEFAULT_EQUATION = "jsc2011"


def register(equation: WhippleEquation) -> WhippleEquation:
    """``EQUATIONS.register(equation.name, equation)`` (a second equation of the same name is an error)."""
    return EQUATIONS.register(equation.name, equation)


def get_equation(name: str | None = None) -> WhippleEquation:
    """The registered equation ``name`` (``None``: :data:`DEFAULT_EQUATION`)."""
    return EQUATIONS.get(DEFAULT_EQUATION if name is None else name)
