"""
A ballistic-limit curve with the nearby test shots
==================================================

The Table 2 shield of the 1994 report (bumper 0.127 cm, rear wall 0.3175 cm of yield stress
40 ksi, 10.16 cm apart, all aluminium) under the NASA JSC Whipple-shield equations, and the
light-gas-gun shots of the packaged test database fired at shields like it.
The equations are in :doc:`/theory/ble`; the command line gives the same curve with
``impactdyn ble whipple ... --plot curve.png --test-shots``.
"""

# %%
# The shield and its critical diameter at the report's four shots (25° from the normal):
import matplotlib.pyplot as plt
import numpy as np

from impactdyn.ble import WhippleShield, ballistic_limit_curve, jsc_verdict, nearby_shots

shield = WhippleShield(bumper_thickness_cm=0.127, wall_thickness_cm=0.3175, spacing_cm=10.16,
                       wall_yield_ksi=40.0)
for velocity, diameter in [(7.0, 0.575), (7.0, 0.475), (10.0, 0.530), (10.0, 0.430)]:
    verdict = jsc_verdict(shield, diameter, velocity, 25.0, projectile_density=2.703)
    d_c = verdict["critical_diameter_cm"]
    print(f"V = {velocity:4.1f} km/s, d = {diameter:.3f} cm: d_c = {d_c:.3f} cm "
          f"({verdict['regime']}) -> {verdict['verdict']}")

# %%
# The database holds few oblique shots on shields like this one, and fifteen at normal
# incidence: the test shots on shields within ±10 % of this one in t_b, t_w and S, fired
# within ±10° of the normal. Each has its own shield, so it is drawn where it was fired, not
# rescaled to this one.
shots = nearby_shots(shield, obliquity_deg=0.0)
print(f"{len(shots)} nearby shots at normal incidence, "
      f"{int(shots.perforated.sum())} of them perforated the wall")

# %%
# The two registered forms of the equation at normal incidence over 1-15 km/s. ``threshold_cm``
# is the diameter above which a sphere perforates; it equals the critical diameter wherever the
# 2011 form has one (its fixed point).
speeds = np.linspace(1.0, 15.0, 141)
curves = {name: ballistic_limit_curve(shield, speeds, 0.0, 2.703, equation=name)
          for name in ("jsc1993", "jsc2011")}
print("regime boundaries of the 2011 form (km/s):",
      curves["jsc2011"].regime_boundaries_km_s)

fig, ax = plt.subplots(figsize=(7, 4.5))
for name, style in (("jsc2011", "-"), ("jsc1993", "--")):
    curve = curves[name]
    ax.plot(curve.velocity_km_s, curve.threshold_cm, style, color="k", label=curve.equation)
ax.scatter(shots.velocity_km_s[shots.perforated], shots.diameter_cm[shots.perforated],
           marker="x", color="tab:red", label="test shot: perforated")
ax.scatter(shots.velocity_km_s[~shots.perforated], shots.diameter_cm[~shots.perforated],
           marker="o", facecolors="none", edgecolors="tab:blue", label="test shot: held")
ax.set(xlabel="impact speed V (km/s)", ylabel="projectile diameter d (cm)", ylim=(0, 1.2),
       title="Table 2 shield, normal incidence: the limit and the nearby tests")
ax.legend(loc="upper right", fontsize="small")
fig.tight_layout()
