"""What a wall run returns: output frames, time histories, measures and verdict."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from impactdyn.wall._mesh import WallMesh
from impactdyn.wall._options import WallOptions

#: Time histories of :attr:`WallResult.history` (units): time µs; energies g·cm²/µs²
#: (1 g·cm²/µs² = 10⁵ J); rear_bulge, front_dent cm; rear_velocity cm/µs; momentum g·cm/µs.
HISTORY_KEYS = ("time", "load_work", "kinetic", "kinetic_wall", "internal", "plastic", "hourglass", "bulk_viscous",
                "eroded", "balance_error", "rear_bulge", "front_dent", "rear_velocity", "momentum_y")

#: How a run ended (``measures["ended_by"]``): the wall's kinetic energy decayed to
#: ``decay_fraction`` of its peak after the last arrival; a through-thickness path of failed material
#: held for ``perforation_hold_us`` after the last arrival (the verdict can no longer change: failure
#: is for good); the ``end_time_us`` asked for; or the ``max_time_us`` ceiling before any of them,
#: with the wall not at rest.
ENDED_BY_DECAY, ENDED_BY_PERFORATION, ENDED_AT_END_TIME, ENDED_AT_CEILING = "decay", "perforated", "end_time", "ceiling"
ENDINGS = (ENDED_BY_DECAY, ENDED_BY_PERFORATION, ENDED_AT_END_TIME, ENDED_AT_CEILING)


@dataclass(frozen=True, eq=False)
class WallFrame:
    """The wall at one output time (float32 fields to keep many frames small).

    time : µs.
    displacement, velocity : (n_nodes, 3), cm and cm/µs (velocity half a step behind).
    plastic_strain, damage, pressure, von_mises : (n_elements,), pressure and von Mises in Mbar.
    failure_cause : (n_elements,) uint8, 0 intact, else 1 + the index in :data:`FAILURE_CAUSES`
        of the criterion that failed the element (:attr:`failed` is its non-zero mask).
    eroded : (n_elements,) bool.
    """

    time: float
    displacement: np.ndarray
    velocity: np.ndarray
    plastic_strain: np.ndarray
    damage: np.ndarray
    pressure: np.ndarray
    von_mises: np.ndarray
    failure_cause: np.ndarray
    eroded: np.ndarray

    @property
    def failed(self) -> np.ndarray:
        """(n_elements,) bool: the failed elements."""
        return self.failure_cause != 0


@dataclass(frozen=True, eq=False)
class WallResult:
    """Outcome of :func:`impactdyn.wall.run_wall`.

    verdict : "perforation", "detached spall" or "no perforation" (:mod:`._verdict`).
    evidence : which criterion decided, with counts.
    measures : continuous measures and the energy and momentum balance (floats, JSON-ready).
    history : time histories (:data:`HISTORY_KEYS`), arrays of one length.
    frames : output frames in time order (the last one is the end state).
    mesh : the solver mesh.
    options : the options used.
    model : the material model's constants and sources (``WallModel.describe()``).
    """

    verdict: str
    evidence: dict[str, Any]
    measures: dict[str, float]
    history: dict[str, np.ndarray]
    frames: tuple[WallFrame, ...]
    mesh: WallMesh
    options: WallOptions
    model: dict[str, Any] = field(default_factory=dict)

    @property
    def final(self) -> WallFrame:
        """The state at the end of the run."""
        return self.frames[-1]

    def summary(self) -> dict[str, Any]:
        """Verdict, evidence, measures and the model, JSON-ready (for stage files)."""
        return {"verdict": self.verdict, "evidence": self.evidence, "measures": self.measures,
                "mesh": self.mesh.describe(), "model": self.model}
