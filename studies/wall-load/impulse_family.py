"""The impulse-only family of validation/impulse-family.md: a cloud with no solid fragment, scaled in mass,
on three walls, against Christiansen 1993 eq. 14.

The cloud is Table 2's 10a as the example runs it, kept whole (``--keep all``: the arrival points are
needed by the ``fine-load`` variant)::

    impactdyn whipple run examples/whipple/table2_10a.toml -o runs/table2_10a --keep all
    python studies/wall-load/impulse_family.py runs/table2_10a --out impulse_family.jsonl
    python studies/wall-load/impulse_family.py runs/table2_10a --out impulse_family.jsonl --walls A --variant fine-load
    python studies/wall-load/impulse_family.py runs/table2_10a --out impulse_family.jsonl --walls A --variant spall-cutoff
    python studies/wall-load/impulse_family.py runs/table2_10a --out impulse_family.jsonl --variant cratering
    python studies/wall-load/impulse_family.py runs/table2_10a --out impulse_family.jsonl --count
    python studies/wall-load/impulse_family.py runs/table2_10a --out impulse_family.jsonl --plot impulse_family.png

Every wall run is appended to ``--out`` (JSON lines) as it finishes; a run already there is read back,
not run again, so an interrupted family resumes.  ``--count`` prints the cloud's momentum ledger
(what reached the wall, outside the window, off the face grid, never reaching the wall plane).
"""

from __future__ import annotations

import argparse
import json
import math
import time
from pathlib import Path

import numpy as np

from impactdyn.debris import cratering_momentum, deposit, read_deposition
from impactdyn.debris._particle import P_SLICE
from impactdyn.io import open_hdf5
from impactdyn.materials import get_material
from impactdyn.wall import run_wall, wall_model
from impactdyn.wallgrid import WallDeposition, WallGrid
from impactdyn.whipple import load_whipple_case
from impactdyn.whipple._case import projectile_mass

#: The walls of the family (validation/impulse-family.md): model, thickness (cm), yield σ (ksi).
WALLS = {"A": ("al6061-t6", 0.3175, 40.0), "B": ("al6061-t6", 0.16, 40.0), "C": ("al2024-t4", 0.635, 50.0)}
FAILED = ("perforation", "detached spall")
BRACKET = 1.10
BAND = 1.5          # k_c / k_14 within [1/BAND, BAND]: consistent with eq. 14 (validation/impulse-family.md)
FINE = 4            # in-plane refinement of the face grid for the ``fine-load`` variant
#: The variants' markers, colours and offsets along the figure's x axis (cm of the wall term, to keep them apart).
VARIANT_STYLE = {"base": ("o", "C0", 0.0), "fine-load": ("s", "C1", -0.04), "spall-cutoff": ("^", "C2", 0.04),
                 "cratering": ("D", "C3", 0.08)}


def projectile(case) -> tuple[float, float]:
    """(M_p g, V_n km/s) of the case's projectile (V_n = V cos θ)."""
    p = case.projectile
    return projectile_mass(case), p.velocity_km_s * math.cos(math.radians(p.obliquity_deg))


def areal_density(wall: str) -> float:
    """m_w (σ/40)^½ of the wall, g/cm²: eq. 14's wall term."""
    model, t, sigma = WALLS[wall]
    return get_material(model).rho0 * t * math.sqrt(sigma / 40.0)


def k_eq14(wall: str, case) -> float:
    """Eq. 14's failing mass over M_p for the wall (validation/impulse-family.md)."""
    mass, vn = projectile(case)
    return areal_density(wall) * case.wall.spacing_cm ** 2 / (41.7 * mass * vn)


def arrivals(run: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The arrived particles of ``debris.h5`` (integration code 0): their deposition points (A, 5, 3), momenta
    (A, 3), masses (A,) and arrival times (A,), as the debris stage deposited them."""
    with open_hdf5(run / "debris" / "debris.h5") as f:
        index, code = f["arrival/index"][()], f["arrival/code"][()]
        points, states = f["arrival/points"][()], f["arrival/states"][()]
        t_arrival, mass = f["particles/t_arrival"][()], f["particles/mass"][()]
    ok = code == 0
    return points[ok], states[ok][:, P_SLICE], mass[index][ok], t_arrival[index][ok]


def fine_deposition(run: Path, wall: WallGrid) -> tuple[WallGrid, WallDeposition]:
    """The arrival points of ``debris.h5`` deposited on the face grid refined ``FINE`` times in plane."""
    points, momentum, _, time_us = arrivals(run)
    fine = WallGrid(x=np.linspace(wall.x[0], wall.x[-1], FINE * (wall.x.size - 1) + 1), y=wall.y,
                    z=np.linspace(wall.z[0], wall.z[-1], FINE * (wall.z.size - 1) + 1))
    return fine, deposit(points, momentum, time_us, fine)[0]


def cratering_deposition(run: Path, wall: WallGrid) -> WallDeposition:
    """The arrival points of ``debris.h5`` deposited on the case grid with each particle's normal momentum times
    the cratering β(V_n) (:func:`impactdyn.debris.cratering_momentum`), as ``wall.momentum_transfer =
    "cratering"`` deposits it."""
    points, momentum, mass, time_us = arrivals(run)
    return deposit(points, cratering_momentum(momentum, mass), time_us, wall)[0]


def one_run(run: Path, case, wall_name: str, k: float, variant: str) -> dict:
    model, t, _ = WALLS[wall_name]
    grid, dep, _ = read_deposition(run / "debris" / "debris.h5")
    options = case.wall_options
    if variant == "fine-load":
        grid, dep = fine_deposition(run, grid)
        options = options.model_copy(update={"max_element_size_cm": 0.16})
    if variant == "cratering":
        dep = cratering_deposition(run, grid)
    if variant == "spall-cutoff":     # the spall law at its limit: failure at once at p < −p_spall
        model = wall_model(options.material_model, model, spall_law="cutoff")
    wall = WallGrid(x=grid.x, y=grid.y[0] + np.linspace(0.0, t, grid.y.size), z=grid.z)
    scaled = WallDeposition(element=dep.element, time=dep.time, impulse=k * dep.impulse)
    start = time.perf_counter()
    result = run_wall(wall, scaled, model, options)
    m = result.measures
    return {"wall": wall_name, "variant": variant, "k": k, "verdict": result.verdict,
            "failed": result.verdict in FAILED, "ended_by": m.get("ended_by"),
            "rear_bulge_cm": m.get("rear_bulge_cm"), "failed_mass_g": m.get("failed_mass_g"),
            "failed_mass_by_cause_g": m.get("failed_mass_by_cause_g"), "spall_mass_g": m.get("spall_mass_g"),
            "mesh": result.mesh.describe()["elements"], "seconds": time.perf_counter() - start}


def search(run: Path, case, wall_name: str, variant: str, out: Path) -> dict:
    """k_c of one wall: from k_14 by doubling or halving, then geometric bisection to ``BRACKET``."""
    done = {(r["wall"], r["variant"], r["k"]): r for r in _read(out)}

    def verdict(k: float) -> bool:
        key = (wall_name, variant, k)
        if key not in done:
            done[key] = one_run(run, case, wall_name, k, variant)
            with out.open("a") as f:
                f.write(json.dumps(done[key]) + "\n")
            r = done[key]
            print(f"{wall_name} {variant} k={k:.4g}: {r['verdict']} ({r['ended_by']}, bulge "
                  f"{r['rear_bulge_cm']:.3g} cm, {r['seconds']:.0f} s)", flush=True)
        return done[key]["failed"]

    k = round(k_eq14(wall_name, case), 4)
    holds, fails = (None, k) if verdict(k) else (k, None)
    while holds is None:
        k = round(fails / 2.0, 4)
        holds, fails = (holds, k) if verdict(k) else (k, fails)
    while fails is None:
        k = round(holds * 2.0, 4)
        holds, fails = (holds, k) if verdict(k) else (k, fails)
    while fails / holds > BRACKET:
        k = round(math.sqrt(holds * fails), 4)
        holds, fails = (holds, k) if verdict(k) else (k, fails)
    k_c = math.sqrt(holds * fails)
    k14 = k_eq14(wall_name, case)
    return {"wall": wall_name, "variant": variant, "k_holds": holds, "k_fails": fails, "k_c": k_c,
            "k_14": k14, "ratio": k_c / k14}


def count(run: Path) -> dict:
    """The cloud's momentum (g·cm/µs, half model) from hand-off to the wall, by where it went."""
    with open_hdf5(run / "debris" / "debris.h5") as f:
        mass, states, t_arr = f["particles/mass"][()], f["particles/states"][()], f["particles/t_arrival"][()]
        index, code, on = f["arrival/index"][()], f["arrival/code"][()], f["arrival/on_wall"][()]
        deposited = f["deposition/impulse"][()].sum(axis=0)
    p = states[:, P_SLICE]
    compact = json.loads((run / "debris" / "summary.json").read_text()).get("compact_fragments")
    window = np.zeros(len(mass), dtype=bool)
    window[index] = True
    reaches = np.isfinite(t_arr)
    ok = code == 0
    on_share = on[ok].mean(axis=1)
    rows = {"in": p.sum(axis=0), "deposited": deposited,
            "off_grid": (p[index][ok] * (1.0 - on_share)[:, None]).sum(axis=0),
            "failed": p[index][~ok].sum(axis=0),
            "outside_window": p[reaches & ~window].sum(axis=0), "never_reaching": p[~reaches].sum(axis=0)}
    late = reaches & ~window
    return {k: v.tolist() for k, v in rows.items()} | {
        "mass_in_g": float(mass.sum()), "mass_outside_window_g": float(mass[late].sum()),
        "mass_never_reaching_g": float(mass[~reaches].sum()),
        "late_arrivals_us": [float(np.min(t_arr[late])), float(np.max(t_arr[late]))] if late.any() else None,
        "compact_fragments": compact}


def jsc_mass(wall: str, case) -> float:
    """The projectile mass (g) of the JSC Whipple equation's d_c for the case's shot on the wall."""
    from impactdyn.ble import WhippleShield, jsc_verdict

    _, t, sigma = WALLS[wall]
    p = case.projectile
    shield = WhippleShield(bumper_thickness_cm=case.bumper.thickness_cm, wall_thickness_cm=t,
                           spacing_cm=case.wall.spacing_cm, wall_yield_ksi=sigma)
    d_c = jsc_verdict(shield, p.diameter_cm, p.velocity_km_s, p.obliquity_deg)["critical_diameter_cm"]
    return get_material(p.material).rho0 * math.pi / 6.0 * d_c ** 3


def plot(out: Path, case, figure: Path) -> None:
    """The failing mass against the wall's areal density: eq. 14's line, the JSC Whipple equation's
    points, and the family's brackets (the largest k held and the smallest failed, times M_p)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    mass, vn = projectile(case)
    s = case.wall.spacing_cm
    rows = _read(out)
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    x = np.linspace(0.2, 2.2, 50)
    ax.plot(x, x * s ** 2 / (41.7 * vn), "k-", label="Christiansen 1993 eq. 14")
    ax.fill_between(x, x * s ** 2 / (41.7 * vn) / BAND, x * s ** 2 / (41.7 * vn) * BAND, color="0.9",
                    label=f"eq. 14 × or ÷ {BAND:g} (consistent)")
    for variant, (marker, colour, shift) in VARIANT_STYLE.items():
        for name in WALLS:
            runs = [r for r in rows if r["wall"] == name and r["variant"] == variant]
            held = [r["k"] for r in runs if not r["failed"]]
            failed = [r["k"] for r in runs if r["failed"]]
            if not (held and failed):
                continue
            xw = areal_density(name) + shift
            lo, hi = max(held) * mass, min(failed) * mass
            ax.errorbar([xw], [math.sqrt(lo * hi)], yerr=[[math.sqrt(lo * hi) - lo], [hi - math.sqrt(lo * hi)]],
                        fmt=marker, color=colour, capsize=3,
                        label=f"simulated ({variant})" if name == "A" else None)
    for name in WALLS:
        ax.plot([areal_density(name)], [jsc_mass(name, case)], "kx",
                label="JSC Whipple equation" if name == "A" else None)
        ax.annotate(name, (areal_density(name), 0.0), textcoords="offset points", xytext=(0, 4),
                    ha="center")
    ax.set_xlabel("wall areal density × (σ/40 ksi)^½  (g/cm²)")
    ax.set_ylabel("projectile mass that fails the wall (g)")
    ax.set_title(f"10a's cloud scaled in mass, S = {s:g} cm, V_n = {vn:.2f} km/s")
    ax.set_xlim(0.0, 2.2)
    ax.set_ylim(0.0, None)
    ax.legend(loc="upper left", fontsize=8)
    fig.tight_layout()
    fig.savefig(figure, dpi=120)


def _read(out: Path) -> list[dict]:
    return [json.loads(line) for line in out.read_text().splitlines() if line.strip()] if out.exists() else []


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run", type=Path, help="the 10a run folder (--keep all)")
    ap.add_argument("--out", type=Path, default=Path("impulse_family.jsonl"))
    ap.add_argument("--walls", default="A,B,C")
    ap.add_argument("--variant", choices=tuple(VARIANT_STYLE), default="base")
    ap.add_argument("--count", action="store_true", help="print the momentum ledger and stop")
    ap.add_argument("--plot", type=Path, help="draw the runs in --out against eq. 14 into this PNG and stop")
    args = ap.parse_args()
    if args.count:
        print(json.dumps(count(args.run), indent=1))
        return
    case = load_whipple_case(args.run / "case.toml")
    if args.plot:
        plot(args.out, case, args.plot)
        return
    for name in args.walls.split(","):
        print(json.dumps(search(args.run, case, name, args.variant, args.out)), flush=True)


if __name__ == "__main__":
    main()
