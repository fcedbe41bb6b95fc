"""Does Grady's size field converge with the spacing?  The own-size rate on two kept SPH states.

For the gate's set-up (studies/fragments/fragments_mechanism.py, its ``--keep-states`` folder), the failed
solid particles of each body (projectile, bumper) at two spacings: the percentiles of Grady's size s
read across each fragment's own size (:func:`impactdyn.shield.own_size_strain_rates`), the share of the
failed particles with s ≥ 0.04 cm, and s at the finer spacing over s at the coarser one at the nearest
reference position.  A diagnosis, deciding nothing (validation/set-4-decision.md).

    python studies/fragments/partition_diagnosis.py STATES --speed 4 --ratio 0.1 --spacings 0.015875 0.0079375
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

from impactdyn import shield
from impactdyn.materials import get_material

MATERIAL = "al6061-t6"


def size_field(folder: Path, speed: float, ratio: float, spacing: float, time_us: float) -> dict:
    """{body: (reference positions, sizes, spacings)} of the failed solid particles of a kept state, sized
    as the package sizes them (:func:`impactdyn.shield.grady_sizes`)."""
    stem = folder / f"fragmentation_{speed:g}_{ratio:g}_{spacing:g}_t{time_us:g}"
    initial, _ = shield.read_particles(f"{stem}_init.h5")
    state, _ = shield.read_particles(f"{stem}_end.h5")
    failed, sizes = shield.grady_sizes(state, initial=initial)
    delta = np.cbrt(state.mass / get_material(MATERIAL).rho0)
    projectile = initial.velocity[:, 1] > 0
    field = {}
    for name, body in (("projectile", projectile), ("bumper", ~projectile)):
        idx = np.flatnonzero(failed & body)
        field[name] = (initial.position[idx], sizes[idx], delta[idx])
    return field


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("states", type=Path, help="the --keep-states folder of fragments_mechanism.py")
    parser.add_argument("--speed", type=float, required=True)
    parser.add_argument("--ratio", type=float, required=True)
    parser.add_argument("--spacings", type=float, nargs=2, required=True, metavar=("COARSE", "FINE"))
    parser.add_argument("--time", type=float, default=3.0)
    args = parser.parse_args()
    coarse, fine = (size_field(args.states, args.speed, args.ratio, d, args.time) for d in args.spacings)
    print("| body | Δ cm | s percentiles 10/25/50/75/90 % (cm) | s ≥ 0.04 cm | s(fine)/s(coarse): median (IQR) |")
    print("| --- | --- | --- | --- | --- |")
    for body in ("projectile", "bumper"):
        (xc, sc, dc), (xf, sf, _) = coarse[body], fine[body]
        distance, nearest = cKDTree(xf).query(xc)
        both = np.isfinite(sc) & np.isfinite(sf[nearest]) & (distance < dc)
        ratio = sf[nearest][both] / sc[both]
        q = np.percentile(ratio, [25, 50, 75])
        for spacing, sizes in zip(args.spacings, (sc, sf)):
            finite = sizes[np.isfinite(sizes)]
            print(f"| {body} | {spacing:g} | {' / '.join(f'{p:.3f}' for p in np.percentile(finite, [10, 25, 50, 75, 90]))} "
                  f"| {np.mean(sizes >= 0.04):.2f} | {q[1]:.2f} ({q[0]:.2f}–{q[2]:.2f}) |")


if __name__ == "__main__":
    main()
