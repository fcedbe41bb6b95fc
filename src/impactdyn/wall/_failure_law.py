"""The registry of wall failure laws: how a Johnson–Cook wall element fails in tension (``spall_law``).

A failure law is a :class:`FailureLaw` record in :data:`FAILURE_LAWS`, one module of
:mod:`impactdyn.wall.failure_laws` each, registered at the bottom of its module like every plug-in of the
package (:class:`impactdyn._registry.Registry`).  It brings everything it needs:

* its constants: where the material keeps them (:attr:`FailureLaw.library_constants`), and the numbers the
  kernel reads, packed after the Johnson–Cook model's own (``prm[J_LAW:]``, :attr:`FailureLaw.kernel_constants`);
* its compiled code, two ``@njit(inline="always")`` functions that
  :func:`impactdyn.wall._johnson_cook.jc_kernel` binds into the model's element update (a kernel per law,
  compiled once, with no branch on the law in the hot loop)::

      accumulate(e, p_old, p_new, dt, es, table, prm) -> None    # the law's state over the step
      fails(e, p_new, es, table, prm) -> bool                    # whether element e fails at the step's end

  ``p_old``, ``p_new`` the element's pressure at the step's start and end (Mbar, tension negative), ``dt`` the
  step (µs), ``es`` the element state (a law with a state of its own keeps it in column ``SPALL_DAMAGE``),
  ``table`` the packed material (:func:`impactdyn.constitutive.pack_materials`, row 0), ``prm`` the model's
  parameter vector.  ``fails`` is asked only of an element that ductile damage has not failed that step;
* the failure cause it records (a name of :data:`impactdyn.wall.FAILURE_CAUSES`);
* its description for the stage record and the report (:attr:`FailureLaw.describe`, under ``describe_key``).

The ``[wall_solver]`` key ``spall_law`` takes any registered name (:class:`impactdyn.wall.WallOptions`).
docs/extending.md shows a law added in one module.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from impactdyn._jitcache import in_package
from impactdyn._registry import Registry

#: Where a law's constants start in the model's parameter vector: ``prm[J_LAW:]`` (the Johnson–Cook model's
#: own switches and damage constants come first, :mod:`impactdyn.wall._johnson_cook`).
J_LAW = 9

#: Registered failure laws by name (the case key ``spall_law``), filled by the modules of
#: :mod:`impactdyn.wall.failure_laws` (and by whoever registers one of their own).
FAILURE_LAWS: Registry["FailureLaw"] = Registry("wall failure law", "spall_law")


@dataclass(frozen=True)
class FailureLaw:
    """A wall failure law (module docstring).

    name : the registry key, the value of ``spall_law``.
    description : one line: the criterion and its source.
    cause : the :data:`impactdyn.wall.FAILURE_CAUSES` name an element failed by this law records.
    accumulate, fails : the compiled kernels (module docstring).
    library_constants : material → the law's constants as the material holds them (a record with a
        ``source``, a number), or None where it has none.
    kernel_constants : constants → the floats the kernel reads at ``prm[J_LAW:]`` (in that order).
    describe : constants → what the stage record and the report show of them (units in the keys).
    describe_key : the key of :meth:`impactdyn.wall.JohnsonCookModel.describe` that holds :attr:`describe`'s
        value (None for a model that does not use this law).
    required : a material without the constants refuses the law (True), or runs without a spall
        criterion (False: the cut-off of a material without a spall strength).
    needs : what the material must have, for the refusal ("Tuler-Butcher constants").
    """

    name: str
    description: str
    cause: str
    accumulate: Callable
    fails: Callable
    library_constants: Callable[[Any], Any]
    kernel_constants: Callable[[Any], tuple[float, ...]]
    describe: Callable[[Any], Any]
    describe_key: str
    required: bool = True
    needs: str = "constants"

    @property
    def in_package(self) -> bool:
        """Whether both kernels are this package's code (then the compiled update is cached on disk:
        :mod:`impactdyn._jitcache` stamps the cache with the package's sources only)."""
        return all(in_package(fn.py_func.__code__.co_filename) for fn in (self.accumulate, self.fails))
