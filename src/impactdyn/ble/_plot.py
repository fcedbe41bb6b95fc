"""Ballistic-limit plots (matplotlib is imported only when a plot is drawn)."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import numpy as np

from impactdyn._errors import InputError
from impactdyn.ble._jsc import BallisticLimitCurve, Regime

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


def plot_ballistic_limit(curves: list[BallisticLimitCurve], path: str | os.PathLike,
                         shot: tuple[float, float, bool] | None = None, title: str | None = None,
                         outcomes: tuple | None = None) -> Path:
    """Draw d_c(V) curves into ``path`` (written under a temporary name, then renamed).

    The first curve's JSC regimes, if it has them, are shaded, with the boundaries
    3/cos θ and 7/cos θ marked; ``shot`` = (V km/s, d cm, perforated) is drawn as one
    point, a red cross for a perforation, a green dot otherwise.  ``outcomes`` =
    (V (n,), d (n,), value (n,), perforated (n,) bool, label): simulated shots,
    coloured by ``value`` (with a colour bar titled ``label``), crosses where the
    curve predicts perforation and dots elsewhere.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    p = Path(path)
    fig, ax = plt.subplots(figsize=(7.5, 5.4), constrained_layout=True)
    main = curves[0]
    v = main.velocity_km_s
    if main.regime is not None:
        v_lo, v_hi = main.regime_boundaries()
        spans = ((Regime.BALLISTIC, v[0], v_lo), (Regime.SHATTER, v_lo, v_hi), (Regime.HYPERVELOCITY, v_hi, v[-1]))
        for reg, a, b in spans:
            a, b = max(a, v[0]), min(b, v[-1])
            if b > a:
                ax.axvspan(a, b, color=_REGIME_COLOURS[reg], zorder=0, label=f"{reg.value} regime")
        for vb, vn in ((v_lo, 3), (v_hi, 7)):
            if v[0] <= vb <= v[-1]:
                ax.axvline(vb, color="0.5", ls=":", lw=1)
                ax.text(vb, 0.02, f"V cos θ = {vn} km/s ", transform=ax.get_xaxis_transform(), rotation=90,
                        va="bottom", ha="right", fontsize=8, color="0.35")
    for c in curves:
        ax.plot(c.velocity_km_s, c.critical_diameter_cm, lw=2, label=c.equation)
    if shot is not None:
        vs, ds, perforated = shot
        ax.plot([vs], [ds], marker="X" if perforated else "o", ms=10, ls="none",
                color="tab:red" if perforated else "tab:green", zorder=5,
                label=f"shot: d = {ds:g} cm at {vs:g} km/s ({'perforation' if perforated else 'no perforation'})")
    top_points = 0.0
    if outcomes is not None:
        vo, do, value, perforated, label = outcomes
        norm = matplotlib.colors.Normalize(vmin=0.0, vmax=max(float(np.max(value)), 1e-300))
        for mask, marker, name in ((perforated, "X", "JSC: perforation"), (~perforated, "o", "JSC: none")):
            if np.any(mask):
                ax.scatter(vo[mask], do[mask], c=value[mask], norm=norm, cmap="inferno_r", marker=marker,
                                s=110, edgecolors="k", linewidths=0.6, zorder=5, label=f"shot ({name})")
        fig.colorbar(matplotlib.cm.ScalarMappable(norm=norm, cmap="inferno_r"), ax=ax, label=label)
        top_points = float(np.max(do))
    ax.set_xlabel("impact velocity V (km/s)")
    ax.set_ylabel("critical projectile diameter d_c (cm)")
    ax.set_xlim(v[0], v[-1])
    top = max(float(c.critical_diameter_cm.max()) for c in curves)
    ax.set_ylim(0.0, 1.15 * max(top, top_points, 0.0 if shot is None else shot[1]))
    ax.grid(alpha=0.3)
    ax.set_title(title or f"Ballistic limit, θ = {main.obliquity_deg:g}°, "
                          f"ρ_p = {main.projectile_density:g} g/cm³", fontsize=10)
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncols=2, frameon=False)
    fd, tmp = tempfile.mkstemp(prefix=f".{p.stem}.", suffix=p.suffix, dir=p.parent)
    os.close(fd)
    try:
        fig.savefig(tmp, dpi=120)
        os.replace(tmp, p)
    finally:
        plt.close(fig)
        if os.path.exists(tmp):
            os.unlink(tmp)
    return p
