"""Thermodynamics of the SPH shield stage in a planar Al 6061-T6 on Al 6061-T6 impact, against the EOS.

A flyer plate strikes a target plate of the same alloy (:func:`impactdyn.shield.planar_impact`, a thin
column periodic across its width, so the flow is uniaxial strain) at 2, 6 and 10 km/s, failure off (so
the release is clean), flow stress by default (elastic–perfectly plastic, Y₀), once with the artificial
viscosity everywhere (``viscosity_switch="none"``) and once with Balsara's factor (``"balsara"``).  What
the SPH gives is compared with the exact states of the library's own EOS (Mie–Grüneisen about
Us = c₀ + s·up, :mod:`impactdyn.constitutive`):

* **shocked plateau** (target layers behind the shock, ahead of the flyer's rarefaction, several spacings
  from the interface): pressure and particle velocity against the Rankine–Hugoniot state of the symmetric
  impact, up = V/2 (:meth:`impactdyn.materials.Material.hugoniot`); specific energy against
  e_H = ½ up², exact for a symmetric impact into material at rest;
* **released flyer** (layers the rarefaction from the flyer's free rear face has already brought to
  p ≈ 0, from 3 spacings off the free face to the flyer's middle, i.e. at least half the flyer away from
  the impact interface and its start-up heating): specific energy against e_r, the energy at p = 0 on the
  isentrope through the Hugoniot state — :func:`impactdyn.constitutive.released_energy`, itself checked
  against scipy's ``solve_ivp`` of de/dv = −p(1/v, e) stopped at p = 0;
* **plateau released analytically** (:func:`impactdyn.shield.released_phase` of the plateau particles):
  released energy, temperature and melted share against those of the exact Hugoniot state;
* **1-D melt speeds** (EOS and latent heats only, no SPH): the symmetric impact speed at which the
  released state begins to melt, is completely melted, and begins to boil, by bisection on
  :func:`impactdyn.constitutive.release_states`, beside the MMOD handbook's statements
  (NASA/TM-2009-214785 §4.2.1: melting begins above about 5.5 km/s, complete above 7 to 8 km/s, some
  material above the vaporisation temperature above 10 km/s).

The EOS alone is the hydrodynamic reference; the SPH also carries strength.  The column "with Y₀" is the
exact elastic–perfectly-plastic state in uniaxial strain (:func:`elastic_plastic`): the shock with
σ_yy = −p − ⅔Y₀, and the release with the deviator reversing elastically and then flowing at +⅔Y₀ until
σ_yy = 0 (the free face), whose plastic work ⅔Y₀(1/ρ_r − 1/ρ_H) stays in the material.  At 2 km/s that
work is a fifth of e_r.

Windows (Lagrangian, in initial position X; flyer X ∈ [−L_f, 0], target [0, L_t]): the flyer's shock
reaches its rear at t₁ = L_f/Us; the release's tail (p = 0) then runs forward at ρ_r c₀/ρ₀, its head — an
elastic unloading wave, the deviator reversing — at the longitudinal speed ρ_H (c_H² + 4G/3ρ_H)^½/ρ₀, 5 %
above the bulk ρ_H c_H/ρ₀ at 6 km/s, and dropping p by about 5 % there (ΔS_yy = 4Y₀/3 needs a strain Y₀/G).
The plateau is read when that head reaches the impact interface; the release when the tail (plus a margin)
has passed the flyer's middle; the target is long enough that its shock has not reached its rear face when
the plateau is read, nor the wave that face reflects the release window when that is read.  Units cm, g,
µs, Mbar; 1 km/s = 0.1 cm/µs.

    python3 verification/planar_thermodynamics.py                      # 0.01 cm, 2 6 10 km/s
    python3 verification/planar_thermodynamics.py --spacing 0.005 --flyer-layers 80   # the same flyer, finer
    python3 verification/planar_thermodynamics.py --spacing 0.02 --width 3 --flyer-layers 20 --speeds 6 10
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import time

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from impactdyn import shield
from impactdyn.constitutive import pack_materials, pack_phases, pressure, release_states, sound_speed
from impactdyn.materials import AL_6061_T6 as AL
from impactdyn.units import km_s_to_cm_us

SWITCHES = ("none", "balsara")
#: Particle layers through the flyer: the release window (3 spacings off the free face to the middle)
#: then lies at least 20 spacings from the impact interface.
FLYER_LAYERS = 40
#: Margins in spacings: the plateau window starts this far into the target (the interface's start-up
#: "wall heating"; it is read when the release's head reaches the interface, so this is also the head's room),
#: ends this far behind the shock front (the shock is smeared over 3–4 particles), the release window ends
#: this far behind the rarefaction's tail, and starts this far from the free face.
INTERFACE_MARGIN, SHOCK_MARGIN, WAVE_MARGIN, FREE_FACE_MARGIN = 6, 4, 4, 3
#: Particles across the column (period 4 Δ; the kernel support 2h ≈ 2.8 Δ of the hot released state).
WIDTH = 4


def _p(rho, e):
    return pressure(rho, e, AL.rho0, AL.c0, AL.s, AL.gamma0)


def released_energy_ivp(rho: float, e: float) -> float:
    """e at p = 0 on the isentrope through (ρ, e): solve_ivp of de/dv = −p(1/v, e) from v = 1/ρ."""
    def zero_pressure(v, y):
        return _p(1.0 / v, y[0])
    zero_pressure.terminal, zero_pressure.direction = True, -1
    sol = solve_ivp(lambda v, y: [-_p(1.0 / v, y[0])], (1.0 / rho, 2.0 / AL.rho0), [e], method="DOP853",
                    events=zero_pressure, rtol=1e-11, atol=1e-15)
    return float(sol.y_events[0][0][0])


def released(rho, e) -> tuple[np.ndarray, ...]:
    """(e_r, T_r, χ_m, χ_v) of Al 6061-T6 states (ρ, e) (:func:`impactdyn.constitutive.release_states`)."""
    rho, e = np.atleast_1d(np.asarray(rho, float)), np.atleast_1d(np.asarray(e, float))
    return release_states(rho, e, np.zeros(rho.size, dtype=np.int64), pack_materials([AL]), pack_phases([AL]))


def elastic_plastic(up: float) -> dict:
    """The exact elastic–perfectly-plastic uniaxial-strain states (Y₀, G of the alloy) at particle velocity up.

    Shock (one plastic shock: Us exceeds the longitudinal elastic speed 6.41 km/s from 2 km/s impacts up):
    ρ₀ Us up = p(ρ, ½up²) + ⅔Y₀, ρ = ρ₀Us/(Us − up).  Release: de = (p − S_yy) dρ/ρ², S_yy rising
    elastically (dS_yy = −(4/3) G dρ/ρ) from −⅔Y₀ to +⅔Y₀ and held there, until σ_yy = S_yy − p = 0.
    """
    e_h, y23 = 0.5 * up * up, 2.0 * AL.yield_stress / 3.0
    us = brentq(lambda u: AL.rho0 * u * up - _p(AL.rho0 * u / (u - up), e_h) - y23, AL.c0, AL.c0 + 3 * AL.s * up)
    rho_h = AL.rho0 * us / (us - up)

    def rate(rho, y):
        dev = min(y[1], y23)
        return [(_p(rho, y[0]) - dev) / rho**2, -4.0 * AL.shear_modulus / (3.0 * rho) if y[1] < y23 else 0.0]

    def free(rho, y):
        return _p(rho, y[0]) - min(y[1], y23)
    free.terminal = True
    sol = solve_ivp(rate, (rho_h, 0.5 * AL.rho0), [e_h, -y23], events=free, rtol=1e-10, atol=1e-15, max_step=1e-3)
    e_free = float(sol.y_events[0][0][0])
    e_r, t_r, melted, _ = released(rho_h, e_h)
    return dict(us=us, p=_p(rho_h, e_h), rho=rho_h, e=e_h, e_free=e_free, e_r=e_r[0], t_r=t_r[0], melted=melted[0])


def exact(speed_km_s: float) -> dict:
    """The hydrodynamic states of the EOS for the symmetric impact at speed_km_s, and their strength-corrected
    counterparts (key ``ep``)."""
    up = km_s_to_cm_us(speed_km_s) / 2.0
    us, p_h, rho_h = AL.hugoniot(up)
    e_h = 0.5 * up * up
    e_r, t_r, melted, vapour = (x[0] for x in released(rho_h, e_h))
    rho_r = AL.rho0 * (1.0 - AL.gamma0 * e_r / AL.c0**2)  # p = 0 on the linear tension branch
    return dict(up=up, us=us, p=p_h, rho=rho_h, e=e_h, e_r=e_r, e_r_ivp=released_energy_ivp(rho_h, e_h), t_r=t_r,
                melted=melted, vapour=vapour, rho_r=rho_r,
                head=rho_h * math.sqrt(sound_speed(rho_h, p_h, AL.rho0, AL.c0, AL.s, AL.gamma0) ** 2
                                       + 4.0 * AL.shear_modulus / (3.0 * rho_h)) / AL.rho0,
                tail=rho_r * AL.c0 / AL.rho0, ep=elastic_plastic(up))


@dataclasses.dataclass(frozen=True)
class Layout:
    """Column lengths, read-out times and windows (initial positions X, cm) of one speed and spacing."""

    flyer: float
    target: float
    t_plateau: float
    t_release: float
    plateau: tuple[float, float]
    release: tuple[float, float]


def layout(ex: dict, spacing: float, flyer_layers: int = FLYER_LAYERS) -> Layout:
    """The windows of the module docstring for the exact states ``ex`` (:func:`exact`)."""
    lf = flyer_layers * spacing
    t1 = lf / ex["us"]  # the flyer's shock at its rear face
    lo = INTERFACE_MARGIN * spacing
    t_plateau = t1 + lf / ex["head"]  # the release's head at the interface, INTERFACE_MARGIN short of the window
    t_release = t1 + (lf / 2 + WAVE_MARGIN * spacing) / ex["tail"]   # tail − margin past the flyer's middle
    # the target: its shock 10 spacings short of its rear face when the plateau is read, and the wave its rear
    # face reflects (at the head's speed, the fastest) still WAVE_MARGIN short of the release window when
    # that is read (shock at the rear at L_t/Us, back at X = −L_f/2 after (L_t + L_f/2)/head more)
    reflect = ((t_release + (WAVE_MARGIN * spacing - lf / 2) / ex["head"]) / (1.0 / ex["us"] + 1.0 / ex["head"]))
    target = math.ceil(max(ex["us"] * t_plateau / spacing + 10, reflect / spacing)) * spacing
    return Layout(flyer=lf, target=target, t_plateau=t_plateau, t_release=t_release,
                  plateau=(lo, ex["us"] * t_plateau - SHOCK_MARGIN * spacing),
                  release=(-lf + FREE_FACE_MARGIN * spacing, -lf / 2))


def measure(speed_km_s: float, spacing: float, switch: str, *, width: int = WIDTH,
            flyer_layers: int = FLYER_LAYERS, material=AL) -> dict:
    """Run one case and read its windows: medians over the particles of each window.

    Returns p, up, e of the plateau; e_r, T_r, χ_m of the plateau released analytically; e and p of the
    released flyer window; the layer counts of the windows; the run time and steps.
    """
    ex = exact(speed_km_s)
    lay = layout(ex, spacing, flyer_layers)
    problem = shield.planar_impact(material, material, velocity_km_s=speed_km_s, flyer_length_cm=lay.flyer,
                                   target_length_cm=lay.target, spacing_cm=spacing, width_particles=width)
    options = shield.SPHOptions(viscosity_switch=switch, failure=False)
    start = time.perf_counter()
    times = sorted({lay.t_plateau, lay.t_release})
    result = shield.run(problem, times[-1], options=options, snapshot_times_us=times)
    seconds = time.perf_counter() - start
    x0 = problem.particles.position[:, 1]
    at = dict(zip(times, result.snapshots))
    plateau_state, release_state = at[lay.t_plateau], at[lay.t_release]
    in_plateau = (x0 > lay.plateau[0]) & (x0 < lay.plateau[1])
    in_release = (x0 > lay.release[0]) & (x0 < lay.release[1])
    phase = shield.released_phase(plateau_state.select(in_plateau))
    med = np.median
    return dict(
        p=med(plateau_state.pressure[in_plateau]), up=med(plateau_state.velocity[in_plateau, 1]),
        e=med(plateau_state.specific_energy[in_plateau]), e_r=med(phase.energy), t_r=med(phase.temperature),
        melted=med(phase.melted), released_e=med(release_state.specific_energy[in_release]),
        released_p=med(release_state.pressure[in_release]),
        plateau_layers=int(in_plateau.sum() // width**2), release_layers=int(in_release.sum() // width**2),
        particles=len(problem.particles), steps=result.steps, seconds=seconds, layout=lay, ex=ex,
        release_profile=_profile(x0, release_state.specific_energy, spacing, -lay.flyer, 0.0),
    )


def _profile(x0, values, spacing, lo, hi):
    """(X, layer mean) of the layers with lo < X < hi."""
    layers = np.round(x0 / spacing - 0.5).astype(int)
    keep = (x0 > lo) & (x0 < hi)
    ids, inverse = np.unique(layers[keep], return_inverse=True)
    return (ids + 0.5) * spacing, np.bincount(inverse, values[keep]) / np.bincount(inverse)


# --- the 1-D melt speeds ---------------------------------------------------------------------------------

def _released_at(speed_km_s: float) -> tuple[float, ...]:
    up = km_s_to_cm_us(speed_km_s) / 2.0
    _, _, rho = AL.hugoniot(up)
    return tuple(float(x[0]) for x in released(rho, 0.5 * up * up))


def bisect_speed(condition, lo: float = 1.0, hi: float = 20.0, tol: float = 1e-3) -> float:
    """The impact speed (km/s) where ``condition(e_r, T_r, χ_m, χ_v)`` of the released state turns true."""
    if condition(*_released_at(lo)) or not condition(*_released_at(hi)):
        raise ValueError(f"the condition does not change between {lo} and {hi} km/s")
    while hi - lo > tol:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if condition(*_released_at(mid)) else (mid, hi)
    return 0.5 * (lo + hi)


def melt_speeds() -> dict:
    """Symmetric Al 6061-T6 impact speeds (km/s): melting begins, is complete, boiling begins (released state)."""
    return dict(incipient=bisect_speed(lambda e, t, m, v: m > 0.0),
                complete=bisect_speed(lambda e, t, m, v: m >= 1.0),
                vapour=bisect_speed(lambda e, t, m, v: v > 0.0))


#: The MMOD handbook (NASA/TM-2009-214785 §4.2.1) on aluminium projectiles, km/s.
HANDBOOK = dict(incipient="about 5.5", complete="7 to 8 (1-D theory)", vapour="above 10")


# --- the table ---------------------------------------------------------------------------------------------

ROWS = (  # key, label, exact key, strength-corrected key, format, absolute error (shares)
    ("p", "plateau p (Mbar)", "p", "p", "{:.4f}", False),
    ("up", "plateau u_p (cm/µs)", "up", "up", "{:.4f}", False),
    ("e", "plateau e vs ½u_p² (cm²/µs²)", "e", "e", "{:.5f}", False),
    ("released_e", "released flyer e vs e_r", "e_r", "e_free", "{:.6f}", False),
    ("e_r", "plateau e_r (released_phase)", "e_r", "e_r", "{:.6f}", False),
    ("t_r", "plateau T_r (K)", "t_r", "t_r", "{:.0f}", False),
    ("melted", "plateau melted share", "melted", "melted", "{:.3f}", True),
)


def _err(value: float, ref: float, absolute: bool) -> str:
    return f"{value - ref:+.3f}" if absolute else f"{(value - ref) / ref:+.1%}"


def table(speed_km_s: float, runs: dict[str, dict]) -> str:
    """The comparison table (Markdown) of one speed; errors relative, the melted share's absolute."""
    ex = next(iter(runs.values()))["ex"]
    ep = dict(ex["ep"], up=ex["up"])
    head = ["quantity", "EOS exact", "with Y0"]
    for sw in runs:
        head += [f"SPH {sw}", "err EOS", "err Y0"]
    rows = []
    for key, label, ek, pk, fmt, absolute in ROWS:
        ref, ref_ep = ex[ek], ep[pk]
        cells = [label, fmt.format(ref), fmt.format(ref_ep)]
        for run in runs.values():
            cells += [fmt.format(run[key]), _err(run[key], ref, absolute), _err(run[key], ref_ep, absolute)]
        rows.append(cells)
    widths = [max(len(r[k]) for r in [head] + rows) for k in range(len(head))]
    fmt_row = lambda cells: "| " + " | ".join(c.ljust(w) if k == 0 else c.rjust(w)
                                              for k, (c, w) in enumerate(zip(cells, widths))) + " |"
    lines = [f"V = {speed_km_s:g} km/s (u_p = {ex['up']:.3f} cm/µs, Us = {ex['us']:.4f} cm/µs)", "",
             fmt_row(head), "| " + " | ".join("-" * w for w in widths) + " |"]
    return "\n".join(lines + [fmt_row(r) for r in rows])


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--spacing", type=float, default=0.01, help="particle spacing, cm (default 0.01)")
    parser.add_argument("--speeds", type=float, nargs="+", default=[2.0, 6.0, 10.0], help="impact speeds, km/s")
    parser.add_argument("--switches", nargs="+", default=list(SWITCHES), choices=SWITCHES)
    parser.add_argument("--width", type=int, default=WIDTH, help="particles across the column (default 4)")
    parser.add_argument("--flyer-layers", type=int, default=FLYER_LAYERS, help="particle layers through the flyer")
    parser.add_argument("--profile", action="store_true", help="print the released flyer's e, layer by layer")
    parser.add_argument("--no-strength", action="store_true",
                        help="diagnostic: Y0 = 0 (hydrodynamic), to separate the strength's share of a difference")
    args = parser.parse_args(argv)
    material = dataclasses.replace(AL, yield_stress=0.0) if args.no_strength else AL

    print(f"Al 6061-T6 on Al 6061-T6, planar; spacing {args.spacing} cm, {args.width}×{args.width} particles "
          f"across, {args.flyer_layers} layers through the flyer; failure off; flow stress "
          f"{'none (Y0 = 0)' if args.no_strength else 'perfectly plastic Y0'}; medians over each window\n")
    for speed in args.speeds:
        runs = {sw: measure(speed, args.spacing, sw, width=args.width, flyer_layers=args.flyer_layers,
                            material=material) for sw in args.switches}
        print(table(speed, runs))
        r = next(iter(runs.values()))
        ex, lay = r["ex"], r["layout"]
        print(f"  e_r of the library {ex['e_r']:.8f} vs solve_ivp {ex['e_r_ivp']:.8f} "
              f"({(ex['e_r'] - ex['e_r_ivp']) / ex['e_r_ivp']:+.1e}); released ρ_r = {ex['rho_r']:.4f} g/cm³")
        print(f"  columns: flyer {lay.flyer:.3f} cm, target {lay.target:.3f} cm; plateau at {lay.t_plateau:.3f} µs, "
              f"X in ({lay.plateau[0]:.3f}, {lay.plateau[1]:.3f}) cm, {r['plateau_layers']} layers; release at "
              f"{lay.t_release:.3f} µs, X in ({lay.release[0]:.3f}, {lay.release[1]:.3f}) cm, "
              f"{r['release_layers']} layers")
        for sw, run in runs.items():
            print(f"  {sw}: {run['particles']} particles, {run['steps']} steps, {run['seconds']:.1f} s; "
                  f"released window p = {run['released_p']:+.4f} Mbar ({run['released_p'] / ex['p']:+.1%} of p_H)")
            if args.profile:
                xs, es = run["release_profile"]
                print("    X (cm) and e / e_r (EOS):  " + "  ".join(
                    f"{x:+.3f}:{e / ex['e_r']:.3f}" for x, e in zip(xs, es)))
        print()
    speeds = melt_speeds()
    print("1-D melt judgement of the EOS and latent heats (symmetric Al 6061-T6 impact, released to p = 0):")
    for key, label in (("incipient", "melting begins"), ("complete", "completely melted"),
                       ("vapour", "boiling begins")):
        print(f"  {label:<18} {speeds[key]:6.2f} km/s   handbook: {HANDBOOK[key]}")


if __name__ == "__main__":
    main()
