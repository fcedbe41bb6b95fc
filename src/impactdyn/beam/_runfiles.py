"""Run folder of a beam simulation: tables, summary, resolved config and plots."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from impactdyn._config import dump_toml
from impactdyn._runfolder import RunFolder
from impactdyn.beam._simulate import Result, simulate

TIMESERIES_HEADER = [
    "time_s", "deflection_m", "theta_dot_rad_s", "theta_rad", "stop_displacement_m", "strain",
    "energy_J", "contact_force_N", "gap_m", "stop_velocity_m_s",
]
IMPACTS_HEADER = [
    "index", "kind", "t_start_s", "t_end_s", "duration_s", "v_approach_m_s", "v_separation_m_s",
    "restitution", "peak_force_N", "impulse_N_s",
]


def timeseries(result: Result) -> np.ndarray:
    """The listing's seven columns plus contact force, gap and stop velocity, (m, 10), SI."""
    m, y = result.model, result.y
    return np.column_stack([
        result.t, m.deflection(y), result.theta_dot, result.theta, m.stop_displacement(y),
        m.strain(y), result.energy, result.contact_force, m.gap(y), m.gap_rate(y),
    ])


def impacts_rows(result: Result) -> list[list]:
    return [[k + 1, i.kind, i.t_start, i.t_end, i.t_end - i.t_start, i.v_approach, i.v_separation,
             i.restitution, "" if i.peak_force is None else i.peak_force, i.impulse]
            for k, i in enumerate(result.impacts)]


def first_impact_zoom(result: Result, samples: int = 400) -> Result | None:
    """Re-integrate a short window around the first contact at fine output resolution.

    Starts from the last output state before the contact (the run is deterministic,
    so this reproduces the same trajectory) and resolves the force pulse, which
    lasts far less than the output step.
    """
    if not result.impacts:
        return None
    first = result.impacts[0]
    k = int(np.searchsorted(result.t, first.t_start)) - 1
    if k < 0:
        return None
    duration = max(first.t_end - first.t_start, 1e-6)
    t0 = float(result.t[k])
    t1 = min(first.t_end + 2.0 * duration, result.case.time.end_s)
    th, q, thd, qd = result.model.split(result.y[k])
    case = result.case
    zoom_case = case.model_copy(update={
        "time": case.time.model_copy(update={"start_s": t0, "end_s": t1,
                                             "output_step_s": (t1 - t0) / samples}),
        "initial": case.initial.model_copy(update={
            "theta_rad": float(th), "theta_dot_rad_s": float(thd), "q_m": q.tolist(),
            "q_dot_m_s": qd.tolist(), "tip_deflection_m": 0.0, "tip_velocity_m_s": 0.0}),
    })
    return simulate(zoom_case)


def write_run(result: Result, outdir: str | Path, force: bool = False, extra_summary: dict | None = None) -> Path:
    """Write the run folder atomically (refuses an existing folder unless ``force``)."""
    with RunFolder(outdir, force=force) as rf:
        summary = result.summary()
        if extra_summary:
            summary.update(extra_summary)
        rf.write_json("summary.json", summary)
        rf.write_text("config.resolved.toml", dump_toml(result.case))
        rf.write_csv("timeseries.csv", TIMESERIES_HEADER, timeseries(result).tolist())
        rf.write_csv("impacts.csv", IMPACTS_HEADER, impacts_rows(result))
        if result.case.output.plots:
            write_plots(result, rf.path / "plots")
    return Path(outdir)


def write_plots(result: Result, folder: Path) -> None:
    """θ and θ̇; deflection and strain; stop point; contact force with a zoom; energy balance."""
    from impactdyn._plotting import pyplot, save_figure

    plt = pyplot()

    folder.mkdir(parents=True, exist_ok=True)
    ts = timeseries(result)
    t = ts[:, 0]

    def two_panel(name, a, b, la, lb):
        fig, axes = plt.subplots(2, 1, sharex=True, figsize=(7, 5), constrained_layout=True)
        axes[0].plot(t, a)
        axes[0].set_ylabel(la)
        axes[1].plot(t, b)
        axes[1].set_ylabel(lb)
        axes[1].set_xlabel("time (s)")
        for ax in axes:
            ax.grid(alpha=0.3)
        save_figure(fig, folder / name, dpi=110)

    two_panel("hub.png", ts[:, 3], ts[:, 2], "θ (rad)", "θ̇ (rad/s)")
    xr = result.case.output.response_point_m
    two_panel("response_point.png", ts[:, 1] * 1e3, ts[:, 5] * 1e6,
              f"deflection w({xr:g} m) (mm)", "strain R₁·w'' (µε)")
    two_panel("stop_point.png", ts[:, 4] * 1e3, ts[:, 9], "stop-point displacement (mm)",
              "stop-point velocity (m/s)")

    fig, axes = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
    zoom = first_impact_zoom(result)
    impulsive = result.impacts and result.impacts[0].peak_force is None
    # the pulses are far shorter than the output step: show one stem per contact
    stems = [i.impulse if impulsive else i.peak_force for i in result.impacts]
    axes[0].vlines([i.t_start for i in result.impacts], 0, stems)
    axes[0].set_ylabel("impulse per impact (N·s)" if impulsive else "peak force per contact (N)")
    axes[0].set_xlabel("time (s)")
    axes[0].set_title("contact")
    if zoom is not None:
        zt = (zoom.t - result.impacts[0].t_start) * 1e6
        if impulsive:
            axes[1].plot(zt, zoom.model.gap_rate(zoom.y))
            axes[1].set_ylabel("stop-point velocity (m/s)")
        else:
            axes[1].plot(zt, zoom.contact_force)
            axes[1].set_ylabel("contact force (N)")
        axes[1].set_xlabel("time from first contact (µs)")
        axes[1].set_title("first impact")
    for ax in axes:
        ax.grid(alpha=0.3)
    save_figure(fig, folder / "contact_force.png", dpi=110)

    terms = result.energy_terms()
    fig, ax = plt.subplots(figsize=(7, 4.5), constrained_layout=True)
    ax.plot(t, terms["energy"] - terms["energy"][0], label="E − E₀")
    ax.plot(t, terms["work_torque"], label="work of torque")
    ax.plot(t, -(terms["dissipated_joint"] + terms["dissipated_modal"]), label="− damping losses")
    ax.plot(t, terms["work_contact"], label="work of contact")
    ax.plot(t, terms["residual"], "k--", label="balance residual")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("energy (J)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    save_figure(fig, folder / "energy.png", dpi=110)
