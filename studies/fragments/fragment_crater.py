"""Would the wall stage crater and perforate under one compact fragment? (issue 11, an experiment)

The validation sets found the simulated wall non-conservative on small projectiles, and the
evidence points at the debris model, which carries no compact fragments (BENCHMARKS.md, "the
2024 walls had no ductile damage").  Before a fragment model is built, this asks the wall stage
the other half of the question: given one solid aluminium sphere of diameter d arriving normally
at speed V — as deposition records, the only way the stage is loaded — does the wall's crater
depth agree with the Cour-Palais single-wall equation (S1) of :mod:`impactdyn.ble`, and does a
thin wall perforate where (S1) says it does (t < 1.8 p_∞)?

The sphere is laid on a uniform face grid of cell ``h`` (half model, centre on the symmetry plane
x = 0) by :func:`impactdyn.wallgrid.sphere_deposition`: each face cell takes the momentum of the
sphere's columns over it at a stopped rod's rate ρ_p V² over L/V.  The wall: the case's
Johnson–Cook model (Mie–Grüneisen EOS, JC damage, spall), cells of ``h`` through the
thickness as in the plane (``--mesh-rule``: the wall stage's default graded mesh of that face grid,
whose core element the mesh rule sets, :func:`impactdyn.wall.core_element_size`), clamped edges at ±``half_width``, the load spread over a depth δ =
``depth_per_diameter`` × d (the default load depth, half the first layer, moves the front nodes
by more than a layer in a step under one fragment at a resolved mesh: the solver stops with its
non-positive-volume error).  Run to ``end`` µs after the last arrival.

    python studies/fragments/fragment_crater.py [--diameter 0.06] [--velocity 6.0] [--cell 0.01]
        [--thickness 0.16 0.6] [--material al2024-t4] [--half-width 0.4] [--end 6]
        [--depth-per-diameter 1] [--bisect LO HI [--tolerance 0.0025]] [--sph SPACING] [--mesh-rule]

Prints, per wall thickness: (S1)'s p_∞ and its verdict for that thickness, the wall stage's
verdict, crater depth (its damage depth: the damaged material connected to the front face,
cm and / p_∞), eroded mass, rear bulge, the energy the load brought against the sphere's kinetic
energy, the impulse against the sphere's momentum, the failed mass by criterion and the wall
time.  A thickness of several p_∞ stands for the semi-infinite target of (S1).  With
``--bisect`` it prints instead, per thickness, the diameters between which the verdict turns to
perforation, beside (S1)'s critical diameter.  ``--sph SPACING`` asks an independent solver the
same question instead: the shield stage's SPH strikes a plate of the wall's material and thickness
(radius ``half_width``) with the sphere itself (:func:`sph_run`), so the wall's response comes from
the full impact rather than from the deposited momentum.  A check of the load model, not a
product option: nothing in the wall stage changes.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from impactdyn import ble, shield, wall
from impactdyn.materials import get_material
from impactdyn.wallgrid import WallGrid, sphere_deposition

from _particles import linked_clusters, projectile_count

PROJECTILE_DENSITY = 2.7
#: The sphere's material in the SPH cross-check (ρ₀ 2.703).
SPH_PROJECTILE = "al6061-t6"
#: Outward speed (km/s) of plate material beyond its rear face counted as ejected in the SPH.
SPH_EJECTA_SPEED = 0.2


def crater_run(thickness: float, diameter: float, args: argparse.Namespace) -> dict:
    h = args.cell
    n_plane = int(round(args.half_width / h))
    n_thick = max(4, int(round(thickness / h)))
    grid = WallGrid.uniform((0.0, n_plane * h), (0.0, thickness), (-n_plane * h, n_plane * h),
                            (n_plane + 1, n_thick + 1, 2 * n_plane + 1))
    v = args.velocity * 0.1
    deposition = sphere_deposition(grid, diameter, v, PROJECTILE_DENSITY, t0_us=1.0)
    options = wall.WallOptions(material_model="johnson_cook", supports="clamped",
                               mesh="graded" if args.mesh_rule else "report",
                               end_time_us=float(deposition.time.max()) + args.end,
                               history_interval_us=0.05,
                               deposition_depth_cm=min(args.depth_per_diameter * diameter, thickness))
    t_wall = time.perf_counter()
    result = wall.run_wall(grid, deposition, args.material, options)
    elapsed = time.perf_counter() - t_wall
    p_inf = float(ble.penetration_depth(single_wall(thickness, args), diameter, args.velocity, 0.0,
                                        PROJECTILE_DENSITY))
    m = result.measures
    return {
        "layers": result.mesh.shape[1], "elements": result.mesh.n_elements, "p_inf": p_inf,
        "equation": "P" if thickness < 1.8 * p_inf else ("DS" if thickness < 2.2 * p_inf else "NP"),
        "verdict": result.verdict, "crater_cm": m["crater_depth_cm"], "eroded_g": m["eroded_mass_g"],
        "bulge": m["rear_bulge_end_cm"], "load_work": m["energy"]["load_work"],
        "impulse": float(deposition.impulse[:, 1].sum()), "seconds": elapsed,
        "causes": {k: v for k, v in m["failed_mass_by_cause_g"].items() if v > 0},
    }


def sph_run(thickness: float, diameter: float, args: argparse.Namespace) -> dict:
    """The same sphere striking the same plate in the shield stage's SPH: the projectile's material, not
    its momentum (Johnson–Cook flow stress, the materials' spall and plastic-strain failure), run
    ``args.end`` µs past the contact.  Perforated when failed plate particles link (within 1.5
    spacings) a particle of the plate's first layer to one of its last, or plate material beyond
    the rear face moves outward faster than :data:`SPH_EJECTA_SPEED`."""
    dx = args.sph
    problem = shield.sphere_on_plate(SPH_PROJECTILE, args.material, diameter_cm=diameter,
                                     velocity_km_s=args.velocity, obliquity_deg=0.0, plate_thickness_cm=thickness,
                                     spacing_cm=dx, plate_radius_cm=args.half_width)
    start = problem.particles
    n_p = projectile_count(problem)
    tick = time.perf_counter()
    end = shield.run(problem, diameter / (args.velocity * 0.1) + args.end,
                     options=shield.SPHOptions(flow_stress="johnson_cook")).state
    elapsed = time.perf_counter() - tick
    plate = np.arange(start.mass.size) >= n_p
    y0, y, vy = start.position[:, 1], end.position[:, 1], end.velocity[:, 1]
    ejected = plate & (y > thickness + 2.0 * dx) & (vy * 10.0 > SPH_EJECTA_SPEED)
    failed = np.flatnonzero(plate & end.failed)
    _, label = linked_clusters(end.position[failed], 1.5 * dx)
    front = set(label[y0[failed] < dx])
    through = bool(front & set(label[y0[failed] > thickness - dx]))
    rear = plate & (y0 > thickness - dx) & (np.hypot(start.position[:, 0], start.position[:, 2]) < diameter)
    return {"perforated": through or bool(ejected.any()), "through": through, "ejected_g": float(end.mass[ejected].sum()),
            "rear_displacement": float((y - y0)[rear].max()), "particles": start.mass.size, "seconds": elapsed}


def single_wall(thickness: float, args: argparse.Namespace) -> ble.SingleWall:
    """The wall as (S1) sees it: its material's density and Brinell hardness."""
    return ble.SingleWall(thickness, get_material(args.material).rho0, ble.BRINELL_HARDNESS[args.material])


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--diameter", type=float, default=0.06, help="sphere diameter, cm")
    ap.add_argument("--velocity", type=float, default=6.0, help="normal speed, km/s")
    ap.add_argument("--cell", type=float, default=0.01, help="element size, cm (plane and thickness)")
    ap.add_argument("--thickness", type=float, nargs="+", default=[0.16, 0.6], help="wall thicknesses, cm")
    ap.add_argument("--material", default="al2024-t4", choices=sorted(ble.BRINELL_HARDNESS))
    ap.add_argument("--half-width", type=float, default=0.4, help="wall half-width (clamped edges), cm")
    ap.add_argument("--depth-per-diameter", type=float, default=1.0,
                    help="load depth δ over the sphere's diameter (default 1)")
    ap.add_argument("--bisect", type=float, nargs=2, metavar=("LO", "HI"),
                    help="find the diameter (cm) between LO and HI where the wall stage's verdict turns to "
                         "perforation, to --tolerance, per thickness")
    ap.add_argument("--tolerance", type=float, default=0.0025, help="bisection tolerance, cm")
    ap.add_argument("--end", type=float, default=6.0, help="run time after the last arrival, µs")
    ap.add_argument("--mesh-rule", action="store_true",
                    help="the wall stage's default graded mesh on the --cell face grid (its core element by the "
                         "mesh rule, wall.core_element_size) instead of --cell elements")
    ap.add_argument("--sph", type=float, metavar="SPACING",
                    help="run the shield stage's SPH on the same sphere and plate instead, at this particle spacing (cm)")
    args = ap.parse_args()
    if args.sph:
        print(f"{args.material} plate of radius {args.half_width} cm, {SPH_PROJECTILE} sphere at {args.velocity} km/s, "
              f"SPH spacing {args.sph} cm, {args.end} µs after the sphere's transit")
    else:
        cell = (f"face cells {args.cell} cm, the default graded mesh (core element "
                f"{', '.join(f'{wall.core_element_size(t):.4g}' for t in args.thickness)} cm)" if args.mesh_rule
                else f"cell {args.cell} cm")
        print(f"{args.material}, {args.velocity} km/s, {cell}, load depth {args.depth_per_diameter} d, "
              f"clamped at ±{args.half_width} cm, {args.end} µs after the last arrival")
    if args.bisect:
        print("t_w (cm) | (S1) d_c, perforation (cm) | " + ("SPH" if args.sph else "wall stage")
              + ": largest d intact, smallest d perforated (cm) | "
              "ratio to (S1) | runs")
        for t in args.thickness:
            d_c = float(ble.single_wall_critical_diameter(single_wall(t, args), args.velocity, 0.0,
                                                          PROJECTILE_DENSITY))
            lo, hi = args.bisect
            runs = 0
            while hi - lo > args.tolerance:
                mid = 0.5 * (lo + hi)
                perforated = (sph_run(t, mid, args)["perforated"] if args.sph
                              else crater_run(t, mid, args)["verdict"] == wall.PERFORATION)
                runs += 1
                lo, hi = (lo, mid) if perforated else (mid, hi)
            print(f"{t:.3f} | {d_c:.4f} | {lo:.4f}, {hi:.4f} | {0.5 * (lo + hi) / d_c:.2f} | {runs}", flush=True)
        return 0
    mass = PROJECTILE_DENSITY * np.pi * args.diameter**3 / 12.0       # the half model's
    kinetic = 0.5 * mass * (args.velocity * 0.1) ** 2
    momentum = mass * args.velocity * 0.1
    if args.sph:
        print("t_w (cm) | SPH spacing (cm) | particles | perforated | through-thickness failed path | "
              "ejected (g) | rear-face displacement (cm) | SPH (s)")
        for t in args.thickness:
            r = sph_run(t, args.diameter, args)
            print(f"{t:.3f} | {args.sph} | {r['particles']} | {r['perforated']} | {r['through']} | {r['ejected_g']:.3e} | "
                  f"{r['rear_displacement']:.4f} | {r['seconds']:.0f}", flush=True)
        return 0
    print(f"sphere d {args.diameter} cm; half-model momentum {momentum:.4e} g·cm/µs, "
          f"kinetic energy {kinetic:.4e} g·cm²/µs²")
    print("t_w (cm) | layers | elements | p_inf (S1) | (S1) | wall stage | crater (cm) | crater/p_inf | "
          "eroded (g) | rear bulge (cm) | load work / KE | impulse / momentum | failed by (g) | wall (s)")
    for t in args.thickness:
        r = crater_run(t, args.diameter, args)
        print(f"{t:.3f} | {r['layers']} | {r['elements']} | {r['p_inf']:.4f} | {r['equation']} | {r['verdict']} | "
              f"{r['crater_cm']:.4f} | {r['crater_cm'] / r['p_inf']:.2f} | {r['eroded_g']:.3e} | {r['bulge']:.4f} | "
              f"{r['load_work'] / kinetic:.3f} | {r['impulse'] / momentum:.4f} | "
              + ", ".join(f"{k} {v:.2e}" for k, v in r["causes"].items()) + f" | {r['seconds']:.1f}", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
