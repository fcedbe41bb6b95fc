"""The momentum a droplet of the debris cloud gives a thick aluminium wall: β = p_wall / p_in, from the SPH.

An Al 6061-T6 sphere strikes a thick Al 6061-T6 plate normally (:func:`impactdyn.shield.sphere_on_plate`, the
half model; the SPH shield stage's default options).  Crater ejecta leave the plate's face moving back
toward the bumper; by momentum conservation the plate keeps the sphere's momentum plus theirs::

    β = 1 + |Σ m v_n over the ejecta| / p_in,   ejecta: in front of the plate's face and moving back (v_n < 0)

Counting every backward-moving particle instead would take in the plate's own ringing (on a 4 d plate it
swings between 3.4 and 3.8 at 10 km/s while the ejecta's sum rises steadily).  The ejecta leave the crater
over many d/V, slowest last, so β is read at the end time 40 d/V (at most 12 µs) and printed also at 70 %
of it: the difference is what the reading may still miss.  The EOS, the strength and the failure
thresholds carry no length, so β depends on the normal speed alone: one sphere stands for droplets of
any size.  The plate is 4 d thick and 5 d in radius (Cour-Palais's crater in a thick Al plate is 2.3 d
deep at 10 km/s; the plate is not semi-infinite for the crater's own depth, whose comparison with
Cour-Palais needs a thicker one: at 7 km/s it sits at the single wall's detached-spall thickness, 2.2 p∞,
and its rear moves as the crater forms).

    python3 verification/momentum_transfer.py                    # the table at d/6 (about 30 minutes on 2 cores)
    python3 verification/momentum_transfer.py --per-d 8 --speeds 7 10   # the resolution check
    python3 verification/momentum_transfer.py --speeds 7 10 --column 4 --gap 1   # a dense cloud's column

A dense cloud: later droplets strike the crater, melt and ejecta of earlier ones.  ``--column N --gap G``
puts N spheres on the axis, G diameters apart surface to surface, each at the same speed, and reads the
wall's share of the whole column's momentum from everything in front of the face::

    β_column = 1 − Σ m v_n over the particles in front of the face / (N p_in)

(one sphere: the formula above, nothing in front moving forward at the end).  End time: 40 d/V after the
last sphere's arrival.  On the axis every droplet strikes the same spot, the most overlap a cloud can
have; a cloud spread over the wall lies between that and one droplet on a bare wall.

The table printed last is :data:`impactdyn.debris.CRATERING_MOMENTUM`'s.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import time

import numpy as np

from impactdyn import shield

MATERIAL = "al6061-t6"
DIAMETER_CM = 0.1                 # any size: β carries no length
THICKNESS_D, RADIUS_D = 4.0, 5.0
END_D_OVER_V, END_MAX_US = 40.0, 12.0
SPEEDS_KM_S = (2.0, 3.0, 5.0, 7.0, 10.0, 13.0)


def column(problem: shield.Problem, spheres: int, gap_d: float) -> shield.Problem:
    """``problem`` with its sphere repeated ``spheres`` times along −y, ``gap_d`` diameters apart surface to
    surface (the copies behind the first, each with the first's state)."""
    state, d = problem.particles, DIAMETER_CM
    sphere = state.velocity[:, 1] > 0
    shifts = [np.array([0.0, -k * (1.0 + gap_d) * d, 0.0]) for k in range(1, spheres)]
    arrays = {}
    for field in dataclasses.fields(state):
        value = getattr(state, field.name)
        if not isinstance(value, np.ndarray):
            continue
        copies = [value[sphere] + shift for shift in shifts] if field.name == "position" else \
            [value[sphere]] * len(shifts)
        arrays[field.name] = np.concatenate([value, *copies])
    return dataclasses.replace(problem, particles=dataclasses.replace(state, **arrays))


def momentum_transfer(speed_km_s: float, per_d: float, spheres: int = 1, gap_d: float = 0.0) -> dict:
    """β of ``spheres`` normal impacts on one spot at ``speed_km_s`` (:func:`column`), spacing d/``per_d``."""
    d = DIAMETER_CM
    problem = shield.sphere_on_plate(MATERIAL, MATERIAL, d, speed_km_s, 0.0, THICKNESS_D * d, d / per_d,
                                     plate_radius_cm=RADIUS_D * d)
    if spheres > 1:
        problem = column(problem, spheres, gap_d)
    init = problem.particles
    incoming = init.velocity[:, 1] > 0
    p_in = float(init.mass[incoming] @ init.velocity[incoming, 1])
    t_end = min((END_D_OVER_V + (spheres - 1) * (1.0 + gap_d)) * d / (0.1 * speed_km_s), END_MAX_US)
    start = time.perf_counter()
    run = shield.run(problem, t_end, snapshot_times_us=[0.7 * t_end])

    def beta(state) -> float:
        front = state.position[:, 1] < 0                                     # the plate's face is y = 0
        if spheres == 1:
            front &= state.velocity[:, 1] < 0                                # the ejecta
        return 1.0 - float(state.mass[front] @ state.velocity[front, 1]) / p_in

    return {"speed_km_s": speed_km_s, "per_d": per_d, "spheres": spheres, "gap_d": gap_d,
            "particles": len(init.mass), "t_end_us": t_end, "beta": round(beta(run.state), 4),
            "beta_at_0.7_t_end": round(beta(run.snapshots[0]), 4), "seconds": round(time.perf_counter() - start, 1)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--per-d", type=float, default=6.0, help="particles across the sphere's diameter")
    parser.add_argument("--speeds", type=float, nargs="+", default=list(SPEEDS_KM_S), help="km/s")
    parser.add_argument("--column", type=int, default=1, help="spheres on the axis, one behind the other")
    parser.add_argument("--gap", type=float, default=1.0, help="their gap, surface to surface, in diameters")
    args = parser.parse_args()
    rows = []
    for speed in args.speeds:
        rows.append(momentum_transfer(speed, args.per_d, args.column, args.gap))
        print(json.dumps(rows[-1]), flush=True)
    print("speed_km_s =", tuple(r["speed_km_s"] for r in rows))
    print("beta       =", tuple(r["beta"] for r in rows))


if __name__ == "__main__":
    main()
