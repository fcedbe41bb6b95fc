r"""The ballistic limit the tests themselves give: a logistic fit of perforation against diameter.

On one shield configuration in one velocity band, the probability that a sphere of
diameter d perforates the rear wall is modelled as::

    P(perforation | d) = 1 / (1 + exp(−b (ln d − ln d50)))  = 1 / (1 + exp(−(a + b ln d))),
    a = −b ln d50,   d50 = exp(−a/b)

and (a, b) are found by maximum likelihood (a binomial GLM with the logit link,
McCullagh & Nelder 1989 §4; Finney 1971 for the same fit in dose–response).  The covariate
is ln d, not d: a diameter is positive and the limit's scatter is multiplicative (the JSC
equations are power laws in d), so ln d gives d50 > 0 and an interval that is not forced to
be symmetric in d.

Interval on d50: profile likelihood.  With m = ln d50 the model is logit P = b (ln d − m);
the interval holds the m whose profile deviance D(m) = 2 [ℓ(m̂, b̂) − max_b ℓ(m, b)] is at
most χ²₁(1 − α) (3.841 at 95 %; Venzon & Moolgavkar 1988).  It was chosen over the delta
method because d50 is a ratio of parameters, −a/b: when b is poorly determined (few shots,
little overlap) the delta-method interval is symmetric in ln d50 and too short, while the
profile interval follows the likelihood's shape, is the same whichever parametrisation is
used, and may be open on one side, which honestly says that the shots do not bound d50 there
(as Fieller's interval does for a ratio).  An end not reached within a factor
:data:`SEARCH_FACTOR` beyond the shots' diameters is reported as ``None`` (unbounded).

When the fit is refused (:attr:`LimitFit.refused` says why):

* fewer than :data:`MIN_SHOTS` shots or fewer than :data:`MIN_EACH` of either outcome;
* the outcomes are separated in d (every held shot no larger than every perforated one):
  the likelihood then grows without bound as b → ∞ and the MLE does not exist (Albert &
  Anderson 1984); the limit is only known to lie in the bracket
  [largest held d, smallest perforated d], which is reported instead;
* the outcomes are separated the wrong way round (every perforated shot no larger than
  every held one) or the fitted slope is not positive: larger projectiles would be safer,
  and d50 means nothing.

Configurations (:func:`configurations`): shots with the same projectile, bumper and wall
alloys, whose bumper thickness t_b, wall thickness t_w and stand-off S are each within
:data:`CONFIGURATION_TOLERANCE` (5 %) of a reference shot's and whose obliquity is within
:data:`CONFIGURATION_OBLIQUITY_DEG` (2.5°) of it.  5 % spans the tolerance with which the
reports give plate thicknesses (0.079 and 0.084 cm for one bumper of the AFML series) while
keeping apart the nominal gauges of a test matrix, which step by 20 % or more; 2.5°
separates every pair of angles the test programmes chose (0, 15, 30, 45, 60, 65°...).
Velocity bands are [k w, (k + 1) w) with w = :data:`VELOCITY_BAND_KM_S` (1 km/s): at a fixed
shield the JSC limit moves by V^{-2/3} in the hypervelocity regime, 10 % across 6.5–7.5 km/s,
less than the scatter of the tests about it.

Sources: D.J. Finney, Probit Analysis, 3rd ed., Cambridge (1971); P. McCullagh, J.A. Nelder,
Generalized Linear Models, 2nd ed., Chapman & Hall (1989); A. Albert, J.A. Anderson,
Biometrika 71 (1984) 1–10; D.J. Venzon, S.H. Moolgavkar, Appl. Stat. 37 (1988) 87–94.
"""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import asdict, dataclass

import numpy as np
from scipy import optimize, special, stats

from impactdyn.ble._database import ShotDatabase

#: Fewest shots a fit takes: two parameters from binary outcomes need several shots on each
#: side of the limit; with fewer than 6 the fit rests on one or two shots at the overlap.
MIN_SHOTS = 6
#: Fewest shots of each outcome (perforated, held) a fit takes.
MIN_EACH = 2
#: Default confidence of the d50 interval.
CONFIDENCE = 0.95
#: The profile interval's ends are searched up to this factor beyond the smallest and largest d.
SEARCH_FACTOR = 10.0
#: Relative bound on t_b, t_w and S within a configuration (module docstring).
CONFIGURATION_TOLERANCE = 0.05
#: Bound on obliquity within a configuration, degrees (module docstring).
CONFIGURATION_OBLIQUITY_DEG = 2.5
#: Width of a velocity band, km/s (module docstring).
VELOCITY_BAND_KM_S = 1.0


@dataclass(frozen=True)
class LimitFit:
    """A logistic fit of perforation against ln d, or why there is none.

    ``d50_cm``, ``low_cm``, ``high_cm``, ``slope``: the 50 % diameter, its profile-likelihood
    interval (an end is ``None`` where the shots do not bound it) and b; all ``None`` when
    ``refused`` gives the reason.  ``largest_held_cm``, ``smallest_perforated_cm``: the
    bracket the shots set on the limit (``None`` without that outcome).
    """

    shots: int
    perforated: int
    d50_cm: float | None
    low_cm: float | None
    high_cm: float | None
    slope: float | None
    largest_held_cm: float | None
    smallest_perforated_cm: float | None
    refused: str | None
    confidence: float


def _log_likelihood(b: float, m: float, x: np.ndarray, y: np.ndarray) -> float:
    """ℓ(m, b) = Σ [y η − ln(1 + e^η)], η = b (x − m)."""
    eta = b * (x - m)
    return float(np.sum(y * eta - np.logaddexp(0.0, eta)))


def _fit_ab(x: np.ndarray, y: np.ndarray) -> tuple[float, float]:
    """The MLE of (a, b) in logit P = a + b x (it exists: checked by the caller)."""
    design = np.column_stack([np.ones_like(x), x])

    def minus_l(beta):
        eta = design @ beta
        return float(np.sum(np.logaddexp(0.0, eta) - y * eta))

    def gradient(beta):
        return design.T @ (special.expit(design @ beta) - y)

    def hessian(beta):
        p = special.expit(design @ beta)
        return design.T @ (design * (p * (1.0 - p))[:, None])

    result = optimize.minimize(minus_l, np.zeros(2), jac=gradient, hess=hessian, method="trust-exact",
                               options={"gtol": 1e-10})
    return float(result.x[0]), float(result.x[1])


def _profile(m: float, x: np.ndarray, y: np.ndarray, b0: float) -> float:
    """max_b ℓ(m, b): concave in b (η is linear in b), so a bounded scalar search finds it."""
    z = x - m
    result = optimize.minimize(lambda b: -_log_likelihood(b[0], m, x, y), np.array([b0]),
                               jac=lambda b: np.array([-np.sum(z * (y - special.expit(b[0] * z)))]),
                               hess=lambda b: np.array([[np.sum(z * z * special.expit(b[0] * z)
                                                                * (1.0 - special.expit(b[0] * z)))]]),
                               method="trust-exact", options={"gtol": 1e-10})
    return -float(result.fun)


def _interval_end(deviance, m_hat: float, limit: float, critical: float) -> float | None:
    """The first m from m̂ toward ``limit`` where the profile deviance reaches ``critical``."""
    steps = np.linspace(m_hat, limit, 201)[1:]
    previous = m_hat
    for m in steps:
        if deviance(m) >= critical:
            return optimize.brentq(lambda t: deviance(t) - critical, previous, m, xtol=1e-10)
        previous = m
    return None


def _refusal(d: np.ndarray, perforated: np.ndarray, shots: int, n_perforated: int) -> str | None:
    held_d, perf_d = d[~perforated], d[perforated]
    if shots < MIN_SHOTS or min(n_perforated, shots - n_perforated) < MIN_EACH:
        return (f"too few shots: {shots} ({n_perforated} perforated); a fit needs {MIN_SHOTS} "
                f"with {MIN_EACH} of each outcome")
    if held_d.max() <= perf_d.min():
        return (f"separable: every held shot ({held_d.max():.4g} cm at most) is no larger than every "
                f"perforated one ({perf_d.min():.4g} cm at least); the MLE does not exist")
    if perf_d.max() <= held_d.min():
        return "separated the wrong way: every perforated shot is no larger than every held one"  # b → −∞
    return None


def fit_limit(diameter_cm, perforated, confidence: float = CONFIDENCE) -> LimitFit:
    """Fit P(perforation) against ln d (module docstring) on shots of one configuration and speed.

    ``diameter_cm``: projectile diameters (> 0); ``perforated``: outcomes (boolean), one per shot.
    """
    d = np.asarray(diameter_cm, dtype=float)
    perforated = np.asarray(perforated, dtype=bool)
    if d.shape != perforated.shape or d.ndim != 1:
        raise ValueError(f"diameter_cm and perforated must be 1-D of one length, got {d.shape}, {perforated.shape}")
    if not np.all(np.isfinite(d) & (d > 0.0)):
        raise ValueError("diameters must be finite and > 0")
    shots, n_perf = int(d.size), int(perforated.sum())
    bracket = dict(largest_held_cm=float(d[~perforated].max()) if n_perf < shots else None,
                   smallest_perforated_cm=float(d[perforated].min()) if n_perf else None)
    refused = _refusal(d, perforated, shots, n_perf)
    if refused is None:
        x, y = np.log(d), perforated.astype(float)
        a, b = _fit_ab(x, y)
        if b <= 0.0:
            refused = f"slope not positive: b = {b:.3g}, larger projectiles would be safer"
    if refused is not None:
        return LimitFit(shots, n_perf, None, None, None, None, refused=refused, confidence=confidence, **bracket)
    m_hat = -a / b
    l_hat = _log_likelihood(b, m_hat, x, y)

    def deviance(m):
        return 2.0 * (l_hat - _profile(m, x, y, b))

    critical = float(stats.chi2.ppf(confidence, 1))
    reach = math.log(SEARCH_FACTOR)
    low = _interval_end(deviance, m_hat, x.min() - reach, critical)
    high = _interval_end(deviance, m_hat, x.max() + reach, critical)
    return LimitFit(shots, n_perf, d50_cm=math.exp(m_hat), low_cm=None if low is None else math.exp(low),
                    high_cm=None if high is None else math.exp(high), slope=b, refused=None,
                    confidence=confidence, **bracket)


@dataclass(frozen=True)
class Configuration:
    """A shield configuration: alloys and the reference shot's t_b, t_w, S (cm) and θ (degrees)."""

    projectile_material: str
    bumper_material: str
    wall_material: str
    bumper_thickness_cm: float
    wall_thickness_cm: float
    spacing_cm: float
    obliquity_deg: float


def configurations(db: ShotDatabase) -> tuple[np.ndarray, list[Configuration]]:
    """Each shot's configuration (module docstring): an index into the returned list.

    References are taken in turn from the most-shot exact (alloys, t_b, t_w, S, θ) not yet
    placed (ties by those values), and take every unplaced shot within the tolerances of
    them, so every shot is within the tolerances of its configuration's reference.
    """
    alloys = np.array([f"{p}|{b}|{w}" for p, b, w in zip(db.projectile_material, db.bumper_material,
                                                       db.wall_material)], dtype=object)
    lengths = np.column_stack([db.bumper_thickness_cm, db.wall_thickness_cm, db.spacing_cm])
    count = Counter((alloys[i], *map(float, lengths[i]), float(db.obliquity_deg[i])) for i in range(len(db)))
    exact = sorted(count, key=lambda key: (-count[key], key))
    label = np.full(len(db), -1)
    found: list[Configuration] = []
    for key in exact:
        ref_alloys, tb, tw, s, theta = key
        here = (label < 0) & (alloys == ref_alloys) & (np.abs(db.obliquity_deg - theta) <= CONFIGURATION_OBLIQUITY_DEG)
        here &= np.all(np.abs(lengths / np.array([tb, tw, s]) - 1.0) <= CONFIGURATION_TOLERANCE, axis=1)
        if not here.any():  # its shots were taken by an earlier reference
            continue
        label[here] = len(found)
        found.append(Configuration(*ref_alloys.split("|"), float(tb), float(tw), float(s), float(theta)))
    return label, found


@dataclass(frozen=True)
class DerivedLimit:
    """The test-derived limit of one configuration in one velocity band [v_low, v_high) km/s."""

    configuration: Configuration
    velocity_low_km_s: float
    velocity_high_km_s: float
    lines: tuple[int, ...]
    fit: LimitFit

    def as_dict(self) -> dict:
        return asdict(self)


def one_record_per_firing(db: ShotDatabase) -> np.ndarray:
    """Mask keeping the first record of each twin group, and no record of a conflicting one.

    Twins are one firing (:mod:`impactdyn.ble._database`): counted twice they would weigh
    twice; with opposite outcomes nothing says what the firing did.
    """
    _, first = np.unique(db.twin_group, return_index=True)
    keep = np.zeros(len(db), dtype=bool)
    keep[first] = True
    return keep & ~db.twin_conflict


def derived_limits(db: ShotDatabase, band_km_s: float = VELOCITY_BAND_KM_S,
                   confidence: float = CONFIDENCE) -> list[DerivedLimit]:
    """:func:`fit_limit` on every configuration and velocity band with :data:`MIN_SHOTS` firings or more.

    One record per firing (:func:`one_record_per_firing`).  Refused fits are listed too, with
    their reason and bracket; the order is by configuration, then band.
    """
    db = db.subset(one_record_per_firing(db))
    label, found = configurations(db)
    band = np.floor(db.velocity_km_s / band_km_s).astype(int)
    out = []
    for c, configuration in enumerate(found):
        for k in np.unique(band[label == c]):
            here = (label == c) & (band == k)
            if here.sum() < MIN_SHOTS:
                continue
            out.append(DerivedLimit(configuration, float(k * band_km_s), float((k + 1) * band_km_s),
                                    tuple(int(i) for i in db.line[here]),
                                    fit_limit(db.diameter_cm[here], db.perforated[here], confidence)))
    return out
