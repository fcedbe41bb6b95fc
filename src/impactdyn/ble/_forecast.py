"""Verdicts scored as forecasts: the Brier score and the log-loss of P(perforation), with bootstrap intervals.

A yes/no verdict near the ballistic limit cannot be right much more than the tests agree with
themselves (half of the shots within 5 % of the equation's limit flip), and counting hits hides how
sure a verdict was.  A forecast P of each shot's perforation is scored instead by proper scoring rules
(Gneiting & Raftery 2007, J. Am. Stat. Assoc. 102:359), lower is better:

* Brier score  B = (1/n) Σ (Pᵢ − yᵢ)²  (Brier 1950): 0 for a sure and right forecaster, 0.25 for one that
  always says ½;
* log-loss  L = −(1/n) Σ [yᵢ ln Pᵢ + (1 − yᵢ) ln(1 − Pᵢ)], with P clipped to [1/(2N), 1 − 1/(2N)] where
  N is the number of draws behind it (k of N draws cannot tell P = 0 from P < 1/N; without the clip one
  sure and wrong verdict makes L infinite); ln 2 = 0.693 for the forecaster of ½.

Each score's 95 % interval is a percentile bootstrap over the shots (:data:`BOOTSTRAP_SAMPLES` resamples,
a fixed seed so a rescoring gives the same interval; Efron & Tibshirani 1993, ch. 13).

The reliability diagram (Murphy & Winkler 1977, Appl. Statist. 26:41; Bröcker & Smith 2007, Weather
Forecast. 22:651) asks whether the forecast P means what it says: the shots are put in bins of P
(:data:`RELIABILITY_EDGES`) and each bin's observed frequency of perforation, with its Wilson 95 % interval,
is set against the bin's mean P; a reliable forecast lies on the diagonal within the intervals.

Two baselines on the same shots: the JSC 2011 verdict as P = 0 or 1 (clipped as the simulation's), and
the test database's own logistic in d/d_c (:func:`database_logistic`): perforation against ln(d/d_c) fitted,
as :func:`impactdyn.ble.fit_limit` fits one configuration, to the database's Al-on-Al shots at normal
incidence and 3–7.2 km/s, less the shots being scored.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from scipy import special

#: Bootstrap resamples of a score's interval, and their seed.
BOOTSTRAP_SAMPLES = 2000
BOOTSTRAP_SEED = 20261204
#: The database's shots behind the logistic baseline: normal incidence and this speed range (the validation
#: sets' 3–7.57 km/s, to the 7.2 km/s where the packaged database's normal shots thin out): 575 shots.
#: Bin edges of P in the reliability diagram: five bins, since a validation set holds a dozen or a few dozen
#: shots and finer bins would hold one or two each (the last bin closed: P = 1 falls in it).
RELIABILITY_EDGES = (0.0, 0.2, 0.4, 0.6, 0.8, 1.0)
LOGISTIC_OBLIQUITY_DEG = 0.0
LOGISTIC_VELOCITY_KM_S = (3.0, 7.2)


def brier_score(p, y) -> float:
    """B = mean (P − y)² (module docstring)."""
    p, y = np.asarray(p, float), np.asarray(y, float)
    return float(np.mean((p - y) ** 2))


def log_loss(p, y, draws) -> float:
    """L = −mean [y ln P + (1 − y) ln(1 − P)], P clipped to [1/(2N), 1 − 1/(2N)] with N = ``draws`` per shot."""
    p, y, n = np.asarray(p, float), np.asarray(y, float), np.asarray(draws, float)
    p = np.clip(p, 0.5 / n, 1.0 - 0.5 / n)
    return float(-np.mean(y * np.log(p) + (1.0 - y) * np.log1p(-p)))


def bootstrap_interval(score: Callable[[np.ndarray], float], n: int, confidence: float = 0.95) -> tuple[float, float]:
    """The percentile bootstrap interval of ``score(indices)`` over ``n`` shots resampled with replacement."""
    rng = np.random.default_rng(BOOTSTRAP_SEED)
    values = [score(rng.integers(0, n, n)) for _ in range(BOOTSTRAP_SAMPLES)]
    tail = 50.0 * (1.0 - confidence)
    low, high = np.percentile(values, [tail, 100.0 - tail])
    return float(low), float(high)


def database_logistic(exclude_lines=()) -> Callable[[np.ndarray], np.ndarray] | None:
    """P(perforation | d/d_c) of the test database (module docstring), fitted without the shots on the lines
    ``exclude_lines``; None where the fit is refused (:func:`impactdyn.ble.fit_limit`'s reasons)."""
    from impactdyn.ble._derived_limits import fit_limit
    from impactdyn.ble._validate import validate

    scored = validate()
    db = scored.database
    v_lo, v_hi = LOGISTIC_VELOCITY_KM_S
    keep = ((np.abs(db.obliquity_deg) <= LOGISTIC_OBLIQUITY_DEG) & (db.velocity_km_s >= v_lo)
            & (db.velocity_km_s <= v_hi) & ~np.isin(db.line, list(exclude_lines)))
    ratio = db.diameter_cm[keep] / scored.limit.threshold_cm[keep]
    fit = fit_limit(ratio, db.perforated[keep])
    if fit.refused is not None:
        return None
    slope, centre = fit.slope, np.log(fit.d50_cm)
    return lambda r: special.expit(slope * (np.log(np.asarray(r, float)) - centre))


def reliability(p, y, edges=RELIABILITY_EDGES) -> list[dict]:
    """The reliability diagram's bins (module docstring): for each bin of ``p`` holding shots, their number,
    mean P, the observed frequency of perforation among them (``y``) and its Wilson 95 % interval."""
    from impactdyn.ble._scoring import wilson_interval

    p, y = np.asarray(p, float), np.asarray(y, bool)
    index = np.clip(np.searchsorted(edges, p, side="right") - 1, 0, len(edges) - 2)
    rows = []
    for b in range(len(edges) - 1):
        inside = index == b
        n, k = int(inside.sum()), int(y[inside].sum())
        if n:
            low, high = wilson_interval(k, n)
            rows.append({"bin": [edges[b], edges[b + 1]], "shots": n, "mean_p": float(p[inside].mean()),
                         "observed": k / n, "observed_95": [low, high]})
    return rows


def forecast_scores(p, draws, perforated, forecasts: dict[str, np.ndarray]) -> dict:
    """Brier and log-loss with their bootstrap intervals of the simulation's P (``p``, each from ``draws``
    draws) and of each baseline in ``forecasts`` (name → P per shot; clipped as the simulation's), against
    the tests' outcomes ``perforated``."""
    y = np.asarray(perforated, float)
    n = np.asarray(draws, float)
    out = {}
    for name, q in {"simulated": np.asarray(p, float), **{k: np.asarray(v, float) for k, v in forecasts.items()}}.items():
        out[name] = {
            "brier": brier_score(q, y),
            "brier_95": list(bootstrap_interval(lambda i: brier_score(q[i], y[i]), len(y))),
            "log_loss": log_loss(q, y, n),
            "log_loss_95": list(bootstrap_interval(lambda i: log_loss(q[i], y[i], n[i]), len(y))),
            "reliability": reliability(q, y)}
    return out
