"""The Dask path equals the local path bit for bit (issue 3: LocalCluster, 2 workers)."""

import numpy as np
import pytest

from impactdyn.debris import ComputeOptions, HydroGrid, ParticleMaterial, WallGrid, run_debris

distributed = pytest.importorskip("dask.distributed")


def test_dask_equals_local_bit_for_bit():
    shape = (4, 2, 4)
    nodes = [np.linspace(0, 0.4, 5), np.linspace(-0.5, -0.3, 3), np.linspace(0, 0.4, 5)]
    ones = np.ones(shape)
    rng = np.random.default_rng(7)
    v = np.array([0.0, 0.5, 0.05]) + 0.03 * rng.normal(size=shape + (3,))  # vibrating particles
    grid = HydroGrid(*nodes, density=2.7 * ones, void_fraction=0.3 * ones, mass=0.7 * 2.7e-3 * ones,
                     pressure=0 * ones, temperature=300 * ones, specific_energy=0 * ones,
                     sound_speed=0.5 * ones, velocity=v)
    wall = WallGrid.uniform((-0.5, 1.0), (0.0, 0.3), (-0.5, 1.0), (7, 2, 7))
    material = ParticleMaterial(mu=0.276, lam=0.56, rho_ref=2.703, eta=1.0)
    local = run_debris(grid, wall, material)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        remote = run_debris(grid, wall, material,
                            compute=ComputeOptions(scheduler="dask", address=cluster.scheduler_address,
                                                   chunk_size=33))
    assert len(local.propagated) == len(remote.propagated) == 160
    assert np.array_equal(local.states, remote.states)
    assert np.array_equal(local.stats.steps, remote.stats.steps)
    assert np.array_equal(local.deposition.impulse, remote.deposition.impulse)
    assert np.array_equal(local.impulse, remote.impulse)
