"""Time integration of the SPH equations (:mod:`._equations`): the solver's records and step sequence, and :func:`run`.

One step is the kick–drift–kick leapfrog with a predicted state of
:mod:`._equations` (one neighbour-list update and one force pass); the step size is
the smallest stable step of the particles, shortened to land on the snapshot times
and the end time.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np
from numba import get_num_threads

from impactdyn._errors import InputError, SimulationError
from impactdyn.constitutive import N_FLAW, pack_damage, pack_materials
from impactdyn.shield._damage import new_flaws
from impactdyn.shield._equations import (FRAGMENTATION, NO_FAILURE, PS_WIDTH, THRESHOLD, Coefficients, Derived,
                                         Materials, PairRows, ParticleState, Predicted, Rates, finish_step,
                                         kick_drift_predict, pair_rows, pair_sums, particle_rates, temperatures,
                                         totals, update_particles)
from impactdyn.shield._kernel import w_shape
from impactdyn.shield._neighbours import NeighbourList, spatial_order
from impactdyn.shield._options import SPHOptions
from impactdyn.shield._state import History, Particles, RunResult


class SPHError(SimulationError):
    """The SPH run broke down (non-finite state or a collapsing time step)."""


def coefficients_of(options: SPHOptions) -> Coefficients:
    """The kernels' :class:`~._equations.Coefficients` of ``options``, each field of one type whatever the
    options hold (an int α would compile the kernels again)."""
    return Coefficients(h_factor=float(options.h_factor), rho_floor=float(options.h_max_factor ** -3.0),
                        artificial_stress=float(options.artificial_stress),
                        artificial_stress_power=int(options.artificial_stress_power),
                        artificial_stress_norm=1.0 / float(w_shape(1.0 / options.h_factor)),
                        alpha=float(options.alpha), beta=float(options.beta),
                        balsara=options.viscosity_switch == "balsara", cfl=float(options.cfl),
                        force_cfl=float(options.force_cfl))


class _Solver:
    """The records of one run (:mod:`._equations`), made once, and the step sequence.

    Particles are kept in spatial (cell-key) order for cache locality: every
    ``REORDER_EVERY`` steps the state, its rates and the neighbour list are
    permuted; ``ids`` maps the stored order back to the problem's particle order.
    The neighbour list is reused across steps within its skin (:mod:`._neighbours`).
    """

    REORDER_EVERY = 10

    def __init__(self, problem, options: SPHOptions):
        init = problem.particles
        n = len(init)
        self.options, self.domain, self.names = options, problem.domain, init.materials
        failure = (NO_FAILURE if not options.failure else
                   FRAGMENTATION if options.failure_model == "fragmentation" else THRESHOLD)
        self.materials = Materials(params=pack_materials(problem.materials),
                                   damage_table=pack_damage(problem.materials),
                                   johnson_cook=options.flow_stress == "johnson_cook", failure=failure)
        self.coefficients = coefficients_of(options)
        mat = init.material.copy()
        self.state = ParticleState(
            x=init.position.copy(), v=init.velocity.copy(), m=init.mass.copy(), rho=init.density.copy(),
            e=init.specific_energy.copy(), S=init.deviatoric_stress.copy(), eps_p=init.plastic_strain.copy(),
            damage=init.damage.copy(), ductile=np.zeros(n),
            flaws=(new_flaws(mat, self.names, self.materials.damage_table) if failure == FRAGMENTATION
                   else np.zeros((n, N_FLAW))),
            failure_rate=init.failure_strain_rate.copy(),
            switch=np.ones(n),  # the viscosity switch fᵢ: 1 until a velocity gradient is known
            mat=mat)
        self.ids = np.arange(n)
        self.rates, self.new_rates = Rates.zeros(n), Rates.zeros(n)
        self.predicted, self.derived, self.rows = Predicted.zeros(n), Derived.zeros(n), PairRows.zeros(n)
        self.sums = np.zeros((0, n, PS_WIDTH))  # per-thread pair sums, sized at the first force pass
        self.neighbours = NeighbourList(n, problem.domain, skin=options.neighbour_skin, half=True)
        self.steps = 0
        self._eos()
        s = self.state
        pair_rows(s, s.v, s.rho, s.S, self.derived, self.rows)
        self._pair_sums()
        particle_rates(s, self.rows, self.materials, self.coefficients, self.sums, self.rates)
        self.dt = float(self.rates.dt.min())

    def _eos(self) -> None:
        update_particles(self.state, self.derived, self.materials, self.coefficients)

    def _pair_sums(self) -> None:
        """Neighbour list at the current positions and the pair sums of the pair-loop rows."""
        nl, h = self.neighbours, self.derived.h
        if 2.0 * h.max() > self.domain.min_period():
            raise SPHError(f"kernel support 2h = {2 * h.max():.4g} cm exceeds the periodic length "
                           f"{self.domain.min_period():.4g} cm")
        nl.update(self.state.x, h)
        if self.sums.shape[0] != get_num_threads():
            self.sums = np.zeros((get_num_threads(), h.size, PS_WIDTH))
        pair_sums(self.rows, self.derived, nl.neighbours, nl.image, nl.count, nl.signs, nl.offsets,
                  self.coefficients, self.sums)

    def totals(self) -> tuple[float, ...]:
        return totals(self.state)

    def step(self, dt: float) -> tuple[float, ...]:
        """Advance by dt (:mod:`._equations`); returns the totals of the new state."""
        if self.steps % self.REORDER_EVERY == 0:
            order = spatial_order(self.state.x, self.derived.h)
            self.state = ParticleState._make(a[order] for a in self.state)
            self.rates = Rates._make(a[order] for a in self.rates)
            self.ids = self.ids[order]
            self.neighbours.permute(order)
        state, predicted = self.state, self.predicted
        kick_drift_predict(state, self.rates, predicted, self.derived, self.rows, self.materials, self.coefficients,
                           dt)
        if self.domain.wrap(state.x):
            self.neighbours.invalidate()
            pair_rows(state, predicted.v, predicted.rho, predicted.S, self.derived, self.rows)
        self._pair_sums()
        finish_step(state, self.rates, self.new_rates, predicted, self.rows, self.sums, self.materials,
                    self.coefficients, dt)
        self.rates, self.new_rates = self.new_rates, self.rates
        self.dt = float(self.rates.dt.min())
        self.steps += 1
        return self.totals()

    def particles(self, time: float) -> Particles:
        """The current state as :class:`Particles`, in the problem's particle order."""
        self._eos()
        s, d = self.state, self.derived
        back = np.argsort(self.ids)
        T = temperatures(s.rho, s.e, s.mat, self.materials.params)
        return Particles(position=s.x[back], velocity=s.v[back], mass=s.m[back], density=s.rho[back],
                         pressure=d.p[back], specific_energy=s.e[back], deviatoric_stress=s.S[back],
                         plastic_strain=s.eps_p[back], failed=s.damage[back] >= 1.0, damage=s.damage[back],
                         failure_strain_rate=s.failure_rate[back], smoothing_length=d.h[back],
                         sound_speed=d.c[back], temperature=T[back], material=s.mat[back],
                         materials=self.names, time=time)


def run(problem, t_end_us: float, *, options: SPHOptions = SPHOptions(),
        snapshot_times_us: Sequence[float] = (), progress: Callable[[float, float], None] | None = None
        ) -> RunResult:
    """Integrate ``problem`` (:class:`impactdyn.shield.Problem`) from its initial state to ``t_end_us``.

    snapshot_times_us : times in (0, t_end] at which to keep the particle state (steps land on them).
    progress : called after every step as ``progress(t_us, t_end_us)`` (a CLI draws its progress bar).

    Returns a :class:`RunResult`: the final :class:`Particles`, the :class:`History`
    of mass, momentum, kinetic and internal energy after every step, and the snapshots.
    Raises :class:`SPHError` if the state stops being finite or the step collapses.
    """
    t_end = float(t_end_us)
    if not (math.isfinite(t_end) and t_end > 0):
        raise InputError(f"t_end_us: must be a positive number, got {t_end_us!r}")
    marks = sorted({float(t) for t in snapshot_times_us})
    if any(not (0 < t <= t_end) for t in marks):
        raise InputError(f"snapshot_times_us: every time must lie in (0, {t_end}], got {list(snapshot_times_us)}")
    targets = marks + ([t_end] if not marks or marks[-1] < t_end else [])

    solver = _Solver(problem, options)
    rows = [(0.0,) + solver.totals()]
    t, snapshots = 0.0, []
    for target in targets:
        while t < target:
            dt = solver.dt
            if not (math.isfinite(dt) and dt > 1e-9 * t_end):
                raise SPHError(f"time step {dt!r} µs at t = {t:.6g} µs (step {solver.steps}): the state is no "
                               "longer finite or the step collapsed")
            step = min(dt, target - t)
            sums = solver.step(step)
            t = target if target - t - step <= 1e-12 * t_end else t + step
            rows.append((t,) + sums)
            if progress is not None:
                progress(t, t_end)
        if target in marks:
            snapshots.append(solver.particles(target))
    h = np.array(rows)
    history = History(time=h[:, 0], mass=h[:, 1], momentum=h[:, 2:5], kinetic=h[:, 5], internal=h[:, 6])
    final = snapshots[-1] if marks and marks[-1] == t_end else solver.particles(t_end)
    return RunResult(state=final, history=history, snapshots=tuple(snapshots), steps=solver.steps)
