"""Ballistic limit equations: NASA JSC Whipple shield and Cour-Palais single wall.

Literature units throughout: cm, g/cm³, km/s, ksi; obliquity in degrees from the
target normal.

>>> from impactdyn.ble import WhippleShield, critical_diameter, regime
>>> s = WhippleShield(bumper_thickness_cm=0.127, wall_thickness_cm=0.3175, spacing_cm=10.0,
...                   wall_yield_ksi=40.0)
>>> round(critical_diameter(s, 7.0, 25.0, 2.7), 3), regime(7.0, 25.0).value
(0.521, 'shatter')
"""

from impactdyn.ble._jsc import (
    DEFAULT_VELOCITIES_KM_S,
    V_BALLISTIC_MAX_KM_S,
    V_HYPERVELOCITY_MIN_KM_S,
    BallisticLimitCurve,
    Regime,
    WhippleShield,
    ballistic_limit_curve,
    critical_diameter,
    normal_velocity,
    perforates,
    regime,
    regime_boundaries,
)
from impactdyn.ble._plot import check_plot_path, plot_ballistic_limit
from impactdyn.ble._single_wall import (
    AL6061_T6_BRINELL,
    AL_SOUND_SPEED_KM_S,
    FailureMode,
    SingleWall,
    penetration_depth,
    rear_wall,
    single_wall_ballistic_limit_curve,
    single_wall_critical_diameter,
    single_wall_perforates,
)

__all__ = [
    "AL6061_T6_BRINELL", "AL_SOUND_SPEED_KM_S", "DEFAULT_VELOCITIES_KM_S", "V_BALLISTIC_MAX_KM_S",
    "V_HYPERVELOCITY_MIN_KM_S", "BallisticLimitCurve", "FailureMode", "Regime", "SingleWall", "WhippleShield",
    "ballistic_limit_curve", "check_plot_path", "critical_diameter", "normal_velocity", "penetration_depth",
    "perforates", "plot_ballistic_limit", "rear_wall", "regime", "regime_boundaries",
    "single_wall_ballistic_limit_curve", "single_wall_critical_diameter", "single_wall_perforates",
]
