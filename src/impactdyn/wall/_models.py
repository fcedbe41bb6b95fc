"""The registry of wall material models.

A model is a frozen dataclass deriving from :class:`WallModel`; its module registers it at its
bottom, ``MODELS.register(name, cls)`` (:class:`impactdyn._registry.Registry`, the package's one plug-in
idiom; :func:`register_model` is the same call, usable as a class decorator), and brings its own compiled stress update,
:attr:`WallModel.update_kernel`, which :func:`._step.step_kernels` compiles into the element
pass (a class without one is abstract and cannot be built).  Registered models:

* ``"mat13"`` — :class:`~impactdyn.wall._mat13.Mat13Model`, DYNA3D type 13 / LS-DYNA
  ``*MAT_013``, the report's wall card;
* ``"johnson_cook"`` — :class:`~impactdyn.wall._johnson_cook.JohnsonCookModel`,
  Johnson–Cook strength, Mie–Grüneisen EOS, Johnson–Cook damage, spall and erosion.

:func:`wall_model` builds a registered model from a library material
(:mod:`impactdyn.materials`).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable
from typing import Any, ClassVar

import numpy as np

from impactdyn._registry import Registry

#: Registered models by name (filled by the model modules at import; the case key ``material_model``).
MODELS: Registry[type["WallModel"]] = Registry("wall material model", "material_model")


class WallModel(ABC):
    """Base of the wall material models (each a frozen dataclass).

    Subclasses set ``name`` (the registry key) and ``option_keys`` (the case keys they take),
    and implement the abstract members below.
    """

    name: ClassVar[str] = ""
    #: The :class:`~impactdyn.wall.WallOptions` keys this model takes (keywords of :meth:`from_material`).
    option_keys: ClassVar[tuple[str, ...]] = ()

    @property
    @abstractmethod
    def density(self) -> float:
        """ρ₀, g/cm³."""

    @property
    @abstractmethod
    def erodes(self) -> bool:
        """Whether failed elements are removed from the force computation at once."""

    @property
    @abstractmethod
    def deck_material(self) -> Any:
        """What an LS-DYNA deck writes for this model (:func:`impactdyn.io.write_lsdyna_deck`):
        a :class:`~impactdyn.materials.Mat13Card` (``*MAT_013``) or a library
        :class:`~impactdyn.materials.Material` (``*MAT_015`` with ``*EOS_GRUNEISEN``)."""

    @property
    def deck_failure_strain_floor(self) -> float | None:
        """The fracture-strain floor an LS-DYNA deck writes (*MAT_JOHNSON_COOK's EFMIN); None: none."""
        return None

    @abstractmethod
    def wave_speed(self) -> float:
        """Longitudinal wave speed of the undeformed material, √((K + 4G/3)/ρ₀), cm/µs."""

    @abstractmethod
    def kernel_params(self) -> np.ndarray:
        """The model's parameter vector for the compiled update (float64, model's own columns)."""

    @property
    @abstractmethod
    def update_kernel(self) -> Callable:
        """The model's ``@njit`` stress update of one element, called by the element pass with the
        convention of :func:`impactdyn.wall._step.material_update`."""

    @abstractmethod
    def reference_moduli(self) -> tuple[float, float]:
        """(K₀, G), Mbar: the undeformed material's bulk and shear moduli, the elastic constants of
        the assumed-strain hourglass form (:mod:`._hourglass`)."""

    def kernel_table(self) -> np.ndarray:
        """A :func:`impactdyn.constitutive.pack_materials` table (a dummy row where unused)."""
        from impactdyn.constitutive import N_COLD, N_PARAMS

        return np.zeros((1, N_PARAMS + N_COLD))

    @abstractmethod
    def failure_criteria(self) -> tuple[str, ...]:
        """The criteria that can fail an element of this model, as names of
        :data:`impactdyn.wall._state.FAILURE_CAUSES` (empty: the wall cannot fail)."""

    @abstractmethod
    def describe(self) -> dict[str, Any]:
        """Every constant the model uses, with units and sources (for stage files and reports),
        and its ``failure_criteria``."""

    @classmethod
    @abstractmethod
    def from_material(cls, material: Any, **kwargs) -> "WallModel":
        """The model of a library material name or :class:`~impactdyn.materials.Material`."""


def register_model(cls: type[WallModel]) -> type[WallModel]:
    """``MODELS.register(cls.name, cls)``, returning ``cls`` (also a class decorator)."""
    return MODELS.register(cls.name, cls)


def check_model_name(name: str, key: str = "material_model") -> str:
    """``name`` if it is a registered model, else an :class:`InputError` naming ``key`` and the choices."""
    return MODELS.check(name, key)


def wall_model(name: str, material: Any = "al6061-t6", **kwargs) -> WallModel:
    """The registered model ``name`` built from ``material`` (a library name or Material).

    ``kwargs`` go to the model's :meth:`WallModel.from_material` (e.g. ``damage=None``
    for the Johnson–Cook model).  Unknown names raise :class:`InputError`.
    """
    return MODELS.get(name).from_material(material, **kwargs)
