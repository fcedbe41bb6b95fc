"""The report stage of a Whipple run: ``summary.json``, the figures and a self-contained ``report.html``.

Figures (``plots/``):

``cloud_handoff.png``     the shield and the debris cloud at hand-off, side and top views
                          coloured by speed, the cloud axis drawn (the report's Figures 9/12/15/18)
``ballistic_limit.png``   the JSC ballistic-limit curve with this shot and the test database's
                          shots near this shield marked (Figure 8)
``conservation.png``      the SPH run's energy and momentum against time
``fragments.png``         the debris's solid fragments: cumulative number against mass, the largest listed
                          (not drawn where the debris holds none: the report says so)
``draws.png``             with the fragments' draws (``[shield] fragment_draws`` > 1), each draw's compact
                          fragments' mass, the wall's failed mass and peak rear bulge against its seed

and the debris stage's ``debris/plots/areal_density.png`` (Figures 10/13/16/19) and the
wall stage's ``wall/plots/wall_front.png``, ``wall_rear.png`` (Figures 6–7, 11, 14, 17, 20)
and ``wall_history.png``.  ``report.html`` embeds them all as PNG data, so it is one
file to mail; its "Wall response" section sets the simulated verdict beside the equation's.
"""

from __future__ import annotations

import base64
import html
import json

import numpy as np

from impactdyn._plotting import pyplot, save_figure
from impactdyn._runfolder import FolderWriter
from impactdyn.units import AREAL_MOMENTUM_UNIT, KM_S_PER_CM_US, N_S_PER_G_CM_US
from impactdyn.whipple._case import WhippleCase, ble_shield
from impactdyn.whipple._stages import FAILED_VERDICTS, STAGES, read_stage
from impactdyn.whipple._validation_record import limit_statement, perforations_called_safe, validation_record


def _records(folder: FolderWriter) -> dict:
    """The records of every stage before the report."""
    return {stage: read_stage(folder.path, stage) for stage in STAGES[:STAGES.index("report")]}


def ble_verdict(case: WhippleCase) -> dict:
    """The ballistic-limit equation's answer for the shot (:func:`impactdyn.ble.jsc_verdict`, the
    package's default equation), with the shield and projectile density it was given."""
    from impactdyn.ble import jsc_verdict
    from impactdyn.materials import get_material

    p = case.projectile
    rho_p = get_material(p.material).rho0
    shield = ble_shield(case)
    return {"shield": shield.as_dict(), "projectile_density_g_cm3": rho_p} | jsc_verdict(
        shield, p.diameter_cm, p.velocity_km_s, p.obliquity_deg, rho_p)


def momentum_ledger(debris: dict) -> dict:
    """Where the debris's momentum at hand-off went, cloud and compact fragments together (g·cm/µs, half
    model): ``in`` + ``added_at_wall`` = ``deposited`` + ``outside_window`` + ``off_wall`` (landed beyond
    the face grid) + ``not_reaching`` (never reaches the wall plane) + ``failed`` (its flight's integration
    failed), to round-off.  ``added_at_wall`` is what the deposition gives beyond the arriving momentum
    (the cloud's crater ejecta under ``wall.momentum_transfer = "cratering"``); zero by default."""
    compact = debris["compact_fragments"]
    cloud = {k: np.array(debris[f"momentum_{k}"]) for k in ("in", "outside_window", "off_wall", "not_reaching",
                                                             "failed", "added_at_wall")}
    landed = np.array(compact["momentum"]) - np.array(compact["momentum_outside_window"])
    ledger = {"in": cloud["in"] + compact["momentum"], "added_at_wall": cloud["added_at_wall"],
              "deposited": np.array(debris["momentum_deposited"]),
              "outside_window": cloud["outside_window"] + compact["momentum_outside_window"],
              "off_wall": cloud["off_wall"] + landed - compact["momentum_deposited"],
              "not_reaching": cloud["not_reaching"], "failed": cloud["failed"]}
    return {k: v.tolist() for k, v in ledger.items()}


def deposition_figures(debris: dict) -> dict:
    """Wall figures of the debris stage's record (half model; the full model doubles y and z)."""
    p = np.array(debris["momentum_deposited"])
    peak = debris["peak_areal_density_g_cm_us"]
    mesh_peak = debris["peak_areal_density_mesh"]
    return {
        "peak_areal_momentum_g_cm_us": peak,
        "peak_areal_momentum_N_s_cm2": N_S_PER_G_CM_US * peak,
        "peak_areal_momentum_mesh_N_s_cm2": N_S_PER_G_CM_US * mesh_peak["peak_g_cm_us"],
        "mesh_face_cell_cm": mesh_peak["cell_cm"],
        "momentum_ledger_g_cm_us": momentum_ledger(debris),
        "impulse_on_wall_g_cm_us": p.tolist(),
        "impulse_on_wall_normal_N_s_full_model": 2.0 * N_S_PER_G_CM_US * float(p[1]),
        "momentum_arrived_g_cm_us": debris["momentum_arrived"],
        "mass_arrived_g": debris["mass_arrived_g"],
        "arrival_time_us": debris["arrival_time_us"],
    }


#: The validation sets of the default wall stage (:func:`~impactdyn.whipple.validation_record`).
VALIDATION = validation_record()
#: What the test shots say of the default wall stage's verdict.  The verdict it gives is the response to
#: the debris cloud's momentum, which carries no solid fragments.
WALL_VALIDATION = (f"on the validation shots the wall stage {perforations_called_safe(VALIDATION)} on "
                   f"{VALIDATION.set_names} ({VALIDATION.diameter_cm[0]:.2f}-{VALIDATION.diameter_cm[1]:.2f}-cm "
                   "projectiles): its load is the debris cloud's momentum, without the solid fragments whose craters "
                   "perforate walls that load only bulges")
#: What stands behind the verdict with the fragments of failed material (``[shield] failed_fragments =
#: "grady"``): an option no validation set has judged, since the gate that would let set 4 judge it fails
#: (validation/set-4-decision.md).
FRAGMENTS_VALIDATION = ("the fragments of failed material are an option no validation set has judged: their "
                        "sizes are not converged with the SPH spacing, and the gate on the verdict fails: at half "
                        "the SPH spacing a shot at 1.1 times the 4-km/s limit holds in 3 of 4 draws "
                        "(docs/vv/test-shots.md)")
#: The diameters and velocities of the validation shots.
VALIDATION_DIAMETER_CM = VALIDATION.diameter_cm
VALIDATION_VELOCITY_KM_S = VALIDATION.velocity_km_s


def wall_caution(case: WhippleCase, d: float, v: float) -> str:
    """Why the simulated verdict of ``case``'s shield against a projectile of diameter ``d`` (cm) at ``v``
    (km/s) should not be read without the equation's: what validation stands behind the case's wall load
    (:data:`WALL_VALIDATION`, or :data:`FRAGMENTS_VALIDATION` where the case loads the wall with the
    fragments of failed material), and whether the shot lies outside the validation shots
    (:data:`VALIDATION_DIAMETER_CM`, :data:`VALIDATION_VELOCITY_KM_S`)."""
    (d_lo, d_hi), (v_lo, v_hi) = VALIDATION_DIAMETER_CM, VALIDATION_VELOCITY_KM_S
    notes = [FRAGMENTS_VALIDATION if case.fragment_options.grady else WALL_VALIDATION]
    if not d_lo <= d <= d_hi:
        notes.append(f"d = {d:g} cm is outside the validation shots' {d_lo:g}-{d_hi:g} cm")
    if not v_lo <= v <= v_hi:
        notes.append(f"V = {v:g} km/s is outside the validation shots' {v_lo:g}-{v_hi:g} km/s")
    return "; ".join(notes) + ": read the equation's verdict beside it"


def draws_statement(draws: dict) -> str:
    """"perforation in k of N draws (P = k/N, 95 % interval lo–hi; seeds …)" of the draws stage's record."""
    low, high = draws["wilson_95"]
    seeds = np.array([d["seed"] for d in draws["draws"]])
    return (f"perforation in {draws['perforated']} of {draws['n_draws']} draw{'s' if draws['n_draws'] > 1 else ''} "
            f"of the fragments (P = {draws['probability']:.2f}, 95 % interval {low:.2f}–{high:.2f}; "
            f"seed{'s' if len(seeds) > 1 else ''} {', '.join(map(str, seeds))})")


def database_shot_record(case: WhippleCase) -> dict | None:
    """The summary's record of the test shot the case reproduces (its ``[test_shot]`` table, the shot's name and
    the outcome in words), or None where the case is no test shot."""
    test = case.test_shot
    return None if test is None else test.model_dump() | {"name": test.name, "outcome": test.outcome}


def outcome_statement(test: dict, simulated: str, equation: str) -> str:
    """The test's outcome, and whether the simulated verdict and the equation's agree with it (a detached spall
    is a failed wall, as in the test: :data:`FAILED_VERDICTS`)."""
    def agrees(failed: bool) -> str:
        return "agrees" if failed == test["perforated"] else "disagrees"

    return (f"{test['outcome']}: the simulated verdict {agrees(simulated in FAILED_VERDICTS)}, "
            f"the equation's {agrees(equation == 'perforation')}")


def wall_figures(wall: dict, ble: dict) -> dict:
    """The wall stage's verdict beside the equation's, and its headline measures."""
    m = wall["measures"]
    keys = ("crater_depth_ratio", "crater_depth_cm", "crater_resolved", "rear_bulge_cm", "peak_rear_bulge_cm",
            "peak_rear_bulge_time_us", "peak_rear_velocity_km_s", "failed_mass_g", "eroded_mass_g", "spall_mass_g",
            "failed_mass_by_cause_g", "failed_elements", "eroded_elements", "hourglass_to_internal", "end_time_us", "ended_by",
            "perforated_at_us", "kinetic_left_fraction", "steps", "permanent_rear_bulge_cm", "settled", "settle_steps",
            "settle_error", "unapplied_records", "impulse_unapplied", "impulse_deposited")
    return {"verdict": wall["verdict"], "criterion": wall["evidence"].get("criterion"),
            "agrees_with_equation": (wall["verdict"] != "no perforation") == (ble["verdict"] == "perforation"),
            "material_model": wall["model"].get("model"), "failure_criteria": wall["model"].get("failure_criteria"),
            "mesh": wall["mesh"],
            "energy": m.get("energy")} | {k: m[k] for k in keys if k in m}


def _fragments(figures: dict | None) -> str:
    """The report's line on the debris's solid fragments (the shield stage's record)."""
    if figures is None:  # a shield stage written before fragments were found
        return "–"
    if not figures["n_fragments"]:
        return "none: every particle of the debris failed or melted"
    origin = ("" if "mass_from_projectile_g" not in figures else   # a shield stage written before origins
              f" ({figures['mass_from_projectile_g']:.4g} g of it projectile material)")
    return (f"{figures['n_fragments']}, {figures['mass_g']:.4g} g{origin}; the largest {figures['largest_g']:.3g} g "
            f"({100 * figures['largest_over_projectile']:.2g} % of the projectile, "
            f"{figures['largest_diameter_cm']:.3g} cm, {figures['largest_particles']} particles, "
            f"{figures['largest_speed_km_s']:.3g} km/s)")


def _phases(shares: dict | None) -> str:
    """Solid / liquid / vapour shares by mass of a part of the debris (:func:`impactdyn.whipple._cloud.debris_state`)."""
    if shares is None:
        return "–"
    if shares["solid_mass_fraction"] is None:
        return "no debris"
    return (f"{100 * shares['solid_mass_fraction']:.3g} % / {100 * shares['liquid_mass_fraction']:.3g} % / "
            f"{100 * shares['vapour_mass_fraction']:.3g} % of {shares['mass_g']:.4g} g")


def _largest_piece(state: dict) -> str:
    """The report's line on the largest intact projectile piece of the debris (full model)."""
    if state.get("largest_projectile_piece_g") is None:
        return "none: no intact fragment of the debris is mostly projectile"
    return (f"{state['largest_projectile_piece_g']:.3g} g ({100 * state['largest_projectile_piece_over_projectile']:.3g} % "
            f"of the projectile), {state['largest_projectile_piece_diameter_cm']:.3g} cm, "
            f"{state['largest_projectile_piece_particles']} particles")


def _debris_state_rows(state: dict | None) -> list[tuple[str, str]]:
    """The report's "debris state at hand-off" rows (the shield stage's ``debris_state`` record; a shield
    stage written before it was recorded gives "–")."""
    if state is None:
        return [("debris state", "– (not recorded by this run's shield stage)")]
    return [("debris, solid / liquid / vapour by mass (half model)", _phases(state)),
            ("projectile's debris, solid / liquid / vapour", _phases(state["projectile"])),
            ("bumper's debris, solid / liquid / vapour", _phases(state["bumper"])),
            ("largest intact projectile piece (full model)", _largest_piece(state))]


_NO_DECKS = "none written (a lean run: --from decks --keep all writes them)"

#: What the report says of the files a run kept (``--keep``).
_KEPT = {"all": "The run kept every file (<code>--keep all</code>).",
         "lean": "A lean run (the default): the debris particles' states and VTU files, the hand-off grid's copy in "
                 "<code>debris/</code>, the decks and most frames of the wall series are not written; "
                 "<code>--keep all</code> writes them (<code>--from decks --keep all</code> writes the decks "
                 "into this folder)."}


def write_report(folder: FolderWriter, case: WhippleCase, keep: str = "all") -> dict:
    """Write ``summary.json``, ``plots/`` and ``report.html`` into the run folder; returns the record.
    ``keep``: how much of the output the run keeps (``--keep``, lean or all), recorded in the summary."""
    from impactdyn.shield import origin_masses, plot_fragment_masses, read_particles
    from impactdyn.whipple._case import projectile_mass, shield_problem
    from impactdyn.whipple._cloud import cloud_figures, projectile_particles, stage_fragments

    records = _records(folder)
    particles, history = read_particles(folder.path / "shield" / "particles.h5")
    cloud = cloud_figures(particles, case.bumper.thickness_cm)
    ble = ble_verdict(case)
    deposition = deposition_figures(records["debris"])
    plots = folder.sub("plots")
    _plot_cloud(plots.file("cloud_handoff.png"), particles, case, cloud)
    _plot_ble(plots.file("ballistic_limit.png"), case, ble)
    _plot_conservation(plots.file("conservation.png"), history)
    fragments = stage_fragments(folder.path)
    if len(fragments):  # with none, the report says so in words: empty axes would read as a failed plot
        projectile = projectile_particles(shield_problem(case)[0])   # the stage's particles, in its order
        plot_fragment_masses(plots.file("fragments.png"), fragments, projectile_mass_g=projectile_mass(case),
                             from_projectile_g=origin_masses(fragments, particles.mass, projectile),
                             title=f"Solid fragments of the debris at {case.shield.handoff_us:g} µs "
                                   f"(failure model: {case.shield.failure_model})")
    if records["draws"]["n_draws"] > 1:
        _plot_draws(plots.file("draws.png"), records["draws"])
    summary = {
        "title": case.title,
        "test_shot": database_shot_record(case),
        "shot": {"projectile": case.projectile.model_dump(), "bumper": case.bumper.model_dump(),
                 "wall": {k: v for k, v in case.wall.model_dump().items() if k in (
                     "material", "thickness_cm", "spacing_cm")} | {"yield_stress_ksi": case.wall_yield_ksi}},
        "ble": ble,
        "cloud": cloud,
        "deposition": deposition,
        "wall": wall_figures(records["wall"], ble) | {
            "caution": wall_caution(case, case.projectile.diameter_cm, case.projectile.velocity_km_s)},
        "draws": {k: v for k, v in records["draws"].items() if k not in ("stage", "settings", "wall_time_s")},
        "stages": {name: {k: v for k, v in r.items() if k not in ("stage", "settings")}
                   for name, r in records.items()},
        "timings_s": {name: r["wall_time_s"] for name, r in records.items()},
        "wall_time_s": float(sum(r["wall_time_s"] for r in records.values())),
        "units": "cm, g, µs, Mbar unless a key names its unit; momenta of the half model x >= 0",
        "keep": keep,
    }
    folder.write_json("summary.json", summary)
    folder.write_text("report.html", _html(folder, case, summary))
    return {"files": ["summary.json", "report.html", "plots/cloud_handoff.png", "plots/ballistic_limit.png",
                      "plots/conservation.png"] + (["plots/fragments.png"] if len(fragments) else [])
            + (["plots/draws.png"] if records["draws"]["n_draws"] > 1 else [])}


def _plot_cloud(path, particles, case: WhippleCase, cloud: dict) -> None:
    plt = pyplot()
    x, speed = particles.position, KM_S_PER_CM_US * np.linalg.norm(particles.velocity, axis=1)
    order = np.argsort(speed)
    fig, axes = plt.subplots(1, 2, figsize=(12, 5.5), constrained_layout=True)
    for ax, (a, b, label) in zip(axes, ((1, 2, "z (cm)"), (1, 0, "x (cm), symmetry plane at 0"))):
        sc = ax.scatter(x[order, a], x[order, b], c=speed[order], s=1.5, cmap="turbo", vmin=0.0)
        for y in (0.0, case.bumper.thickness_cm):
            ax.axvline(y, color="0.4", lw=0.6, ls="--")
        if "centre_of_mass_velocity_km_s" in cloud and b == 2:
            v = np.array(cloud["centre_of_mass_velocity_km_s"])
            reach = x[:, 1].max()
            ax.plot([0.0, reach], [0.0, reach * v[2] / v[1]], color="k", lw=1,
                    label=f"cloud axis, {_angle(cloud['axis_angle_from_normal_deg'])}° from the normal")
            ax.legend(loc="upper left", fontsize=8)
        ax.set_xlabel("y (cm), toward the wall")
        ax.set_ylabel(label)
        ax.set_aspect("equal", adjustable="datalim")
        ax.grid(alpha=0.3)
    axes[0].set_title(f"side view at hand-off, t = {particles.time:g} µs")
    axes[1].set_title("top view")
    fig.colorbar(sc, ax=axes, label="speed (km/s)", shrink=0.8)
    save_figure(fig, path, dpi=110)


def _plot_ble(path, case: WhippleCase, ble: dict) -> None:
    from impactdyn.ble import ballistic_limit_curve, nearby_shots, plot_ballistic_limit

    p = case.projectile
    shield = ble_shield(case)
    curve = ballistic_limit_curve(shield, None, p.obliquity_deg, ble["projectile_density_g_cm3"])
    w, b = case.wall, case.bumper
    plot_ballistic_limit([curve], path, shot=(p.velocity_km_s, p.diameter_cm, ble["verdict"] == "perforation"),
                         shots=nearby_shots(shield, p.obliquity_deg),
                         title=f"Whipple shield t_b = {b.thickness_cm:g} cm, t_w = {w.thickness_cm:g} cm, "
                               f"S = {w.spacing_cm:g} cm, σ = {case.wall_yield_ksi:g} ksi, θ = {p.obliquity_deg:g}°")


def _plot_conservation(path, history) -> None:
    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(11, 4), constrained_layout=True)
    t = history.time
    e0 = history.total_energy[0]
    ax = axes[0]
    ax.plot(t, history.kinetic / e0, label="kinetic")
    ax.plot(t, history.internal / e0, label="internal")
    ax.plot(t, history.total_energy / e0, "k", label="total")
    ax.set_xlabel("t (µs)")
    ax.set_ylabel("energy / initial energy")
    ax.legend()
    ax = axes[1]
    p0 = np.linalg.norm(history.momentum[0])
    for k, name in ((1, "y"), (2, "z")):
        ax.plot(t, (history.momentum[:, k] - history.momentum[0, k]) / p0, label=f"p_{name}")
    ax.set_xlabel("t (µs)")
    ax.set_ylabel("(p − p₀)/|p₀|")
    ax.legend()
    for ax in axes:
        ax.grid(alpha=0.3)
    fig.suptitle("SPH shield stage: conservation (half model; p_x is exchanged with the mirror half)")
    save_figure(fig, path, dpi=100)


def _plot_draws(path, draws: dict) -> None:
    """Each draw of the fragments' partition (the draws stage's record): the compact fragments' mass, the
    wall's failed mass and its peak rear bulge against the draw's seed, a cross where the wall failed."""
    plt = pyplot()
    fig, axes = plt.subplots(1, 3, figsize=(11, 3.4), constrained_layout=True)
    seeds = np.array([d["seed"] for d in draws["draws"]])
    failed = np.array([d["perforated"] for d in draws["draws"]])
    for ax, key, label in zip(axes, ("compact_mass_g", "failed_mass_g", "peak_rear_bulge_cm"),
                              ("compact fragments' mass (g)", "wall's failed mass (g)", "peak rear bulge (cm)")):
        value = np.array([d[key] for d in draws["draws"]])
        for which, style in ((failed, dict(marker="X", s=70, color="tab:red", label="perforation or detached spall")),
                             (~failed, dict(marker="o", s=50, color="tab:green", label="no perforation"))):
            if which.any():      # a legend entry only for an outcome some draw had
                ax.scatter(seeds[which], value[which], **style)
        ax.set(xlabel="partition seed", ylabel=label, xticks=seeds.tolist())
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.suptitle(f"The fragments' draws: {draws_statement(draws)}", fontsize=9)
    save_figure(fig, path, dpi=100)


def _img(path) -> str:
    if not path.is_file():
        return f"<p><em>{html.escape(path.name)} was not drawn (plots switched off).</em></p>"
    data = base64.b64encode(path.read_bytes()).decode()
    return f'<img alt="{html.escape(path.name)}" src="data:image/png;base64,{data}">'


def _fragments_plot(path, figures: dict | None) -> str:
    """The fragment masses' plot, or, where the debris holds no solid fragment, a line saying so."""
    if figures is not None and not figures["n_fragments"]:
        return "<p><em>No solid fragments in the debris at hand-off: nothing to plot.</em></p>"
    return _img(path)


def _rows(pairs) -> str:
    return "\n".join(f"<tr><th>{html.escape(k)}</th><td>{html.escape(v)}</td></tr>" for k, v in pairs)


#: Below this share of its ledger's total a momentum is the round-off of the sums, not a measure (the ledger
#: closes to ~1e-12 of its total, float64 sums over up to 10⁶ records).
LEDGER_ROUND_OFF = 1e-9
#: The cloud axis's angle is read to 0.05°: below it the half model's mirror makes it zero to round-off.
ANGLE_RESOLUTION_DEG = 0.05


def _fmt(v, unit="", digits=4, resolution=0.0) -> str:
    """``v`` to ``digits`` significant figures, for people: a value within ``resolution`` of zero (what the
    measure cannot resolve, round-off) reads 0, never −0 or 1e-17."""
    if v is None:
        return "–"
    v = 0.0 if abs(v) <= resolution else v + 0.0     # + 0.0: −0.0 reads 0
    return f"{v:.{digits}g}" + (f" {unit}" if unit else "")


def _angle(degrees: float | None) -> str:
    """An angle to 3 figures, 0 within :data:`ANGLE_RESOLUTION_DEG`."""
    return _fmt(degrees, digits=3, resolution=ANGLE_RESOLUTION_DEG)


def _error(v: float) -> str:
    """A relative conservation error: 0 when exact, else to two figures (1.2e-07)."""
    return "0" if v == 0.0 else f"{v:.1e}"


def _mesh(mesh: dict) -> str:
    """The wall mesh in words: elements along x, y (through the thickness) and z, their number, its kind."""
    counts = " × ".join(str(n) for n in mesh["elements"])
    total = mesh.get("n_elements")
    return counts + (f" = {total:,} elements" if total else " elements") + (f", {mesh['kind']}" if mesh.get("kind") else "")


def verdict_record(case: WhippleCase) -> str:
    """What stands behind the simulated verdict of ``case``, in words, from the package's record: the default
    wall's validation sets (:func:`impactdyn.whipple.limit_statement`), or, where the case loads the wall with
    the fragments of failed material, that no validation set has judged them (:data:`FRAGMENTS_VALIDATION`)."""
    if case.fragment_options.grady:
        return (f"The simulated wall is loaded by the debris cloud and its solid fragments: "
                f"{FRAGMENTS_VALIDATION}; weigh its verdict, either way, against the equation's.")
    return limit_statement(VALIDATION)


def _top(wall: dict, ble: dict, case: WhippleCase) -> str:
    """The report's first lines: a banner when the simulated verdict and the equation's differ, with what stands
    behind the simulated one for this case (:func:`verdict_record`); the caution always."""
    caution = (f'<p class="caution"><strong>Caution:</strong> {html.escape(wall["caution"])}.</p>'
               if wall.get("caution") else "")
    if wall["agrees_with_equation"]:
        return caution
    return (f'<div class="banner" role="alert"><p><strong>The simulation and the equation disagree:</strong> '
            f'simulated wall: {html.escape(wall["verdict"])}; {html.escape(ble["equation"])}: '
            f'{html.escape(ble["verdict"])}.</p><p>{html.escape(verdict_record(case))}</p></div>\n' + caution)


def _bulge(wall: dict) -> str:
    """The rear bulge at the end of the run, and its peak with the time it came."""
    if wall.get("peak_rear_bulge_cm") is None:
        return _fmt(wall.get("rear_bulge_cm"), "cm")
    return (f"{_fmt(wall.get('rear_bulge_cm'), 'cm')}; {_fmt(wall['peak_rear_bulge_cm'], 'cm')} "
            f"({wall['peak_rear_bulge_time_us']:.4g} µs)")


def wall_permanent_bulge(wall: dict) -> str:
    """The permanent bulge of a settled wall, or how to get it."""
    if wall.get("settle_error"):
        return f"not measured: {wall['settle_error']} while the wall was brought to rest"
    if wall.get("permanent_rear_bulge_cm") is None:
        return "not computed ([wall_solver] settle = true)"
    text = _fmt(wall["permanent_rear_bulge_cm"], "cm") + f" after {wall['settle_steps']} settling steps"
    return text if wall["settled"] else text + ", NOT at rest (max_settle_steps reached)"


def wall_ending(wall: dict) -> str:
    """How the wall run ended, in words, with the warning that a run cut off at the ceiling needs
    (``wall`` the summary's wall record; :data:`impactdyn.wall.ENDINGS`)."""
    how = wall.get("ended_by")
    if how is None:
        return "–"
    text = {"decay": "the wall's kinetic energy decayed", "end_time": "the end time asked for",
            "ceiling": "the max_time_us ceiling",
            "perforated": "a through-thickness path of failed material held after the last record so far"}[how]
    text += f" at {wall['end_time_us']:.4g} µs, {wall['kinetic_left_fraction']:.0%} of its peak kinetic energy left"
    if how == "ceiling":
        text += ("; the wall is not at rest: the failed mass and the verdict stand if the damage has stopped "
                 "growing, the bulge is that moment's, not a permanent set")
    if how == "perforated":
        text += (f"; perforated from {wall['perforated_at_us']:.4g} µs on (failure is for good, so the verdict "
                 "cannot change): the hole, the failed mass and the bulge are those of the end of the run")
    if wall.get("unapplied_records"):
        share = np.linalg.norm(wall["impulse_unapplied"]) / np.linalg.norm(wall["impulse_deposited"])
        text += (f"; {wall['unapplied_records']} record{'s' if wall['unapplied_records'] > 1 else ''} arriving "
                 f"later ({share:.2%} of the deposited momentum) not applied")
    return text


def _outcome_rows(test: dict | None, simulated: str, equation: str) -> list[tuple[str, str]]:
    """The verdict table's row of the test's outcome (:func:`outcome_statement`); none where the case is no
    test shot."""
    if test is None:
        return []
    return [(f"test shot {test['name']}", outcome_statement(test, simulated, equation))]


def _crater(wall: dict) -> str:
    """The crater depth over the wall's thickness, and whether the mesh resolves it (one element layer deep)."""
    text = _fmt(wall.get("crater_depth_ratio"))
    if wall.get("crater_resolved") is False:
        text += " (less than the front element layer: not resolved by the mesh)"
    return text


def _mesh_peak(dep: dict) -> str:
    """The peak areal momentum on the wall mesh's own face cells, and their size."""
    return f"{_fmt(dep['peak_areal_momentum_mesh_N_s_cm2'], AREAL_MOMENTUM_UNIT)} ({_fmt(dep['mesh_face_cell_cm'], 'cm', 2)} cells)"


def _ledger(ledger: dict) -> str:
    """The normal component of the momentum ledger (:func:`momentum_ledger`), full model, N·s and shares."""
    total = ledger["in"][1]
    noise = LEDGER_ROUND_OFF * abs(total)
    parts = [0.0 if abs(v) <= noise else v for v in
             (ledger[k][1] for k in ("deposited", "outside_window", "off_wall", "not_reaching", "failed"))]
    share = (lambda v: f" ({_fmt(100.0 * v / total, digits=3, resolution=0.05)} %)") if total else (lambda v: "")
    added = ledger["added_at_wall"][1]
    return (f"{_fmt(2.0 * N_S_PER_G_CM_US * total, 'N·s')} in: "
            + ", ".join(_fmt(2.0 * N_S_PER_G_CM_US * v, "N·s") + share(v) for v in parts)
            + (f"; the wall took {_fmt(2.0 * N_S_PER_G_CM_US * added, 'N·s')} more from the crater ejecta "
               "(wall.momentum_transfer = \"cratering\")" if added else ""))


def _criteria(names: list[str] | None) -> str:
    """The criteria that can fail the wall, in words ("none" says the wall cannot fail)."""
    if names is None:
        return "–"
    return ", ".join(n.replace("_", " ") for n in names) if names else "none: no element can fail"


def _by_cause(masses: dict | None) -> str:
    """The failed mass by criterion, the criteria that failed something only ("none" if nothing failed)."""
    if masses is None:
        return "–"
    hit = {k: v for k, v in masses.items() if v > 0.0}
    return ", ".join(f"{k.replace('_', ' ')} {v:.4g} g" for k, v in hit.items()) if hit else "none"


def _html(folder: FolderWriter, case: WhippleCase, s: dict) -> str:
    p, ble, cloud, dep, st = case.projectile, s["ble"], s["cloud"], s["deposition"], s["stages"]
    shot = _rows([
        ("projectile", f"{p.material} sphere, d = {p.diameter_cm:g} cm, {p.velocity_km_s:g} km/s, "
                       f"{p.obliquity_deg:g}° from the normal"),
        ("bumper", f"{case.bumper.material}, {case.bumper.thickness_cm:g} cm"),
        ("rear wall", f"{case.wall.material}, {case.wall.thickness_cm:g} cm, {case.wall.spacing_cm:g} cm behind "
                      f"the bumper, σ = {case.wall_yield_ksi:g} ksi"),
    ])
    verdict = _rows([
        ("regime", ble["regime"]),
        ("equation", ble["equation"]),
        ("critical diameter d_c", _fmt(ble["critical_diameter_cm"], "cm") + (f" ({ble['note']})" if ble["note"] else "")),
        ("verdict (d vs d_c)", f"{ble['verdict']} (d = {p.diameter_cm:g} cm)"),
    ])
    cloud_rows = _rows([
        ("cloud centre-of-mass velocity", _fmt(cloud.get("centre_of_mass_speed_km_s"), "km/s")
         + f" at {_angle(cloud.get('axis_angle_from_normal_deg'))}° from the normal"),
        ("cloud leading-edge velocity", _fmt(cloud.get("leading_edge_velocity_km_s"), "km/s")),
        ("cone half-angle (95 % of momentum)", _fmt(cloud.get("cone_half_angle_deg"), "°")),
        ("debris mass (half model)", _fmt(cloud.get("debris_mass_g"), "g")),
        ("solid fragments in the debris (full model)", _fragments(st["shield"].get("fragments"))),
    ])
    state_rows = _rows(_debris_state_rows(st["shield"].get("debris_state")))
    loading_rows = _rows([
        ("peak areal momentum on the wall: on the case grid's cells (the load); on the wall mesh's face cells",
         _fmt(dep["peak_areal_momentum_N_s_cm2"], AREAL_MOMENTUM_UNIT) + "; " + _mesh_peak(dep)),
        ("the debris's normal momentum (full model): on the wall, outside the arrival window (compact fragments: "
         "the wall run), off the face grid, never reaching the wall, failed flights",
         _ledger(dep["momentum_ledger_g_cm_us"])),
        ("impulse on the wall, normal (full model)", _fmt(dep["impulse_on_wall_normal_N_s_full_model"], "N·s")),
        ("arrival times (first, median, last)", "–" if not dep["arrival_time_us"] else
         ", ".join(_fmt(dep["arrival_time_us"][k]) for k in ("first", "median", "last")) + " µs after hand-off"),
    ])
    wall = s["wall"]
    wall_rows = _rows([
        ("simulated verdict", f"{wall['verdict']} ({wall['criterion']})"),
        ("perforation over the partition's draws", draws_statement(s["draws"])),
        ("equation's verdict", f"{ble['verdict']} ({ble['equation']})"),
        *_outcome_rows(s.get("test_shot"), wall["verdict"], ble["verdict"]),
        ("caution", wall["caution"]),
        ("crater depth / wall thickness", _crater(wall)),
        ("rear-face bulge at the end; its peak (when)", _bulge(wall)),
        ("run ended by", wall_ending(wall)),
        ("rear-face permanent bulge (the wall brought to rest)", wall_permanent_bulge(wall)),
        ("peak rear-face velocity", _fmt(wall.get("peak_rear_velocity_km_s"), "km/s")),
        ("failed / eroded / spalled mass", " / ".join(_fmt(wall.get(k, 0.0), "g") for k in (
            "failed_mass_g", "eroded_mass_g", "spall_mass_g"))),
        ("failure criteria of the wall model", _criteria(wall.get("failure_criteria"))),
        ("failed mass by criterion", _by_cause(wall.get("failed_mass_by_cause_g"))),
        ("hourglass / internal energy", _fmt(wall.get("hourglass_to_internal"))),
        ("mesh (elements), material model", f"{_mesh(wall['mesh'])}, {wall['material_model']}"),
    ])
    stages = _rows([
        ("shield (SPH)", f"{st['shield']['n_particles']} particles, {st['shield']['steps']} steps to "
                         f"{st['shield']['t_handoff_us']:g} µs; momentum error {_error(st['shield']['momentum_error_rel'])}, "
                         f"energy error {_error(st['shield']['energy_error_rel'])}; "
                         f"{st['shield']['wall_time_s']:.1f} s"),
        ("binning", f"{st['binning']['n_cells_with_mass']} cells with mass of {st['binning']['n_cells']}, "
                    f"mass error {_error(st['binning']['mass_error_rel'])}; {st['binning']['wall_time_s']:.1f} s"),
        ("debris (DC3D)", f"{st['debris']['n_particles']} particles, {st['debris']['n_arrived']} arrived, "
                          f"{st['debris']['integrator']['n_failed']} failed; {st['debris']['wall_time_s']:.1f} s"),
        ("wall (FE)", f"{st['wall']['measures'].get('steps', 0)} steps to {_fmt(st['wall']['measures'].get('end_time_us'), 'µs')}; "
                      f"{st['wall']['wall_time_s']:.1f} s"),
        ("decks", (", ".join(st["decks"]["files"]) or _NO_DECKS) + f"; {st['decks']['wall_time_s']:.1f} s"),
        ("total", f"{s['wall_time_s']:.1f} s"),
    ])
    plots = folder.path / "plots"
    title = html.escape(case.title or "Whipple shield impact")
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>{title}</title>
<style>body{{font-family:sans-serif;max-width:1150px;margin:2em auto;color:#222}}
table{{border-collapse:collapse;margin:0.5em 0 1.5em}}th,td{{border:1px solid #ccc;padding:4px 10px;text-align:left}}
th{{background:#f4f4f4;font-weight:normal}}img{{max-width:100%}}
.banner{{border:2px solid #b00020;background:#fdecee;padding:0.2em 1em;margin:1em 0}}
.caution{{border-left:4px solid #c77700;background:#fff6e5;padding:0.5em 1em}}</style></head><body>
{_top(wall, ble, case)}
<h1>{title}</h1>
<p>impactdyn Whipple pipeline: SPH shield impact → debris cloud (DC3D) → momentum on the rear wall → the wall's
finite-element response and verdict → wall decks.
Half model (x ≥ 0); units as labelled.</p>
<h2>Shot</h2><table>{shot}</table>
<h2>Ballistic limit (NASA JSC equation)</h2><table>{verdict}</table>
{_img(plots / "ballistic_limit.png")}
<h2>Simulated debris cloud and wall loading</h2><table><tbody>{cloud_rows}</tbody>
<tbody><tr><th colspan="2"><strong>debris state at hand-off</strong> (released to zero pressure)</th></tr>
{state_rows}</tbody>
<tbody><tr><th colspan="2"><strong>wall loading</strong></th></tr>
{loading_rows}</tbody></table>
<h3>Cloud at hand-off</h3>{_img(plots / "cloud_handoff.png")}
<h3>Solid fragments of the debris</h3>{_fragments_plot(plots / "fragments.png", st["shield"].get("fragments"))}
<h3>Areal momentum density on the wall</h3>{_img(folder.path / "debris" / "plots" / "areal_density.png")}
<h2>Wall response</h2><table>{wall_rows}</table>
{_img(folder.path / "wall" / "plots" / "wall_front.png")}
{_img(folder.path / "wall" / "plots" / "wall_rear.png")}
{_img(folder.path / "wall" / "plots" / "wall_history.png")}
{_img(plots / "draws.png") if s["draws"]["n_draws"] > 1 else ""}
<h2>Stages</h2><table>{stages}</table>
{_img(plots / "conservation.png")}
<h2>Files</h2><p><code>summary.json</code> (all numbers), <code>case.toml</code> (every setting used),
<code>shield/particles.h5</code>, <code>binning/handoff_grid.h5</code>, <code>debris/</code> (an
<code>impactdyn debris run</code> folder), <code>wall/</code> (the wall's measures and ParaView time series),
<code>decks/</code> (LS-DYNA and DYNA3D wall decks).  {_KEPT[s.get("keep", "all")]}</p>
<script type="application/json" id="summary">{html.escape(json.dumps(s, default=str))}</script>
</body></html>
"""
