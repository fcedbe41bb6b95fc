"""Time integration of the SPH equations (:mod:`._equations`): the solver's arrays and step sequence, and :func:`run`.

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
from impactdyn.shield._equations import (FRAGMENTATION, NO_FAILURE, PS_WIDTH, ST_WIDTH, THRESHOLD, finish_step,
                                         kick_drift_predict, pair_rows, pair_sums, particle_rates, temperatures,
                                         totals, update_particles)
from impactdyn.shield._kernel import w_shape
from impactdyn.shield._neighbours import NeighbourList, spatial_order
from impactdyn.shield._options import SPHOptions
from impactdyn.shield._state import History, Particles, RunResult


class SPHError(SimulationError):
    """The SPH run broke down (non-finite state or a collapsing time step)."""



class _Solver:
    """The arrays of one run and the step sequence (:mod:`._equations`), allocated once.

    Particles are kept in spatial (cell-key) order for cache locality: every
    ``REORDER_EVERY`` steps the state, its rates and the neighbour list are
    permuted; ``ids`` maps the stored order back to the problem's particle order.
    The neighbour list is reused across steps within its skin (:mod:`._neighbours`).
    """

    REORDER_EVERY = 10
    STATE = ("x", "v", "m", "rho", "e", "S", "eps_p", "damage", "ductile", "flaws", "failure_rate", "switch", "mat",
             "ids", "acc", "dlnrho", "de", "dS", "rate")

    def __init__(self, problem, options: SPHOptions):
        init = problem.particles
        n = len(init)
        self.options, self.domain, self.names = options, problem.domain, init.materials
        self.params = pack_materials(problem.materials)
        self.x, self.v = init.position.copy(), init.velocity.copy()
        self.m, self.rho, self.e = init.mass.copy(), init.density.copy(), init.specific_energy.copy()
        self.S, self.eps_p, self.damage = init.deviatoric_stress.copy(), init.plastic_strain.copy(), init.damage.copy()
        self.mat, self.ids = init.material.copy(), np.arange(n)
        self.failure = (NO_FAILURE if not options.failure else
                        FRAGMENTATION if options.failure_model == "fragmentation" else THRESHOLD)
        self.damage_table = pack_damage(problem.materials)
        self.ductile = np.zeros(n)
        self.failure_rate = init.failure_strain_rate.copy()
        self.flaws = (new_flaws(self.mat, self.names, self.damage_table) if self.failure == FRAGMENTATION
                      else np.zeros((n, N_FLAW)))
        self.balsara = options.viscosity_switch == "balsara"
        self.switch = np.ones(n)  # the viscosity switch fᵢ: 1 until a velocity gradient is known
        z1, z3, z6 = (lambda: np.zeros(n)), (lambda: np.zeros((n, 3))), (lambda: np.zeros((n, 6)))
        self.p, self.c, self.h, self.rate, self.dt_i = z1(), z1(), z1(), z1(), z1()
        self.R, self.tension = z6(), np.zeros(n, dtype=np.bool_)
        self.pos, self.st = np.zeros((n, 4)), np.zeros((n, ST_WIDTH))
        self.sums = np.zeros((0, n, PS_WIDTH))  # per-thread pair sums, sized at the first force pass
        self.work_a, self.work_v, self.grad_v = np.zeros((n, 3, 3)), np.zeros((n, 3, 3)), np.zeros((n, 3, 3))
        self.acc, self.dlnrho, self.de, self.dS = z3(), z1(), z1(), z6()
        self.acc_new, self.dlnrho_new, self.de_new, self.dS_new = z3(), z1(), z1(), z6()
        self.v_p, self.rho_p, self.e_p, self.S_p = z3(), z1(), z1(), z6()
        self.neighbours = NeighbourList(n, problem.domain, skin=options.neighbour_skin, half=True)
        self.jc = options.flow_stress == "johnson_cook"
        self.rho_floor = options.h_max_factor ** -3.0
        self.as_norm = 1.0 / float(w_shape(1.0 / options.h_factor))
        self.steps = 0
        self._eos(self.rho, self.e, self.S)
        pair_rows(self.x, self.h, self.v, self.c, self.rho, self.m, self.S, self.p, self.damage, self.switch, self.pos,
                  self.st)
        self._pair_sums()
        particle_rates(self.pos, self.st, self.S, self.damage, self.mat, self.params, self.rho_floor, options.alpha,
                       options.beta, options.cfl, options.force_cfl, self.balsara, self.sums, self.grad_v, self.acc,
                       self.dlnrho, self.de, self.dS, self.rate, self.switch, self.dt_i)
        self.dt = float(self.dt_i.min())

    def _eos(self, rho, e, S) -> None:
        o = self.options
        update_particles(self.m, rho, e, S, self.damage, self.mat, self.params, o.h_factor, self.rho_floor,
                         o.artificial_stress, self.p, self.c, self.h, self.R, self.tension, self.work_a, self.work_v)

    def _pair_sums(self) -> None:
        """Neighbour list at the current positions and the pair sums of the pair-loop rows (pos, st)."""
        o, nl = self.options, self.neighbours
        if 2.0 * self.h.max() > self.domain.min_period():
            raise SPHError(f"kernel support 2h = {2 * self.h.max():.4g} cm exceeds the periodic length "
                           f"{self.domain.min_period():.4g} cm")
        nl.update(self.x, self.h)
        if self.sums.shape[0] != get_num_threads():
            self.sums = np.zeros((get_num_threads(), self.m.size, PS_WIDTH))
        pair_sums(self.pos, self.st, self.R, self.tension, nl.neighbours, nl.image, nl.count, nl.signs, nl.offsets,
                  o.alpha, o.beta, o.artificial_stress_power, self.as_norm, self.sums)

    def totals(self) -> tuple[float, ...]:
        return totals(self.m, self.v, self.e)

    def step(self, dt: float) -> tuple[float, ...]:
        """Advance by dt (:mod:`._equations`); returns the totals of the new state."""
        if self.steps % self.REORDER_EVERY == 0:
            order = spatial_order(self.x, self.h)
            for name in self.STATE:
                setattr(self, name, getattr(self, name)[order])
            self.neighbours.permute(order)
        o = self.options
        kick_drift_predict(self.x, self.v, self.acc, self.rho, self.dlnrho, self.e, self.de, self.S, self.dS,
                           self.eps_p, self.rate, self.damage, self.switch, self.m, self.mat, self.params, self.jc,
                           o.h_factor, self.rho_floor, o.artificial_stress, dt, self.v_p, self.rho_p, self.e_p,
                           self.S_p, self.p, self.c, self.h, self.R, self.tension, self.work_a, self.work_v, self.pos,
                           self.st)
        if self.domain.wrap(self.x):
            self.neighbours.invalidate()
            pair_rows(self.x, self.h, self.v_p, self.c, self.rho_p, self.m, self.S_p, self.p, self.damage, self.switch,
                      self.pos, self.st)
        self._pair_sums()
        new_totals = finish_step(self.pos, self.st, self.S_p, self.damage, self.mat, self.params, self.rho_floor,
                                 o.alpha, o.beta, o.cfl, o.force_cfl, self.sums, self.grad_v, self.acc_new,
                                 self.dlnrho_new, self.de_new, self.dS_new, self.rate, self.dt_i, self.v, self.m,
                                 self.rho, self.dlnrho, self.e, self.de, self.S, self.dS, self.eps_p, self.jc,
                                 self.failure, self.damage_table, self.flaws, self.ductile, self.failure_rate,
                                 self.balsara, self.switch, dt)
        self.dt = float(self.dt_i.min())
        self.acc, self.acc_new = self.acc_new, self.acc
        self.dlnrho, self.dlnrho_new = self.dlnrho_new, self.dlnrho
        self.de, self.de_new = self.de_new, self.de
        self.dS, self.dS_new = self.dS_new, self.dS
        self.steps += 1
        return new_totals

    def particles(self, time: float) -> Particles:
        """The current state as :class:`Particles`, in the problem's particle order."""
        self._eos(self.rho, self.e, self.S)
        back = np.argsort(self.ids)
        T = temperatures(self.rho, self.e, self.mat, self.params)
        return Particles(position=self.x[back], velocity=self.v[back], mass=self.m[back], density=self.rho[back],
                         pressure=self.p[back], specific_energy=self.e[back], deviatoric_stress=self.S[back],
                         plastic_strain=self.eps_p[back], failed=self.damage[back] >= 1.0, damage=self.damage[back],
                         failure_strain_rate=self.failure_rate[back], smoothing_length=self.h[back],
                         sound_speed=self.c[back], temperature=T[back], material=self.mat[back],
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
