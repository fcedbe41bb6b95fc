"""How often a Whipple equation calls the test shots right.

Each shot is evaluated with its own bumper, wall, stand-off, yield stress, densities,
speed and obliquity; the equation calls perforation where the projectile diameter
exceeds its threshold (d_c, or where the 2011 form has no fixed point the diameter at
which perforation starts, see :mod:`impactdyn.ble._jsc2011`).  Scores:

* accuracy: shots called right / shots;
* false-safe rate: perforations called safe / perforations (the dangerous error);
* false-alarm rate: non-perforations called perforation / non-perforations;

overall, on the shots where d_c exists, by the equation's own regime, and by obliquity
band (:data:`OBLIQUITY_BANDS`).  Nothing here is fitted: the database only judges.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from impactdyn.ble._database import ShotDatabase, read_database
from impactdyn.ble._equation import BallisticLimit, Regime
from impactdyn.ble._registry import get_equation

#: Obliquity bands: θ = 0, 0 < θ < 45°, 45° ≤ θ ≤ 65°, θ > 65° (evaluated at the 65° cap).
OBLIQUITY_BANDS = ("0°", "0–45°", "45–65°", "65–90° (capped)")


def obliquity_band(theta: np.ndarray) -> np.ndarray:
    """The :data:`OBLIQUITY_BANDS` label of each angle (degrees, 0 ≤ θ < 90)."""
    return np.select([theta == 0.0, theta < 45.0, theta <= 65.0], OBLIQUITY_BANDS[:3], OBLIQUITY_BANDS[3])


def _rate(count: int, of: int) -> float | None:
    return count / of if of else None


@dataclass(frozen=True)
class Scores:
    """Counts of one group of shots; the rates are ``None`` for an empty denominator."""

    shots: int
    perforated: int
    correct: int
    false_safe: int
    false_alarm: int

    @classmethod
    def of(cls, perforated: np.ndarray, called: np.ndarray) -> Scores:
        """Scores of the outcomes ``perforated`` against the calls ``called`` (boolean arrays)."""
        return cls(shots=int(perforated.size), perforated=int(perforated.sum()),
                   correct=int((perforated == called).sum()), false_safe=int((perforated & ~called).sum()),
                   false_alarm=int((~perforated & called).sum()))

    @property
    def accuracy(self) -> float | None:
        return _rate(self.correct, self.shots)

    @property
    def false_safe_rate(self) -> float | None:
        return _rate(self.false_safe, self.perforated)

    @property
    def false_alarm_rate(self) -> float | None:
        return _rate(self.false_alarm, self.shots - self.perforated)

    def as_dict(self) -> dict:
        return {"shots": self.shots, "perforated": self.perforated, "correct": self.correct,
                "false_safe": self.false_safe, "false_alarm": self.false_alarm, "accuracy": self.accuracy,
                "false_safe_rate": self.false_safe_rate, "false_alarm_rate": self.false_alarm_rate}


@dataclass(frozen=True)
class Validation:
    """One equation on a test database: the per-shot limits and calls, and the scores."""

    equation: str
    title: str
    database: ShotDatabase
    limit: BallisticLimit
    called: np.ndarray
    overall: Scores
    with_fixed_point: Scores
    by_regime: dict[str, Scores]
    by_obliquity: dict[str, Scores]

    @property
    def no_fixed_point(self) -> int:
        """Shots on which the equation has no critical diameter (scored at their threshold)."""
        return self.overall.shots - self.with_fixed_point.shots

    def as_dict(self) -> dict:
        return {"equation": self.equation, "title": self.title, "database": self.database.path,
                "overall": self.overall.as_dict(), "no_fixed_point": self.no_fixed_point,
                "with_fixed_point": self.with_fixed_point.as_dict(),
                "by_regime": {k: s.as_dict() for k, s in self.by_regime.items()},
                "by_obliquity": {k: s.as_dict() for k, s in self.by_obliquity.items()}}


def _groups(labels: np.ndarray, order, perforated: np.ndarray, called: np.ndarray) -> dict[str, Scores]:
    return {str(k): Scores.of(perforated[labels == k], called[labels == k]) for k in order}


def validate(equation: str | None = None, database: ShotDatabase | None = None) -> Validation:
    """Score a Whipple equation (``None``: the default) on a database (``None``: the packaged one)."""
    eq = get_equation(equation)
    db = read_database() if database is None else database
    limit = eq.limit(db, db.velocity_km_s, db.obliquity_deg, db.projectile_density_g_cm3)
    called = db.diameter_cm > limit.threshold_cm
    p = db.perforated
    fixed = ~np.isnan(limit.critical_diameter_cm)
    return Validation(
        equation=eq.name, title=eq.title, database=db, limit=limit, called=called,
        overall=Scores.of(p, called),
        with_fixed_point=Scores.of(p[fixed], called[fixed]),
        by_regime=_groups(limit.regime, list(Regime), p, called),
        by_obliquity=_groups(obliquity_band(db.obliquity_deg), OBLIQUITY_BANDS, p, called),
    )
