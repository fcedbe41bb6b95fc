"""The registry of materials: every :class:`~impactdyn.materials.Material` the stages can name.

The library (:mod:`impactdyn.materials._library`) registers its alloys with :func:`register_material`
at the bottom of its module, as a grid format or a wall model registers itself; a case file's
``[materials.NAME]`` tables register theirs when the case is validated
(:mod:`impactdyn.materials._case_table`).  The stages look materials up by name with
:func:`get_material`: the shield's particles carry their materials' names, so that a state written to
a file names what it is made of.
"""

from __future__ import annotations

from typing import Annotated

from pydantic import AfterValidator

from impactdyn._errors import InputError
from impactdyn._registry import Registry
from impactdyn.materials._records import Material


def _key(name: str) -> str:
    return "".join(ch for ch in name.lower() if ch.isalnum())


#: Registered materials by name (a :class:`impactdyn._registry.Registry`, the package's one plug-in idiom);
#: look names up with :func:`get_material` (case and separators ignored).
MATERIALS: Registry[Material] = Registry(
    "material", normalize=_key, hint="a case file defines its own in a [materials.NAME] table")
#: Names a later registration may redefine: a case file's materials (the case validated last
#: defines them), never the library's.
_REPLACEABLE: set[str] = set()


def _registered_name(name: str) -> str | None:
    return MATERIALS.check(name) if name in MATERIALS else None


def register_material(material: Material, *, replaceable: bool = False) -> Material:
    """Enter ``material`` in :data:`MATERIALS` under its name and return it.

    A name that matches a registered one (case and separators ignored) raises :class:`InputError`,
    unless the record is the same (registering twice is harmless) or the registered one was entered
    ``replaceable`` (a case file's, redefined by the next case) and so is this one.
    """
    if not isinstance(material, Material):
        raise InputError(f"register_material: expected a Material, got {material!r}")
    if not _key(material.name):
        raise InputError(f"register_material: the name {material.name!r} needs a letter or digit")
    known = _registered_name(material.name)
    if known is not None and MATERIALS[known] != material and not (replaceable and known in _REPLACEABLE):
        what = "a case's material" if known in _REPLACEABLE else "a library material"
        raise InputError(f"material {material.name!r}: {what} {known!r} is registered under this name; "
                         "choose another name")
    if known is not None:
        _REPLACEABLE.discard(known)
    MATERIALS.register(material.name, material, replace=True)
    if replaceable:
        _REPLACEABLE.add(material.name)
    return material


def get_material(name: str | Material) -> Material:
    """The registered material called ``name`` ("Al6061-T6", "al_6061_t6", ... all match).

    A :class:`Material` passes through. Unknown names raise :class:`InputError`
    listing the known ones.
    """
    if isinstance(name, Material):
        return name
    return MATERIALS.get(name)


def _known_material(name: str) -> str:
    try:
        return get_material(name).name
    except InputError as err:
        raise ValueError(str(err)) from None


MaterialName = Annotated[str, AfterValidator(_known_material)]
"""A name of :data:`impactdyn.materials.MATERIALS`, stored as its canonical name."""
REPORT_MATERIAL = "al6061-t6"
"""Projectile, bumper and wall material by default: the report's Al 6061-T6."""
