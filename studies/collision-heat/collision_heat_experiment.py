"""An experiment, not a model of the product: does the collision heat the wall load leaves out make a
small-projectile wall fail at the default mesh? (issue 11; BENCHMARKS.md, "the 2024 walls had no ductile
damage").

The wall stage's load carries the deposited momentum and, with it, only |I|²/2M of the debris's kinetic
energy (``load_energy_share.py``).  Here a share ``F_WALL`` of each deposition record's own kinetic energy,
|I|²/2m (m the mass that arrives with the record: a fifth of its particle's), is added as internal
energy to the first-layer element under the record when the record arrives (binned to 0.1 µs).  Heat
softens the Johnson–Cook wall (T*) and raises its Grüneisen pressure.  F_WALL = 0.5 is the share of an
equal-material collision's dissipation each side takes; 1.0 is an upper bound (all of it).  The heat
is not in the solver's energy balance, and refinement 1 only (the case's mesh).  Nothing was tuned.

    OMP_WAIT_POLICY=passive python studies/collision-heat/collision_heat_experiment.py F_WALL RUN_FOLDER [RUN_FOLDER ...]
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

from impactdyn import wall
from impactdyn.debris import POINTS_PER_PARTICLE, read_arrivals, read_deposition
from impactdyn.wall._state import ERODED, IE  # state columns (no public accessor)
from impactdyn.whipple import load_whipple_case

#: Heat of the records arrived within this many µs is added at once.
BIN_US = 0.1


class HeatedSolver(wall.WallSolver):
    """The wall solver with heat q (g·cm²/µs²) added to element e at time t, for each (t, e, q)."""

    def add_heat(self, t: np.ndarray, e: np.ndarray, q: np.ndarray) -> None:
        order = np.argsort(t, kind="stable")
        self.heat_time, self.heat_element, self.heat = t[order], e[order], q[order]
        self.heat_next = 0
        self.heat_in = 0.0

    def _heat_arrived(self) -> None:
        j = int(np.searchsorted(self.heat_time, self.time, side="right"))
        e, q = self.heat_element[self.heat_next:j], self.heat[self.heat_next:j]
        live = self.flags[e, ERODED] == 0
        np.add.at(self.es[:, IE], e[live], q[live] / self.mesh.element_mass[e[live]])
        self.heat_in += float(q[live].sum())
        self.heat_next = j

    def advance(self, t_stop: float, max_steps: int = 2**62, settling: bool = False) -> int:
        steps = 0
        while self.time < t_stop:
            self._heat_arrived()
            due = self.heat_time[self.heat_next] + BIN_US if self.heat_next < self.heat_time.size else math.inf
            steps += super().advance(min(t_stop, max(due, self.time + 1e-9)), max_steps, settling)
        self._heat_arrived()
        return steps


def heated_run(run: Path, share: float) -> tuple[wall.WallResult, float]:
    """The run's wall stage (case mesh, no output) with ``share`` of each record's kinetic energy as heat."""
    case = load_whipple_case(run / "case.toml")
    h5 = run / "debris" / "debris.h5"
    grid, deposition, _ = read_deposition(h5)
    mass, momentum, on_grid = read_arrivals(h5)
    # the records are the arrived particles' on-grid points, in particle then point order (debris.deposit)
    points = np.rint(on_grid * POINTS_PER_PARTICLE).astype(np.int64)
    record_mass = np.repeat(mass / POINTS_PER_PARTICLE, points)
    record_momentum = np.repeat(momentum / POINTS_PER_PARTICLE, points, axis=0)
    np.testing.assert_allclose(record_momentum, deposition.impulse, rtol=1e-12, atol=1e-18)
    heat = share * 0.5 * np.sum(deposition.impulse**2, axis=1) / record_mass
    options = case.wall_options.replaced(output_interval_us=None)
    if (options.refinement_thickness, options.refinement_plane) != (1, 1):
        raise SystemExit(f"{run}: the experiment heats the case mesh's first layer; refinement must be 1")
    model = wall.wall_model(options.material_model, case.wall.material)
    mesh = wall.build_mesh(grid, model.density, 1, 1, options.supports)
    load = wall.nodal_load(mesh, deposition, options.spread, options.deposition_depth_cm)
    solver = HeatedSolver(mesh, model, options, load=load, t_start=float(load.time.min()))
    # face element i + nx k lies on the first-layer element of the same number (WallMesh.element_ijk)
    solver.add_heat(deposition.time, deposition.element, heat)
    return solver.run(), solver.heat_in


def main() -> int:
    if len(sys.argv) < 3:
        print(__doc__)
        return 2
    share = float(sys.argv[1])
    for run in map(Path, sys.argv[2:]):
        result, heat_in = heated_run(run, share)
        m = result.measures
        causes = {k: round(v, 4) for k, v in m["failed_mass_by_cause_g"].items() if v}
        print(f"{run.name:14s} share {share}: {result.verdict:15s} heat {heat_in:.3e} (load work "
              f"{m['energy']['load_work']:.3e}) bulge {m['rear_bulge_cm']:.4f} crater {m['crater_depth_ratio']:.3f} "
              f"eroded {m['eroded_mass_g']:.4f} g by {causes}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
