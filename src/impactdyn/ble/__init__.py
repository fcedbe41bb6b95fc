"""Ballistic limit equations: NASA JSC Whipple shield and Cour-Palais single wall.

Literature units throughout: cm, g/cm³, km/s, ksi; obliquity in degrees from the
target normal.  Two Whipple equations are registered (:data:`EQUATIONS`, selected by
name with ``equation=``): ``"jsc1993"`` (Christiansen 1993) and ``"jsc2011"`` (Ryan &
Christiansen 2011, the default, :data:`DEFAULT_EQUATION`); :func:`validate` scores them on
the packaged test database of 1135 shots (:func:`read_database`).

>>> from impactdyn.ble import WhippleShield, critical_diameter, regime
>>> s = WhippleShield(bumper_thickness_cm=0.127, wall_thickness_cm=0.3175, spacing_cm=10.0,
...                   wall_yield_ksi=40.0)
>>> round(critical_diameter(s, 7.0, 25.0, 2.7, equation="jsc1993"), 3), regime(7.0, 25.0).value
(0.521, 'shatter')
"""

from impactdyn.ble import _jsc, _jsc2011  # noqa: F401  (each registers its equation)
from impactdyn.ble._curve import DEFAULT_VELOCITIES_KM_S, BallisticLimitCurve
from impactdyn.ble._forecast import brier_score, database_logistic, forecast_scores, log_loss, reliability
from impactdyn.ble._database import DATABASE_PATH, ShotDatabase, nearby_shots, read_database
from impactdyn.ble._scoring import (
    DISTANCE_BANDS,
    BandScore,
    McNemar,
    Proportion,
    VerdictScore,
    mcnemar,
    mcnemar_exact,
    score_by_distance,
    wilson_interval,
)
from impactdyn.ble._equation import (
    MAX_OBLIQUITY_DEG,
    V_HYPERVELOCITY_MIN_KM_S,
    BallisticLimit,
    Regime,
    WhippleEquation,
)
from impactdyn.ble._plot import check_plot_path, plot_ballistic_limit, plot_reliability, plot_validation
from impactdyn.ble._check import positive as check_positive
from impactdyn.ble._check import scalar_obliquity as check_obliquity
from impactdyn.ble._registry import DEFAULT_EQUATION, EQUATIONS, get_equation
from impactdyn.ble._derived_limits import (
    CONFIGURATION_OBLIQUITY_DEG,
    CONFIGURATION_TOLERANCE,
    MIN_EACH,
    MIN_SHOTS,
    VELOCITY_BAND_KM_S,
    Configuration,
    DerivedLimit,
    LimitFit,
    configurations,
    derived_limits,
    fit_limit,
    one_record_per_firing,
)
from impactdyn.ble._shield import ALUMINIUM_DENSITY_G_CM3, WhippleShield
from impactdyn.ble._single_wall import (
    AL6061_T6_BRINELL,
    AL_SOUND_SPEED_KM_S,
    BRINELL_HARDNESS,
    FailureMode,
    SingleWall,
    penetration_depth,
    rear_wall,
    single_wall_ballistic_limit_curve,
    single_wall_critical_diameter,
    single_wall_perforates,
)
from impactdyn.ble._validate import OBLIQUITY_BANDS, Scores, Validation, validate
from impactdyn.ble._whipple import (
    ballistic_limit,
    ballistic_limit_curve,
    critical_diameter,
    jsc_verdict,
    normal_velocity,
    perforates,
    regime,
    regime_boundaries,
)

__all__ = [
    "AL6061_T6_BRINELL", "AL_SOUND_SPEED_KM_S", "ALUMINIUM_DENSITY_G_CM3", "BRINELL_HARDNESS", "DATABASE_PATH", "DEFAULT_EQUATION",
    "DEFAULT_VELOCITIES_KM_S", "EQUATIONS", "MAX_OBLIQUITY_DEG", "OBLIQUITY_BANDS", "V_HYPERVELOCITY_MIN_KM_S",
    "BallisticLimit", "BallisticLimitCurve", "FailureMode", "Regime", "Scores", "ShotDatabase", "SingleWall",
    "Validation", "WhippleEquation", "WhippleShield", "ballistic_limit", "ballistic_limit_curve", "check_obliquity",
    "check_plot_path", "check_positive",
    "DISTANCE_BANDS", "BandScore", "McNemar", "Proportion", "VerdictScore", "mcnemar", "mcnemar_exact",
    "score_by_distance", "wilson_interval", "brier_score", "database_logistic", "forecast_scores", "log_loss",
    "reliability", "plot_reliability",
    "CONFIGURATION_OBLIQUITY_DEG", "CONFIGURATION_TOLERANCE", "MIN_EACH", "MIN_SHOTS", "VELOCITY_BAND_KM_S",
    "Configuration", "DerivedLimit", "LimitFit", "configurations", "derived_limits", "fit_limit",
    "one_record_per_firing",
    "critical_diameter", "get_equation", "jsc_verdict", "nearby_shots", "normal_velocity", "penetration_depth",
    "perforates", "plot_ballistic_limit", "plot_validation", "read_database", "rear_wall", "regime",
    "regime_boundaries", "single_wall_ballistic_limit_curve", "single_wall_critical_diameter",
    "single_wall_perforates", "validate",
]
