"""A wall run's numbers, bit for bit, do not depend on how its kernels came to the process (compiled there, or
loaded from numba's cache) nor on the thread count: a draw run in a worker process is the run a case with its
seed makes (:func:`impactdyn.whipple._pipeline.draw_schedule`), and a run on a laptop the run on a cluster.

With fused multiply-adds allowed (``fastmath={"contract"}``) the block kernels compiled in a process and the
same kernels loaded from the cache fused differently: the plastic work of an element moved by 0.7 %, the nodes
by 1e-14 cm after 3 µs of the report's wall."""

import os
import subprocess
import sys

import numpy as np

from impactdyn.wall._state import W_PLASTIC

RUN = """
import sys
import numba
import numpy as np

from impactdyn.wall._state import W_PLASTIC
from impactdyn import wall
from impactdyn.wallgrid import WallDeposition, WallGrid

numba.set_num_threads(int(sys.argv[1]))
grid = WallGrid.uniform((0.0, 1.2), (0.0, 0.16), (-0.6, 0.6), (13, 3, 13))
centre = np.flatnonzero(np.ones((12, 12), bool).ravel())
xc, zc = np.meshgrid(0.5 * (grid.x[1:] + grid.x[:-1]), 0.5 * (grid.z[1:] + grid.z[:-1]))
weight = np.exp(-((xc.ravel() / 0.2) ** 2 + (zc.ravel() / 0.2) ** 2))
impulse = np.zeros((centre.size, 3))
impulse[:, 1] = 0.002 * weight / weight.sum()
deposition = WallDeposition(element=centre.astype(np.int64), time=np.linspace(1.0, 1.5, centre.size),
                            impulse=impulse)
options = wall.WallOptions()
model = wall.wall_model(options.material_model, "al6061-t6")
mesh = wall.build_mesh(grid, model.density, 1, 1)
solver = wall.WallSolver(mesh, model, options, load=wall.nodal_load(mesh, deposition, options.spread), t_start=1.0)
solver.advance(4.0)
np.savez(sys.argv[2], x=solver.nodes.x, v=solver.nodes.v, es=solver.elements.es, S=solver.elements.S,
         energy=np.array(list(solver.energies().values()), dtype=float))
"""


def test_a_wall_run_is_the_same_compiled_here_loaded_from_the_cache_and_on_one_thread(tmp_path):
    env = {"NUMBA_CACHE_DIR": str(tmp_path / "cache")}      # empty: the first run compiles every kernel
    runs = {}
    for name, threads in (("compiled", 2), ("cached", 2), ("one_thread", 1)):
        out = tmp_path / f"{name}.npz"
        subprocess.run([sys.executable, "-c", RUN, str(threads), str(out)], check=True,
                       env={**os.environ, **env})
        runs[name] = np.load(out)
    assert np.count_nonzero(runs["compiled"]["es"][:, W_PLASTIC]) > 100     # the load yields the wall
    for name in ("cached", "one_thread"):
        for key in runs["compiled"].files:
            assert np.array_equal(runs[name][key], runs["compiled"][key]), (name, key)
