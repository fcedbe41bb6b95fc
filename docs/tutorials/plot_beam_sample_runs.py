"""
The rotating beam's two sample runs
===================================

The two sample runs of the 1988 report: a flexible aluminium beam on a light hub
(inertia ratio 0.002), swung by a torque pulse from θ = 3.3 rad against a stop 0.515 m out
along it. ``impactc_sample.toml`` resolves the strike by momentum balance with the listing's
speed-dependent restitution (IMPACTC); ``impactb_sample.toml`` by a Hertzian spring–dashpot
contact force (IMPACTB). The model's equations: :doc:`the theory of the rotating beam
</theory/beam>`; the comparison with the numbers the report printed: :doc:`the rotating-beam
page, its sample runs against the 1988 report </beam>`. From the command line:
``impactdyn beam run examples/beam/impactb_sample.toml -o runs/impactb``.
"""

# %%
# Both cases, run as they are shipped (the first call compiles the integrator, cached after):
from pathlib import Path

import matplotlib.pyplot as plt

from impactdyn.beam import load_case, simulate

# the tutorials run from docs/tutorials
EXAMPLES = Path("../../examples/beam")
results = {name: simulate(load_case(EXAMPLES / f"{name}_sample.toml"))
           for name in ("impactc", "impactb")}

# %%
# The first contact of each: the approach and separation speeds of the stop point and their
# ratio, the coefficient of restitution. The momentum law's contact is an instant; the Hertzian
# one lasts some 39 µs and has a peak force.
for name, result in results.items():
    first = result.impacts[0]
    duration_us = 1e6 * (first.t_end - first.t_start)
    force = ("an impulse" if first.peak_force is None else
             f"{duration_us:.1f} µs long, peak force {first.peak_force:.0f} N")
    print(f"{name}: {len(result.impacts)} contacts; the first at {first.t_start:.7f} s,\n"
          f"  {first.v_approach:.6f} -> {first.v_separation:.6f} m/s, "
          f"e = {first.restitution:.6f}, {force}")

# %%
# The hub angle and speed through the strike: IMPACTC (the momentum law) as a wide, light solid
# line, IMPACTB (the Hertzian contact) as a dark dashed line over it, so that where the two runs
# agree the dashes lie on the wide line. With the momentum law the beam chatters against the
# stop (the micro-impacts counted above) until the approach speed falls below
# ``contact.rest_velocity_m_s`` and it rests there.
STYLES = {"impactc": dict(label="IMPACTC (momentum law)", color="tab:orange", linewidth=4, alpha=0.6),
          "impactb": dict(label="IMPACTB (Hertzian contact)", color="tab:blue", linewidth=1.5, linestyle="--")}
fig, (angle, speed) = plt.subplots(2, 1, sharex=True, figsize=(7, 5))
for name, result in results.items():
    angle.plot(result.t, result.theta, **STYLES[name])
    speed.plot(result.t, result.theta_dot, **STYLES[name])
angle.set(ylabel="hub angle θ (rad)")
speed.set(xlabel="time (s)", ylabel="hub speed θ̇ (rad/s)")
angle.legend()
fig.tight_layout()
