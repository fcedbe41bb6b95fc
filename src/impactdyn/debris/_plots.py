"""The plots of a debris run: DCMPLT's contour map of the areal density, and the cloud at hand-off and arrival."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from impactdyn import units
from impactdyn.debris._particle import P_SLICE
from impactdyn.debris._propagate import DebrisResult


#: The colour bar of the areal-momentum map, in the unit the reports' tables give the peak in.
AREAL_MOMENTUM_LABEL = f"areal momentum density |Σp|/(Δx Δz) ({units.AREAL_MOMENTUM_UNIT})"


def areal_momentum_figure(x: np.ndarray, z: np.ndarray, areal_g_cm_us: np.ndarray):
    """DCMPLT's contour map of the areal momentum ``areal_g_cm_us`` ``(nx, nz)`` on the face grid of edges ``x``,
    ``z`` (cm), drawn in :data:`impactdyn.units.AREAL_MOMENTUM_UNIT`."""
    from impactdyn._plotting import pyplot

    xc = 0.5 * (x[:-1] + x[1:])
    zc = 0.5 * (z[:-1] + z[1:])
    fig, ax = pyplot().subplots(figsize=(6, 7), constrained_layout=True)
    areal = units.N_S_PER_G_CM_US * np.asarray(areal_g_cm_us).T
    if np.any(areal > 0):
        levels = np.linspace(0.0, areal.max(), 16)
        cs = ax.contourf(xc, zc, areal, levels=levels, cmap="viridis")
        fig.colorbar(cs, ax=ax, label=AREAL_MOMENTUM_LABEL)
    else:
        ax.text(0.5, 0.5, "no momentum deposited", transform=ax.transAxes, ha="center")
    ax.set_xlim(x[0], x[-1])
    ax.set_ylim(z[0], z[-1])
    ax.set_aspect("equal")
    ax.set_xlabel("x (cm), symmetry plane at x = %.3g" % x[0])
    ax.set_ylabel("z (cm)")
    ax.set_title("Momentum deposited on the rear wall (DCPOST)")
    return fig


def write_plots(result: DebrisResult, folder: Path) -> None:
    """DCMPLT's contour map of the areal momentum (:func:`areal_momentum_figure`), and the cloud at hand-off
    and arrival."""
    from impactdyn._plotting import pyplot, save_figure

    plt = pyplot()

    folder.mkdir(parents=True, exist_ok=True)
    w, r = result.wall, result
    save_figure(areal_momentum_figure(w.x, w.z, r.areal), folder / "areal_density.png", dpi=120)

    c = r.cloud
    speed = units.cm_us_to_km_s(np.linalg.norm(c.states[:, P_SLICE] / c.mass[:, None], axis=1))
    fig, axes = plt.subplots(1, 2, figsize=(12, 5.5), constrained_layout=True)
    ax = axes[0]
    sc = ax.scatter(c.centroid[:, 1], c.centroid[:, 2], c=speed, s=2, cmap="plasma")
    fig.colorbar(sc, ax=ax, label="particle speed (km/s)")
    ax.set_xlabel("y (cm), toward the wall")
    ax.set_ylabel("z (cm)")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_title(f"cloud at hand-off, side view (t = {r.t_handoff:g} µs)")
    ax = axes[1]
    arrived = r.stats.code == 0
    if np.any(arrived):
        hit = r.points[arrived, 4]
        sc = ax.scatter(hit[:, 0], hit[:, 2], c=r.t_arrival[r.propagated][arrived], s=2, cmap="viridis")
        fig.colorbar(sc, ax=ax, label="arrival time after hand-off (µs)")
    ax.add_patch(plt.Rectangle((w.x[0], w.z[0]), w.x[-1] - w.x[0], w.z[-1] - w.z[0], fill=False, lw=1))
    ax.set_xlabel("x (cm)")
    ax.set_ylabel("z (cm)")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_title("centroids at arrival on the wall plane (wall outlined)")
    for ax in axes:
        ax.grid(alpha=0.3)
    save_figure(fig, folder / "cloud.png", dpi=120)
