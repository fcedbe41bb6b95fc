"""The simulated ballistic limit: for each velocity, the diameter where the simulated verdict changes.

For each velocity V the search brackets the critical diameter between a diameter the
simulation calls safe (``no perforation``) and one it calls failed (``perforation`` or
``detached spall``: JSC test practice counts both as a failed rear wall), then halves
the bracket until it is no wider than ``tolerance_cm``:

1. start from [d_JSC/r, d_JSC·r] about the JSC critical diameter (r = ``bracket_ratio``), or
   from the bracket the user gives for that velocity (``brackets``: a bracket found by an
   earlier, interrupted search, or a guess), whose ends are shot again like any other;
2. while both ends give the same verdict, move the bracket by the factor r toward the
   change (down if both fail, up if both hold), at most ``max_expansions`` times, after
   which the velocity is reported as unbracketed, with the shots it took;
3. bisect: d = (d_safe + d_failed)/2 until d_failed − d_safe ≤ ``tolerance_cm``.

The SPH resolution follows the diameter: a shot smaller than the case's projectile gets
the case's particles per projectile diameter (``shield.spacing_cm`` scaled by d/d_case),
a larger one keeps the case's spacing, so no shot is resolved more coarsely than the
case itself.

With the fragments' draws (``draws`` = N, ``shield.fragment_draws``), each shot runs N partitions of
the fragments and its verdict is a fraction k/N; the bisection counts a shot as failed when
k/N ≥ 1/2, so it closes on the diameter where P(perforation) = 0.5.  The band P = 0.1–0.9 is then
the logistic in ln d fitted by maximum likelihood to every draw the search made (each draw one
trial at its shot's diameter: :func:`impactdyn.ble.fit_limit`, the fit of the test-derived
limits, so the simulated band and the tests' own limit are one measure): d_q = d50 ·
exp(logit(q)/b).  Why not bisect to P = 0.1 and 0.9 as well: three searches cost three times
the shots, and a fraction near 0.1 read from N = 8 draws is 0 in 43 % of shots (binomial), so
such a bisection wanders; the fit pools N × (shots) trials, and the bisection's shots lie where a
logistic's d50 is best determined.  Its price: the band's width rests on the spread of outcomes
about d50, and where every shot's draws are unanimous (separable outcomes) the fit does not
exist and no band is given (``band_note`` says why; the bracket still bounds the 50 % diameter).

The limit reported is the bracket's midpoint ± half its width.  The search assumes one
change of verdict along d at fixed V (a thicker projectile does not do less damage);
every shot is kept in ``shots.csv``, so a non-monotone result is there to see.  Each
round runs the pending shot of every velocity at once (in parallel), so a search of
n velocities takes about as many rounds as one.

Folder (a family folder, :mod:`impactdyn._family`: written as the search goes, resumable):
``limit.csv`` / ``limit.json`` (one row per velocity; ``status`` is ``searching`` while a
velocity's search is under way), ``shots.csv`` (every shot), ``limit.png`` (the simulated
limit with its brackets over the JSC curve, the test database's shots near the
configuration and, where the tests of that configuration are enough for one, the limit fitted
to them (:func:`tested_limits`); drawn when the search ends) and ``runs/V<v>_d<d>/`` (lean run folders,
:mod:`._shots`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from impactdyn._config import set_dotted, validate
from impactdyn._errors import InputError
from impactdyn._family import FamilyFolder, run_members
from impactdyn._sweep import case_variants
from impactdyn.whipple._case import WhippleCase
from impactdyn.whipple._report import ble_verdict, wall_caution
from impactdyn.whipple._stages import FAILED_VERDICTS
from impactdyn.whipple._shots import run_shot, shot_name, shot_tasks, shot_variant, shot_workers
from impactdyn.whipple._database_shot import ALLOYS

LIMIT_HEADER = ["velocity_km_s", "limit_diameter_cm", "half_width_cm", "largest_safe_cm", "smallest_failed_cm",
                "jsc_critical_diameter_cm", "n_shots", "status", "caution", "draws_d50_cm", "draws_d50_low_cm",
                "draws_d50_high_cm", "p10_diameter_cm", "p90_diameter_cm", "band_note"]
SHOTS_HEADER = ["velocity_km_s", "diameter_cm", "simulated_verdict", "failed", "jsc_verdict", "run",
                "perforated_draws", "n_draws"]
#: logit(0.9) = ln 9: the band P = 0.1–0.9 is d50 · exp(∓ln 9 / b).
_BAND_LOGIT = math.log(9.0)



@dataclass
class _Search:
    """The bracket of one velocity: the largest safe and the smallest failed diameter found so far."""

    velocity: float
    case: WhippleCase
    jsc: float
    ratio: float
    start: tuple[float, float]
    safe: float | None = None
    failed: float | None = None
    expansions: int = 0
    status: str = "searching"
    shots: list = field(default_factory=list)

    def pending(self) -> list[float]:
        """Diameters to shoot next (none when finished)."""
        if self.status != "searching":
            return []
        if self.safe is None and self.failed is None:
            return list(self.start)
        if self.safe is None:
            return [self.failed / self.ratio]
        if self.failed is None:
            return [self.safe * self.ratio]
        return [0.5 * (self.safe + self.failed)]

    def record(self, diameter: float, failed: bool) -> None:
        if failed:
            self.failed = diameter if self.failed is None else min(self.failed, diameter)
        else:
            self.safe = diameter if self.safe is None else max(self.safe, diameter)

    def settle(self, tolerance: float, max_expansions: int) -> None:
        """After a round: done, unbracketed, or one more expansion counted."""
        if self.safe is not None and self.failed is not None:
            if self.failed < self.safe:
                self.status = "non-monotone"
            elif self.failed - self.safe <= tolerance * (1.0 + 1e-9):   # a bisected bracket lands on it in round-off
                self.status = "converged"
        elif len(self.shots) > 2:
            self.expansions += 1
            if self.expansions > max_expansions:
                self.status = "unbracketed"


def limit_velocities(raw: dict, velocities: list[float], source: str) -> list[WhippleCase]:
    """The base case at each velocity, validated before any shot."""
    return case_variants(WhippleCase, raw, [{"projectile.velocity_km_s": float(v)} for v in velocities], source)


def run_limit(raw: dict, velocities: list[float], outdir: str | Path, *, source: str = "<case>",
              tolerance_cm: float = 0.02, bracket_ratio: float = 1.25, max_expansions: int = 4,
              brackets: dict[float, tuple[float, float]] | None = None, force: bool = False, resume: bool = False,
              scheduler: str = "processes", workers: int | None = None, address: str | None = None,
              keep_all: bool = False, draws: int | None = None, progress=None) -> list[dict]:
    """Search the simulated limit at each velocity (module docstring); returns the ``limit.csv`` rows.

    ``draws``: N draws of the fragments' partition per shot (``shield.fragment_draws``; the module
    docstring says what the search and the band then are); None: the case's own.

    ``brackets`` maps a velocity (km/s, one of ``velocities``) to the diameters (low, high) (cm)
    its search starts from instead of the JSC bracket.  The tables are rewritten after each
    shot, so an interrupted search leaves them with the shots it finished; ``resume`` goes on
    in that folder, reading those shots back instead of running them again (the search asks
    for the same diameters in the same order).  ``progress(shots_done)`` is called after each shot.
    """
    if not velocities:
        raise InputError("limit: needs at least one velocity")
    if not (np.isfinite(tolerance_cm) and tolerance_cm > 0):
        raise InputError(f"--tolerance {tolerance_cm}: must be > 0 (cm)")
    if not (np.isfinite(bracket_ratio) and bracket_ratio > 1):
        raise InputError(f"--bracket-ratio {bracket_ratio}: must be > 1")
    brackets = _check_brackets(brackets or {}, velocities)
    if draws is not None:
        raw, source = set_dotted(raw, "shield.fragment_draws", draws), f"{source} (--draws {draws})"
    base = validate(WhippleCase, raw, source)
    bases = limit_velocities(raw, velocities, source)
    searches = []
    for v, case in zip(velocities, bases):
        jsc = ble_verdict(case)["threshold_cm"]
        start = brackets.get(float(v), (jsc / bracket_ratio, jsc * bracket_ratio))
        searches.append(_Search(velocity=float(v), case=case, jsc=jsc, ratio=bracket_ratio, start=start))
    settings = {"case": base.model_dump(mode="json"), "velocities_km_s": [s.velocity for s in searches],
                "tolerance_cm": tolerance_cm, "bracket_ratio": bracket_ratio, "max_expansions": max_expansions,
                "start_brackets_cm": {f"{s.velocity:g}": list(s.start) for s in searches}, "keep_all": keep_all}
    with FamilyFolder(outdir, "whipple limit", settings, table="limit.csv", member="shot", force=force,
                      resume=resume) as family:
        def record(search: _Search, d: float, case: WhippleCase, summary: dict) -> None:
            verdict = summary["wall"]["verdict"]
            # a shot run before the draws stage existed has no draws record: its one verdict is its draw
            k, n = ((summary["draws"]["perforated"], summary["draws"]["n_draws"]) if "draws" in summary
                    else (int(verdict in FAILED_VERDICTS), 1))
            failed = 2 * k >= n
            search.shots.append((d, verdict, failed, ble_verdict(case)["verdict"],
                                 f"runs/{shot_name(search.velocity, d)}", k, n))
            search.record(d, failed)
            family.finished += 1
            _write_tables(family, searches, tolerance_cm, bracket_ratio)
            if progress:
                progress(family.finished)

        _write_tables(family, searches, tolerance_cm, bracket_ratio)
        while batch := [(s, d) for s in searches for d in s.pending()]:
            cases = case_variants(WhippleCase, raw, [shot_variant(base, s.velocity, d) for s, d in batch], source)
            summaries = [family.path / "runs" / shot_name(s.velocity, d) / "summary.json" for s, d in batch]
            run_members(run_shot, summaries,
                        lambda pending: shot_tasks([cases[k] for k in pending], [summaries[k].parent for k in pending],
                                                   scheduler, workers, keep_all),
                        lambda k, summary: record(*batch[k], cases[k], summary),
                        scheduler=scheduler, workers=shot_workers(scheduler, workers, len(batch)), address=address)
            for s in searches:
                s.settle(tolerance_cm, max_expansions)
            rows = _write_tables(family, searches, tolerance_cm, bracket_ratio)
        _plot(family.path / "limit.png", bases[0], searches, rows, tolerance_cm)
    return rows


def _write_tables(folder: FamilyFolder, searches: list[_Search], tolerance_cm: float, bracket_ratio: float
                  ) -> list[dict]:
    """``limit.csv``, ``limit.json`` and ``shots.csv`` as the searches stand; returns the rows."""
    rows = [_limit_row(s) for s in searches]
    folder.write_csv("limit.csv", LIMIT_HEADER, [[r[k] for k in LIMIT_HEADER] for r in rows])
    folder.write_json("limit.json", {"tolerance_cm": tolerance_cm, "bracket_ratio": bracket_ratio,
                                     "start_brackets_cm": {f"{s.velocity:g}": list(s.start) for s in searches},
                                     "rows": rows})
    folder.write_csv("shots.csv", SHOTS_HEADER, [[s.velocity, *shot] for s in searches for shot in s.shots])
    return rows


def _check_brackets(brackets: dict, velocities: list[float]) -> dict[float, tuple[float, float]]:
    """The start brackets keyed by the search's own velocity values; each 0 < low < high."""
    checked = {}
    for v, (low, high) in brackets.items():
        where = f"--bracket {v:g}:{low:g}:{high:g}"
        match = [u for u in velocities if np.isclose(u, v, rtol=1e-9, atol=0.0)]
        if not match:
            raise InputError(f"{where}: {v:g} km/s is not one of the --velocity values "
                             f"({', '.join(f'{u:g}' for u in velocities)})")
        if not (np.isfinite(low) and np.isfinite(high) and 0 < low < high):
            raise InputError(f"{where}: needs 0 < LOW < HIGH (cm)")
        checked[float(match[0])] = (float(low), float(high))
    return checked


def _limit_row(s: _Search) -> dict:
    both = s.safe is not None and s.failed is not None
    return {"velocity_km_s": s.velocity,
            "limit_diameter_cm": 0.5 * (s.safe + s.failed) if both else None,
            "half_width_cm": 0.5 * abs(s.failed - s.safe) if both else None,
            "largest_safe_cm": s.safe, "smallest_failed_cm": s.failed,
            "jsc_critical_diameter_cm": s.jsc, "n_shots": len(s.shots), "status": s.status,
            "caution": wall_caution(s.case, 0.5 * (s.safe + s.failed), s.velocity) if both else None} | _band(s)


def _band(s: _Search) -> dict:
    """The logistic over every draw of the search's shots (module docstring): its 50 % diameter with the
    profile-likelihood 95 % interval and the diameters at P = 0.1 and 0.9; all None with one draw a shot,
    and with ``band_note`` saying why where the fit does not exist."""
    from impactdyn.ble import fit_limit

    band = dict.fromkeys(LIMIT_HEADER[LIMIT_HEADER.index("draws_d50_cm"):])
    if not s.shots or max(n for *_, n in s.shots) == 1:
        return band
    diameters = [d for d, *_, k, n in s.shots for _ in range(n)]
    outcomes = [j < k for d, *_, k, n in s.shots for j in range(n)]
    fit = fit_limit(diameters, outcomes)
    if fit.refused is not None:
        return band | {"band_note": f"no logistic over the {len(outcomes)} draws: {fit.refused}"}
    spread = math.exp(_BAND_LOGIT / fit.slope)
    return band | {"draws_d50_cm": fit.d50_cm, "draws_d50_low_cm": fit.low_cm, "draws_d50_high_cm": fit.high_cm,
                   "p10_diameter_cm": fit.d50_cm / spread, "p90_diameter_cm": fit.d50_cm * spread,
                   "band_note": f"logistic in ln d over {len(outcomes)} draws of {len(s.shots)} shots"}


def tested_limits(case: WhippleCase) -> list:
    """The limits fitted to the test database's shots of the case's configuration, where a fit exists
    (:func:`impactdyn.ble.derived_limits`): the same modelled alloys (:data:`ALLOYS`), and t_b, t_w, S
    and θ within the tolerances that define a configuration there.  This, not a single shot, is what a
    simulated limit should be compared with; on the packaged database few configurations have one."""
    from impactdyn.ble import CONFIGURATION_OBLIQUITY_DEG, CONFIGURATION_TOLERANCE, derived_limits, read_database

    def near(value: float, reference: float) -> bool:
        return abs(value / reference - 1.0) <= CONFIGURATION_TOLERANCE

    p, b, w = case.projectile, case.bumper, case.wall
    found = []
    for t in derived_limits(read_database()):
        c = t.configuration
        if (t.fit.refused is None
                and (ALLOYS.get(c.projectile_material), ALLOYS.get(c.bumper_material), ALLOYS.get(c.wall_material))
                == (p.material, b.material, w.material)
                and near(c.bumper_thickness_cm, b.thickness_cm) and near(c.wall_thickness_cm, w.thickness_cm)
                and near(c.spacing_cm, w.spacing_cm)
                and abs(c.obliquity_deg - p.obliquity_deg) <= CONFIGURATION_OBLIQUITY_DEG):
            found.append(t)
    return found


def _plot(path: Path, case: WhippleCase, searches: list[_Search], rows: list[dict], tolerance: float) -> None:
    """The simulated limit of the ``limit.csv`` rows with its brackets and every shot, over the JSC
    curve and the test database's shots near the configuration (:func:`impactdyn.ble.nearby_shots`)."""
    from impactdyn.ble import ballistic_limit_curve, nearby_shots, plot_ballistic_limit
    from impactdyn.materials import get_material
    from impactdyn.whipple._case import ble_shield

    p, w, b = case.projectile, case.wall, case.bumper
    vmax = max(15.0, 1.1 * max(s.velocity for s in searches))
    shield = ble_shield(case)
    curve = ballistic_limit_curve(shield, np.linspace(1.0, vmax, 281), p.obliquity_deg, get_material(p.material).rho0)
    shots = [(s.velocity, d, failed) for s in searches for d, _, failed, *_ in s.shots]
    banded = [r for r in rows if r["p10_diameter_cm"] is not None]
    drawn = any(n > 1 for s in searches for *_, n in s.shots)
    done = [r for r in rows if r["limit_diameter_cm"] is not None]
    tested = [(0.5 * (t.velocity_low_km_s + t.velocity_high_km_s), t.fit.low_cm or 0.0, t.fit.d50_cm,
               t.fit.high_cm or 2.0 * t.fit.d50_cm, 0.5 * (t.velocity_high_km_s - t.velocity_low_km_s))
              for t in tested_limits(case)]
    plot_ballistic_limit(
        [curve], path, shots=nearby_shots(shield, p.obliquity_deg),
        simulated=tuple(np.array(c) for c in zip(*shots)) if shots else None,
        limit=([r["velocity_km_s"] for r in done], [r["limit_diameter_cm"] for r in done],
               [r["half_width_cm"] for r in done],
               f"simulated limit (bisection to {tolerance:g} cm{' on P ≥ 1/2 of the draws' if drawn else ''})"),
        tested=tuple(zip(*tested)) if tested else None,
        band=tuple(zip(*[(r["velocity_km_s"], r["p10_diameter_cm"], r["draws_d50_cm"], r["p90_diameter_cm"])
                         for r in banded])) if banded else None,
        title=f"Simulated ballistic limit: t_b = {b.thickness_cm:g} cm, t_w = {w.thickness_cm:g} cm, "
              f"S = {w.spacing_cm:g} cm, θ = {p.obliquity_deg:g}°, wall model {case.wall_solver.material_model}")
