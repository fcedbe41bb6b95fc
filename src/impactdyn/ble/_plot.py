"""Ballistic-limit plots (matplotlib is imported only when a plot is drawn)."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from impactdyn._errors import InputError
from impactdyn._plotting import pyplot, save_figure
from impactdyn.ble._curve import BallisticLimitCurve
from impactdyn.ble._database import ShotDatabase
from impactdyn.ble._equation import V_HYPERVELOCITY_MIN_KM_S, Regime, capped_cos
from impactdyn.ble._registry import get_equation
from impactdyn.ble._validate import Validation

_REGIME_COLOURS = {Regime.BALLISTIC: "#dbe9f6", Regime.SHATTER: "#fdf1d6", Regime.HYPERVELOCITY: "#f6dede"}


def check_plot_path(path: str | os.PathLike, force: bool = False) -> Path:
    """Refuse a plot path that cannot be written, before any work is done.

    The suffix must be an image format matplotlib writes, the folder must exist, and
    an existing file is replaced only with ``force``.
    """
    p = Path(path)
    from matplotlib.figure import Figure

    formats = Figure().canvas.get_supported_filetypes()
    if p.suffix.lower().lstrip(".") not in formats:
        raise InputError(f"{p}: unknown plot format {p.suffix!r}; use one of "
                         + ", ".join("." + f for f in sorted(formats)))
    if not p.parent.is_dir():
        raise InputError(f"{p}: folder {p.parent} does not exist")
    if p.is_dir():
        raise InputError(f"{p}: is a folder")
    if p.exists() and not force:
        raise InputError(f"{p}: exists; pass --force to overwrite it")
    return p


def _shade_regimes(ax, curve: BallisticLimitCurve) -> None:
    v = curve.velocity_km_s
    v_lo, v_hi = curve.regime_boundaries_km_s
    spans = ((Regime.BALLISTIC, v[0], v_lo), (Regime.SHATTER, v_lo, v_hi), (Regime.HYPERVELOCITY, v_hi, v[-1]))
    for reg, a, b in spans:
        a, b = max(a, v[0]), min(b, v[-1])
        if b > a:
            ax.axvspan(a, b, color=_REGIME_COLOURS[reg], zorder=0, label=f"{reg.value} regime")
    cos_t = capped_cos(curve.obliquity_deg)
    for vb in (v_lo, v_hi):
        if v[0] <= vb <= v[-1]:
            ax.axvline(vb, color="0.5", ls=":", lw=1)
            ax.text(vb, 0.02, f"V cos θ = {vb * cos_t:.3g} km/s ", transform=ax.get_xaxis_transform(), rotation=90,
                    va="bottom", ha="right", fontsize=8, color="0.35")


#: Test shots of one outcome drawn as one stack, with its count: diameters within this share of each other ...
STACK_DIAMETER_SHARE = 0.01
#: ... and speeds within this share of the velocity axis's span of the next (a marker is about 2 % wide).
STACK_SPEED_SHARE = 0.02


def _draw_shots(ax, shots: ShotDatabase, x: np.ndarray, y: np.ndarray, what: str) -> None:
    """P as red crosses, NP as open blue circles, half transparent so that markers over one another darken."""
    p = shots.perforated
    if p.any():
        ax.scatter(x[p], y[p], marker="X", s=45, color="tab:red", edgecolors="k", linewidths=0.4, alpha=0.6,
                   zorder=4, label=f"{what}: perforated ({int(p.sum())})")
    if not p.all():
        ax.scatter(x[~p], y[~p], marker="o", s=36, facecolors="none", edgecolors="tab:blue", linewidths=1.0,
                   alpha=0.7, zorder=4, label=f"{what}: not perforated ({int((~p).sum())})")


def shot_stacks(velocity: np.ndarray, diameter: np.ndarray, speed_gap: float) -> list[np.ndarray]:
    """The indices of each stack of shots drawn over one another: the same diameter (within
    :data:`STACK_DIAMETER_SHARE` of the stack's smallest) and speeds each within ``speed_gap`` (km/s) of the
    next; stacks of two or more only, each in order of speed."""
    by_diameter = np.argsort(diameter, kind="stable")
    rows, row = [], []
    for i in by_diameter:
        if row and diameter[i] > (1.0 + STACK_DIAMETER_SHARE) * diameter[row[0]]:
            rows.append(row)
            row = []
        row.append(i)
    rows.append(row)
    stacks = []
    for row in rows:
        ordered = sorted(row, key=lambda k: velocity[k])
        cuts = [j for j in range(1, len(ordered)) if velocity[ordered[j]] - velocity[ordered[j - 1]] > speed_gap]
        stacks += [np.array(part) for part in np.split(np.array(ordered, dtype=int), cuts) if len(part) > 1]
    return stacks


def _count_stacks(ax, shots: ShotDatabase, speed_gap: float) -> None:
    """Each stack of test shots of one outcome (:func:`shot_stacks`) counted beside it, ×n above the
    perforations and below the holds (a white halo keeps it legible over a neighbouring row's markers), and a
    legend line that says what ×n is."""
    from matplotlib.patheffects import withStroke

    v, d, p = shots.velocity_km_s, shots.diameter_cm, shots.perforated
    counted = False
    for outcome, colour, offset, va in ((True, "tab:red", 7, "bottom"), (False, "tab:blue", -7, "top")):
        pick = np.flatnonzero(p == outcome)
        for stack in shot_stacks(v[pick], d[pick], speed_gap):
            k = pick[stack]
            ax.annotate(f"×{len(k)}", (float(np.mean(v[k])), float(d[k[0]])), xytext=(0, offset),
                        textcoords="offset points", ha="center", va=va, fontsize=7, color=colour, zorder=5,
                        path_effects=[withStroke(linewidth=2.5, foreground="white")])
            counted = True
    if counted:
        ax.plot([], [], ls="none", label=f"×n: n test shots of one outcome and diameter within {speed_gap:.2g} km/s")


def _draw_curves(ax, curves: list[BallisticLimitCurve], shot=None, outcomes=None,
                 shots: ShotDatabase | None = None, simulated=None, limit=None, tested=None, band=None) -> None:
    main = curves[0]
    v = main.velocity_km_s
    if main.regime_boundaries_km_s is not None:
        _shade_regimes(ax, main)
    tops = []
    for c in curves:
        (line,) = ax.plot(c.velocity_km_s, c.critical_diameter_cm, lw=2, label=c.equation)
        missing = np.isnan(c.critical_diameter_cm)
        if missing.any():
            ax.plot(c.velocity_km_s, np.where(missing, c.threshold_cm, np.nan), lw=1.5, ls="--", color=line.get_color(),
                    label=f"{c.equation}: no fixed point, perforation starts here")
        tops.append(np.nanmax(c.threshold_cm))
    if shot is not None:
        vs, ds, perforated = shot
        ax.plot([vs], [ds], marker="X" if perforated else "o", ms=10, ls="none",
                color="tab:red" if perforated else "tab:green", zorder=5,
                label=f"shot: d = {ds:g} cm at {vs:g} km/s ({'perforation' if perforated else 'no perforation'})")
        tops.append(ds)
    if outcomes is not None:
        import matplotlib

        vo, do, value, perforated, label = outcomes
        norm = matplotlib.colors.Normalize(vmin=0.0, vmax=max(float(np.max(value)), 1e-300))
        for mask, marker, name in ((perforated, "X", "JSC: perforation"), (~perforated, "o", "JSC: none")):
            if np.any(mask):
                ax.scatter(vo[mask], do[mask], c=value[mask], norm=norm, cmap="inferno_r", marker=marker,
                           s=110, edgecolors="k", linewidths=0.6, zorder=5, label=f"shot ({name})")
        ax.figure.colorbar(matplotlib.cm.ScalarMappable(norm=norm, cmap="inferno_r"), ax=ax, label=label)
        tops.append(float(np.max(do)))
    if shots is not None and len(shots):
        _draw_shots(ax, shots, shots.velocity_km_s, shots.diameter_cm, "test shot")
        _count_stacks(ax, shots, STACK_SPEED_SHARE * (v[-1] - v[0]))
        tops.append(float(np.max(shots.diameter_cm)))
    if simulated is not None and len(simulated[0]):
        vs, ds, failed = (np.asarray(a) for a in simulated)
        for mask, marker, colour, name in ((failed, "P", "darkred", "perforation / detached spall"),
                                           (~failed, "s", "darkgreen", "no perforation")):
            if mask.any():
                ax.scatter(vs[mask], ds[mask], marker=marker, s=40, color=colour, alpha=0.75, zorder=6,
                           label=f"simulated shot: {name} ({int(mask.sum())})")
        tops.append(float(np.max(ds)))
    if limit is not None and len(limit[0]):
        vl, dl, half, label = limit
        ax.errorbar(vl, dl, yerr=half, fmt="D-", color="tab:purple", ms=7, capsize=5, lw=1.5, zorder=7, label=label)
        tops.append(float(np.max(np.asarray(dl) + np.asarray(half))))
    if band is not None and len(band[0]):
        vb, p10, p50, p90 = (np.asarray(a, dtype=float) for a in band)
        ax.errorbar(vb, p50, yerr=[p50 - p10, p90 - p50], fmt="s", mfc="none", color="tab:purple", ms=9,
                    capsize=8, lw=3, alpha=0.6, zorder=6,
                    label="simulated P = 0.5, band P = 0.1–0.9 (logistic over the draws)")
    if tested is not None and len(tested[0]):
        vt, low, d50, high, v_band = (np.asarray(a, dtype=float) for a in tested)
        ax.errorbar(vt, d50, xerr=v_band, yerr=[d50 - low, high - d50], fmt="o", color="tab:orange", ms=8,
                    capsize=5, lw=1.5, zorder=7, label="limit from the tests (50 %, 95 % interval; velocity band)")
        tops.append(float(np.max(high)))
    ax.set_xlabel("impact velocity V (km/s)")
    ax.set_ylabel("critical projectile diameter d_c (cm)")
    ax.set_xlim(v[0], v[-1])
    ax.set_ylim(0.0, 1.15 * max(tops))
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncols=2, frameon=False)


def plot_ballistic_limit(curves: list[BallisticLimitCurve], path: str | os.PathLike,
                         shot: tuple[float, float, bool] | None = None, title: str | None = None,
                         outcomes: tuple | None = None, shots: ShotDatabase | None = None,
                         simulated: tuple | None = None, limit: tuple | None = None,
                         tested: tuple | None = None, band: tuple | None = None) -> Path:
    """Draw d_c(V) curves into ``path`` (written under a temporary name, then renamed).

    The first curve's regimes, if it has them, are shaded, with the boundaries marked;
    where a curve has no fixed point (2011 form) its perforation threshold is dashed.
    ``shot`` = (V km/s, d cm, perforated) is drawn as one point, a red cross for a
    perforation, a green dot otherwise.  ``outcomes`` = (V (n,), d (n,), value (n,),
    perforated (n,) bool, label): simulated shots, coloured by ``value`` (with a colour bar
    titled ``label``), crosses where the curve predicts perforation and dots elsewhere.
    ``shots``: test shots (e.g. :func:`impactdyn.ble.nearby_shots`), red crosses where the
    rear wall was perforated (P), open blue circles where not (NP).  ``simulated`` = (V (n,),
    d (n,), failed (n,) bool): shots whose wall verdict a simulation gave, dark red pluses where
    it failed and dark green squares where not.  ``limit`` = (V (m,), d (m,), half width (m,),
    label): a limit found by bisection, drawn with its brackets as error bars.  ``tested`` = (V (k,),
    d low (k,), d50 (k,), d high (k,), half band (k,)): limits fitted to test shots
    (:func:`impactdyn.ble.derived_limits`), an open interval end drawn to the plot's edge.  ``band`` =
    (V (j,), d at P = 0.1 (j,), d at P = 0.5 (j,), d at P = 0.9 (j,)): a simulated limit over the fragments'
    draws, its 50 % diameter with the band 10–90 %.
    """
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8.5, 5.8), constrained_layout=True)
    _draw_curves(ax, curves, shot, outcomes, shots, simulated, limit, tested, band)
    main = curves[0]
    ax.set_title(title or f"Ballistic limit, θ = {main.obliquity_deg:g}°, "
                          f"ρ_p = {main.projectile_density:g} g/cm³", fontsize=10)
    return save_figure(fig, path, dpi=120)


def _percent(x: float | None) -> str:
    return "–" if x is None else f"{100 * x:.1f} %"


def plot_validation(validations: list[Validation], path: str | os.PathLike,
                    curves: list[BallisticLimitCurve] | None = None, shots: ShotDatabase | None = None,
                    title: str | None = None) -> Path:
    """Test shots as d/d_c against V cos θ, one panel per equation; optionally a configuration.

    d/d_c > 1 is a perforation call; a red cross above 1 or an open circle below it is a
    right call.  θ is capped at 65° as in the equations, so V cos θ places each shot in its
    regime (dotted lines at the boundaries).  Shots where the 2011 form has no fixed point
    are drawn at d over the perforation threshold, ringed in grey.  With ``curves``, a last
    panel draws them with ``shots`` (those near the configuration) on them; ``title``
    heads that panel.
    """
    plt = pyplot()
    n = len(validations) + (curves is not None)
    fig, axes = plt.subplots(1, n, figsize=(6.4 * n, 5.6), constrained_layout=True, squeeze=False)
    for ax, val in zip(axes[0], validations):
        db = val.database
        vn = db.velocity_km_s * capped_cos(db.obliquity_deg)
        ratio = db.diameter_cm / val.limit.threshold_cm
        ax.axhline(1.0, color="k", lw=1)
        for vb in (get_equation(val.equation).ballistic_max_km_s, V_HYPERVELOCITY_MIN_KM_S):
            ax.axvline(vb, color="0.5", ls=":", lw=1)
        _draw_shots(ax, db, vn, ratio, "test shot")
        none = np.isnan(val.limit.critical_diameter_cm)
        if none.any():
            ax.scatter(vn[none], ratio[none], s=110, facecolors="none", edgecolors="0.55", linewidths=1.2, zorder=3,
                       label=f"no fixed point: d / threshold ({int(none.sum())})")
        s = val.overall
        ax.set_title(f"{val.title}\naccuracy {_percent(s.accuracy)}, false-safe {_percent(s.false_safe_rate)}, "
                     f"false-alarm {_percent(s.false_alarm_rate)} ({s.shots} shots)", fontsize=9)
        ax.set_yscale("log")
        ax.set_xlabel("V cos θ (km/s), θ capped at 65°")
        ax.set_ylabel("d / d_c")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncols=2, frameon=False)
    if curves is not None:
        ax = axes[0][-1]
        _draw_curves(ax, curves, shots=shots)
        ax.set_title(title or "configuration", fontsize=9)
    return save_figure(fig, path, dpi=120)


#: Names of the forecasts in the reliability diagram's legend (keys of :func:`impactdyn.ble.forecast_scores`).
FORECAST_LABELS = {"simulated": "simulation, k of N draws", "jsc": "JSC 2011 verdict (0 or 1)",
                   "database_logistic": "the database's logistic in d/d_c"}


def plot_reliability(forecasts: dict, path: str | os.PathLike, title: str | None = None) -> Path:
    """The reliability diagram of :func:`impactdyn.ble.forecast_scores`' result ``forecasts`` (name → its
    scores with ``reliability`` bins): each bin's observed frequency of perforation (Wilson 95 % interval)
    against its mean forecast P, the marker's area growing with the bin's shots, over the diagonal of a
    reliable forecast."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6.0, 5.6), constrained_layout=True)
    ax.plot([0, 1], [0, 1], color="0.6", lw=1, ls="--", label="reliable: observed = forecast")
    for k, ((name, scores), marker, offset) in enumerate(zip(forecasts.items(), "osD^v",
                                                            (0.0, -0.012, 0.012, -0.024, 0.024))):
        bins = scores["reliability"]
        mean_p = np.array([b["mean_p"] for b in bins]) + offset     # side by side where bins coincide
        observed = np.array([b["observed"] for b in bins])
        low, high = (np.array([b["observed_95"][i] for b in bins]) for i in (0, 1))
        shots = np.array([b["shots"] for b in bins])
        ax.errorbar(mean_p, observed, yerr=[observed - low, high - observed], fmt="none", capsize=3, lw=1,
                    color=f"C{k}")
        ax.scatter(mean_p, observed, s=25 + 12 * shots, marker=marker, color=f"C{k}",
                   alpha=0.8, label=f"{FORECAST_LABELS.get(name, name)} (Brier {scores['brier']:.3f})", zorder=3)
        for x, y, n in zip(mean_p, observed, shots):
            ax.annotate(str(n), (x, y), textcoords="offset points", xytext=(6, -10), fontsize=7)
    ax.set(xlim=(-0.05, 1.05), ylim=(-0.05, 1.05), xlabel="forecast P(perforation), bin mean",
           ylabel="observed frequency of perforation (95 % interval)")
    ax.legend(loc="upper left", fontsize=8)
    ax.set_title(title or "Reliability of the forecasts (numbers: shots in the bin)", fontsize=10)
    return save_figure(fig, path, dpi=120)
