r"""Statistics of a verdict score: proportions with their intervals, paired tests, bands.

A verdict ("perforated" or "held") called on a test shot is right or wrong; a score is a
binomial proportion over the shots, and two classifiers called on the same shots are
compared by their discordant pairs.

Wilson score interval (Wilson 1927; Newcombe 1998 method 3; Agresti & Coull 1998) of k
successes in n trials at confidence 1 − α, z = Φ⁻¹(1 − α/2)::

    p̂ = k/n,   centre = (k + z²/2) / (n + z²),
    half-width = z / (n + z²) · sqrt( k (n − k) / n + z²/4 )

It stays inside [0, 1], is not degenerate at k = 0 or k = n (where the Wald interval
p̂ ± z sqrt(p̂(1 − p̂)/n) has zero width), and keeps close to its nominal coverage for the
small counts of a band of shots (Agresti & Coull 1998, Brown, Cai & DasGupta 2001).

Exact McNemar test (McNemar 1947; Fagerland, Lydersen & Laake 2013): of the shots on which
two classifiers disagree, b are called right by the first only and c by the second only;
under the null hypothesis of equal accuracy each discordant shot is a fair coin, so::

    p_exact = min(1, 2 · F(min(b, c); b + c, 1/2))
    p_mid   = p_exact − f(min(b, c); b + c, 1/2)        b ≠ c
    p_mid   = 1 − f(b; 2b, 1/2) / 2                      b = c

with F and f the binomial CDF and PMF (Fagerland et al. 2013, eqs. 1–2 of their
supplement; with no discordant shot, b = c = 0, both are 1).  Fagerland et al. recommend
the mid-p form for small samples (the exact test is conservative); both are given.

Bands by distance from the equation's limit, |d/d_lim − 1| (:data:`DISTANCE_BANDS`): the
further a shot lies from the limit the easier its verdict, so an overall accuracy mixes easy
and hard shots in whatever proportion the test programme chose; a score by band does not.

Sources: E.B. Wilson, J. Am. Stat. Assoc. 22 (1927) 209–212; A. Agresti, B.A. Coull,
Am. Stat. 52 (1998) 119–126; R.G. Newcombe, Stat. Med. 17 (1998) 857–872; L.D. Brown,
T.T. Cai, A. DasGupta, Stat. Sci. 16 (2001) 101–133; Q. McNemar, Psychometrika 12 (1947)
153–157; M.W. Fagerland, S. Lydersen, P. Laake, BMC Med. Res. Methodol. 13 (2013) 91.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np
from scipy import stats

#: Bands of |d/d_lim − 1|, each [low, high): within 5 %, 5–15 %, 15–30 %, 30 % or more.
DISTANCE_BANDS = {"<5%": (0.0, 0.05), "5-15%": (0.05, 0.15), "15-30%": (0.15, 0.30), ">=30%": (0.30, math.inf)}
#: Default confidence of every interval here.
CONFIDENCE = 0.95


def wilson_interval(k: int, n: int, confidence: float = CONFIDENCE) -> tuple[float, float]:
    """Wilson score interval (module docstring) of ``k`` successes in ``n`` trials.

    ``(nan, nan)`` for n = 0: no trials say nothing about the proportion.
    """
    if not 0 <= k <= n:
        raise ValueError(f"need 0 <= k <= n, got k={k}, n={n}")
    if not 0.0 < confidence < 1.0:
        raise ValueError(f"confidence must be in (0, 1), got {confidence}")
    if n == 0:
        return math.nan, math.nan
    z = float(stats.norm.ppf(0.5 + confidence / 2.0))
    centre = (k + z * z / 2.0) / (n + z * z)
    half = z / (n + z * z) * math.sqrt(k * (n - k) / n + z * z / 4.0)
    # at k = 0 (k = n) the lower (upper) end is exactly 0 (1); rounding may leave it a hair off
    return (0.0 if k == 0 else centre - half), (1.0 if k == n else centre + half)


@dataclass(frozen=True)
class Proportion:
    """``count`` of ``of`` with its rate and Wilson interval; ``None`` where ``of`` is 0."""

    count: int
    of: int
    rate: float | None
    low: float | None
    high: float | None

    @classmethod
    def of_counts(cls, count: int, of: int, confidence: float = CONFIDENCE) -> Proportion:
        if of == 0:
            return cls(int(count), 0, None, None, None)
        low, high = wilson_interval(int(count), int(of), confidence)
        return cls(int(count), int(of), count / of, low, high)


@dataclass(frozen=True)
class McNemar:
    """Exact McNemar test: ``b`` shots right by the first classifier only, ``c`` by the second only."""

    b: int
    c: int
    p_exact: float
    p_mid: float


def mcnemar_exact(b: int, c: int) -> McNemar:
    """The exact and mid-p McNemar tests (module docstring) of the discordant counts ``b``, ``c``."""
    if b < 0 or c < 0:
        raise ValueError(f"discordant counts must be >= 0, got b={b}, c={c}")
    n, low = b + c, min(b, c)
    if n == 0:  # no discordant shot: no evidence either way
        return McNemar(0, 0, 1.0, 1.0)
    point = float(stats.binom.pmf(low, n, 0.5))
    if b == c:
        return McNemar(int(b), int(c), 1.0, 1.0 - point / 2.0)
    p_exact = min(1.0, 2.0 * float(stats.binom.cdf(low, n, 0.5)))
    return McNemar(int(b), int(c), p_exact, p_exact - point)


def mcnemar(truth, first, second) -> McNemar:
    """McNemar test of two classifiers' verdicts ``first``, ``second`` on the same shots.

    ``truth``, ``first``, ``second``: boolean arrays, one element per shot (perforated in
    the test; called perforated by each).  b counts the shots only ``first`` calls right,
    c those only ``second`` calls right.
    """
    truth, first, second = (np.asarray(a, dtype=bool) for a in (truth, first, second))
    right_1, right_2 = first == truth, second == truth
    return mcnemar_exact(int((right_1 & ~right_2).sum()), int((~right_1 & right_2).sum()))


@dataclass(frozen=True)
class BandScore:
    """One band's score: accuracy over its shots, false-safe rate over its perforated shots
    (perforated in the test, called safe: the dangerous error), false-alarm rate over its
    held shots (held in the test, called perforated)."""

    band: str
    shots: int
    accuracy: Proportion
    false_safe: Proportion
    false_alarm: Proportion


@dataclass(frozen=True)
class VerdictScore:
    """Scores by band of |d/d_lim − 1| (:data:`DISTANCE_BANDS`) and overall.

    ``unbanded``: shots with no finite d/d_lim, counted in ``overall`` only.
    """

    bands: tuple[BandScore, ...]
    overall: BandScore
    unbanded: int
    confidence: float

    def as_dict(self) -> dict:
        """Plain types only (``json.dumps`` takes it); empty denominators are ``None``."""
        return asdict(self)


def band_score(band: str, perforated: np.ndarray, called: np.ndarray, confidence: float = CONFIDENCE) -> BandScore:
    """The :class:`BandScore` of outcomes ``perforated`` against verdicts ``called`` (boolean arrays)."""
    held = ~perforated
    return BandScore(
        band=band, shots=int(perforated.size),
        accuracy=Proportion.of_counts(int((perforated == called).sum()), perforated.size, confidence),
        false_safe=Proportion.of_counts(int((perforated & ~called).sum()), int(perforated.sum()), confidence),
        false_alarm=Proportion.of_counts(int((held & called).sum()), int(held.sum()), confidence),
    )


def score_by_distance(ratio, perforated, called, confidence: float = CONFIDENCE) -> VerdictScore:
    """Score verdicts by band of distance from the limit (module docstring).

    ``ratio``: d/d_lim per shot (the projectile diameter over the diameter at which the
    verdict changes; NaN where there is none); ``perforated``: the test outcome;
    ``called``: the verdict "perforated".  Arrays of one shape.
    """
    ratio = np.asarray(ratio, dtype=float)
    perforated, called = np.asarray(perforated, dtype=bool), np.asarray(called, dtype=bool)
    if not ratio.shape == perforated.shape == called.shape:
        raise ValueError(f"ratio, perforated and called must have one shape, got "
                         f"{ratio.shape}, {perforated.shape}, {called.shape}")
    distance = np.abs(ratio - 1.0)
    bands = []
    for name, (low, high) in DISTANCE_BANDS.items():
        inside = (distance >= low) & (distance < high)
        bands.append(band_score(name, perforated[inside], called[inside], confidence))
    return VerdictScore(bands=tuple(bands), overall=band_score("overall", perforated, called, confidence),
                        unbanded=int((~np.isfinite(distance)).sum()), confidence=confidence)
