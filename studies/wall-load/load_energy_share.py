"""How much of the arriving debris's kinetic energy the wall stage's load puts into the wall (issue 11).

The wall is loaded with the deposited momentum: an impulse I on wall material of mass M at rest
brings |I|²/2M, and the rest of the debris's kinetic energy is what a perfectly inelastic
collision of the debris with that material dissipates — heat and cratering, which the load does
not carry.  For each finished Whipple run this prints the arriving particles' kinetic energy
(the share deposited on the wall grid; all of it and its wall-normal part ½ p_y²/m) beside the
work the load did in the wall stage (``wall/wall.json``), and the particles' median mass.

    python studies/wall-load/load_energy_share.py RUN_FOLDER [RUN_FOLDER ...]
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

from impactdyn.debris import read_arrivals


def energy_share(run: Path) -> dict:
    """The arriving debris's kinetic energy (g·cm²/µs²) and the load's work for one run folder."""
    mass, momentum, share = read_arrivals(run / "debris" / "debris.h5")
    load = json.loads((run / "wall" / "wall.json").read_text())["measures"]["energy"]["load_work"]
    normal = 0.5 * float(np.sum(share * momentum[:, 1] ** 2 / mass))
    return {"particles": int(mass.size), "mass_g": float(mass.sum()),
            "kinetic": 0.5 * float(np.sum(share * np.sum(momentum**2, axis=1) / mass)),
            "kinetic_normal": normal, "load_work": load, "load_share_of_normal": load / normal,
            "median_particle_mass_g": float(np.median(mass))}


def main() -> int:
    if len(sys.argv) < 2:
        print(__doc__)
        return 2
    print("| run | arrived particles | mass (g) | kinetic energy | its normal part | load work | load / normal |"
          " median particle (g) |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    for run in map(Path, sys.argv[1:]):
        e = energy_share(run)
        print(f"| {run.name} | {e['particles']} | {e['mass_g']:.4f} | {e['kinetic']:.3e} | {e['kinetic_normal']:.3e} "
              f"| {e['load_work']:.3e} | {e['load_share_of_normal']:.2%} | {e['median_particle_mass_g']:.1e} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
