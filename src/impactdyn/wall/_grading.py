"""The graded solver mesh: near-cubic elements where the debris load is, growing away from it.

A structured rectilinear grid (a :class:`~impactdyn.wallgrid.WallGrid` with non-uniform x, y,
z nodes), so DYNGEN's numbering, the supports and the solver work on it unchanged; node
lines land on the wall's edges and on the symmetry plane x = x[0] exactly.

**The core element** (:func:`core_element_size`): a cube of edge h = t/n, n layers through
the thickness t, with n the smallest count that satisfies both

* n ≥ :data:`MIN_LAYERS` = 8: the report's 4 layers do not resolve the wall's bending and
  spall (docs/vv/convergence.md, "Why the defaults are what they are": the 7a bulge 0.796 cm and perforation at 4
  layers, 0.506 cm and detached spall at 8; the one-point bricks' hourglass share of the
  internal energy 6.7 % at 4 layers in bending, 4.3–5.8 % on 7a from 8 layers), and
* h ≤ D/:data:`ELEMENTS_ACROSS_CRATER`: the crater of a solid fragment of diameter
  :data:`FRAGMENT_DIAMETER_CM` = 0.06 cm at :data:`FRAGMENT_SPEED_KM_S` = 6 km/s spans at
  least 4 elements.  The crater is the hemispherical hypervelocity crater, diameter D ≈ 2 p∞,
  p∞ the semi-infinite penetration depth of the Cour-Palais equation (S1)
  (:func:`impactdyn.ble.penetration_depth`; Cour-Palais 1987; Christiansen 1991, 2009) on the
  report's Al 6061-T6 wall (HB 95, C 5.1 km/s, ρ_p = ρ_t): p∞ = 0.096 cm, D = 0.19 cm, so
  h ≤ 0.048 cm.  The numbers come from the one-fragment study (docs/vv/convergence.md, "The wall: one compact
  fragment under mesh refinement", 0.16-cm 2024 wall at 6 km/s): 0.06 cm is (S1)'s perforation limit
  d_c = 0.0598 cm there, and the wall stage perforates from 0.67 d_c at 0.005–0.01-cm cells,
  0.77 d_c at 0.02, 0.82 at 0.04 (4–5 elements across D), but 2.9 d_c at the pipeline's
  0.16-cm cells (1.2 across D).  4 elements across the crater is the coarsest of those
  meshes that still resolves a fragment near the limit (within 20 % of the finest).

For the report's 0.3175-cm wall the layers decide: n = 8, h = 0.0397 cm (the crater rule would
allow 0.048); for a 0.16-cm wall n = 8, h = 0.02 cm.  The crater rule takes over above
t = 8 × 0.048 = 0.38 cm.  On a 2024 wall (HB 120) the crater is 6 % smaller ((95/120)^¼):
within the rule's margin, so the rule does not take the material.

**The resolving region** (:func:`resolving_region`): the bounding box of the case grid's face
cells whose areal momentum Σ|I|/area is at least a share f of the peak cell's, widened by
:data:`REGION_MARGIN_THICKNESSES` = 1 wall thickness on every side (the shear ring of a punched
plug and the crater's lip lie within about a thickness of the load) and clipped to the wall.  f is
the first of :data:`REGION_FRACTIONS` (0.1 … 0.9) whose mesh fits the cost budget below, or else
0.9 — the box of the cells within 10 % of the peak, where the cloud's core and so its largest
fragments arrive.  Outside it the elements grow.

**Grading** (:func:`graded_nodes`): along x and along z the element size follows the size field
h(x) = min(h_max, h_c + ln(r)·d(x)), d the distance to the region, r = ``grading_ratio``; the
nodes equidistribute ∫dx/h (⌈∫dx/h⌉ elements, each spanning the same ∫dx/h ≤ 1).  Seen against
that integral, h is a clamped exponential r^Φ, so neighbouring elements differ by at most the
factor r (exactly: r^{ΔΦ} with ΔΦ ≤ 1) — in the region, into the grading and onto the plateau —
and no element is larger than h_max or, in the region, than h_c.  The default r = 1.2 and the
bound :data:`MAX_GRADING_RATIO` = 1.5: a wave crossing a size jump has the band between the two
elements' cut-off frequencies reflected (Bažant 1978, "Spurious reflection of elastic waves in
nonuniform finite element grids", CMAME 16; Celep & Bažant 1983 on gradually changing sizes,
IJNME 19), so the change is kept gradual; above 1.5 a "grading" is a sequence of jumps.

**The largest in-plane size** h_max (``max_element_size_cm``): by default the case grid's
largest in-plane cell (0.16 cm on the report's grid) — the far field is never coarser than the
report's wall stage, and the deposition there is known on that grid only, so finer cells would
not resolve the load any better.  There the elements are flat (0.16/0.0397 ≈ 4 on the report's
wall, where the report's own were 2): 8 layers everywhere at aspect ≤ 2 would be 164,000
elements on the report's 8 × 16-cm half wall, 3 times the budget below.  The flat elements
are where the wall carries the load by bending over lengths of many thicknesses, not where it
craters.

**The load** (:func:`rebin_deposition`): each record on a case-grid face cell is split over the
graded grid's face cells it overlaps, in proportion to the overlap areas (rectilinear: products
of 1-D overlaps), at its arrival time; then :func:`~._load.nodal_load` spreads it as on any
mesh.  Every record's impulse is kept to round-off, and the depth δ of the load stays defined
from the case's grid (:func:`~._load.default_depth`), so the load's energy does not change
with the mesh.

**Cost**: the solver does 3–9 M element-steps/s at 2 threads (benchmarks/BENCHMARKS.md, "Throughput") and its step is
∝ h_c (:data:`STEP_PER_CM_US`), so a ≤ 60-s wall stage of a ~100-µs run allows
:data:`ELEMENT_STEPS_BUDGET` = 1.5e8 element-steps.  On the report's 8 × 16-cm half wall the
budget is not met by any region: the far field alone is 5,000 columns of 0.16-cm cells × 8
layers = 40,000 elements, and the fine lines of a structured grid run across the whole wall, so
the smallest region is taken.  Measured (tests/wall/test_grading.py and the 7a run):

=====================================  ==========  =============================  =================
wall, deposition                       h_c (cm)    elements (nx × 8 × nz)         element-steps
=====================================  ==========  =============================  =================
0.3175 cm, the 7a shot's               0.0397      66 × 8 × 135 = 71,280          1.62e8 measured
                                                   (report mesh: 20,000)          (2,278 steps)
0.3175 cm, a 0.5-cm sphere             0.0397      63 × 8 × 126 = 63,504          1.7e8 estimated
0.3175 cm, a 2-cm-wide cloud           0.0397      72 × 8 × 144 = 82,944          2.2e8 estimated
0.16 cm, a 0.5-cm sphere               0.02        71 × 8 × 142 = 80,656          4.2e8 estimated
0.16 cm, a 2-cm-wide cloud             0.02        92 × 8 × 184 = 135,424         7.1e8 estimated
=====================================  ==========  =============================  =================

So a Table 2 wall costs about the budget (7a: ~66 s at 2.5 M element-steps/s), a 0.16-cm wall
3–5 times it: its 8 layers of 0.02 cm halve the step, and its far-field elements are 8 times
as wide as thick.
"""

from __future__ import annotations

import math

import numpy as np

from impactdyn._errors import InputError
from impactdyn.ble import SingleWall, penetration_depth
from impactdyn.wall._mesh import (
    MESH_KINDS, WallMesh, assemble_mesh, check_density_supports, check_refinements, refined)
from impactdyn.wallgrid import WallDeposition, WallGrid, check_nodes, face_overlaps

#: Layers through the thickness at least: the bulge converges from 8 (module docstring).
MIN_LAYERS = 8
#: Core elements across a fragment's crater diameter 2 p∞ at least (module docstring).
ELEMENTS_ACROSS_CRATER = 4
#: The fragment whose crater the core resolves: (S1)'s perforation limit of a 0.16-cm wall at 6 km/s.
FRAGMENT_DIAMETER_CM = 0.06
#: Its speed, km/s: the one-fragment study's (module docstring).
FRAGMENT_SPEED_KM_S = 6.0
#: Shares of the peak areal momentum tried in turn for the resolving region: the first whose mesh
#: fits :data:`ELEMENT_STEPS_BUDGET` is taken (module docstring).
REGION_FRACTIONS = (0.1, 0.2, 0.3, 0.5, 0.7, 0.9)
#: Elements × steps a wall run may cost: ~60 s at the solver's ~2.5 M element-steps/s on 2 threads.
ELEMENT_STEPS_BUDGET = 1.5e8
#: The run length the budget is for, µs: the Table 2 runs end at the wall stage's 100-µs ceiling.
BUDGET_RUN_US = 100.0
#: The region's margin around those cells, in wall thicknesses.
REGION_MARGIN_THICKNESSES = 1.0
#: The solver's mean step over the core element's edge, µs/cm, measured on the 7a wall (Johnson–Cook
#: 6061-T6, default options, 0.0397-cm core): 1.38 at the start (courant 0.9 × ℓ/c), 0.95–0.97 over
#: the whole run (87.5 µs in 2,278–2,334 steps), the elements' deformation and erosion shortening it.
STEP_PER_CM_US = 0.95
#: Default and largest ratio of neighbouring element sizes (module docstring).
GRADING_RATIO = 1.2
MAX_GRADING_RATIO = 1.5


def core_element_size(thickness_cm: float, fragment_diameter_cm: float = FRAGMENT_DIAMETER_CM,
                      fragment_speed_km_s: float = FRAGMENT_SPEED_KM_S) -> float:
    """Edge h = t/n of the core's cubic elements for a wall of thickness t (cm; module docstring):
    n = max(8, ⌈t / (2 p∞ / 4)⌉), p∞ the Cour-Palais (S1) crater depth of the fragment on Al 6061-T6."""
    if not (math.isfinite(thickness_cm) and thickness_cm > 0):
        raise InputError(f"thickness_cm: must be > 0, got {thickness_cm!r}")
    crater = 2.0 * float(penetration_depth(SingleWall(thickness_cm), fragment_diameter_cm, fragment_speed_km_s))
    layers = max(MIN_LAYERS, math.ceil(thickness_cm / (crater / ELEMENTS_ACROSS_CRATER)))
    return thickness_cm / layers


def resolving_region(wall: WallGrid, deposition: WallDeposition, fraction: float
                     ) -> tuple[tuple[float, float], tuple[float, float]] | None:
    """((x0, x1), (z0, z1)), cm: the box of ``wall``'s face cells whose areal momentum Σ|I|/area is at
    least ``fraction`` of the peak's, widened by the margin and clipped (module docstring); None
    without momentum."""
    deposition.check_fits(wall)
    nx = wall.shape[0]
    momentum = np.bincount(deposition.element, np.linalg.norm(deposition.impulse, axis=1),
                           minlength=wall.n_face_elements)
    if not momentum.any():
        return None
    area = np.outer(np.diff(wall.z), np.diff(wall.x)).ravel()      # face element i + nx k
    areal = momentum / area
    k, i = np.divmod(np.flatnonzero(areal >= fraction * areal.max()), nx)
    margin = REGION_MARGIN_THICKNESSES * wall.thickness
    return ((max(wall.x[0], wall.x[i.min()] - margin), min(wall.x[-1], wall.x[i.max() + 1] + margin)),
            (max(wall.z[0], wall.z[k.min()] - margin), min(wall.z[-1], wall.z[k.max() + 1] + margin)))


def graded_nodes(lo: float, hi: float, region: tuple[float, float] | None, h_core: float, ratio: float,
                 h_max: float, lines: np.ndarray | None = None) -> np.ndarray:
    """Nodes on [lo, hi] (exactly at both ends) graded from h ≤ ``h_core`` in ``region`` (a ≤ b in
    [lo, hi]; None: none) by at most ``ratio`` per element up to ``h_max`` ≥ ``h_core`` (module docstring).

    ``lines``: the case grid's nodes on [lo, hi], equally spaced by ``h_max``; then the grading
    ends on one of them where it has reached the plateau, and beyond it the nodes are those
    lines (so the records there are not split).
    """
    if region is None:
        return lines.copy() if lines is not None else _equidistributed(lo, hi, lo, lo, h_max, ratio, h_max)
    a, b = region
    if lines is None:
        return _equidistributed(lo, hi, a, b, h_core, ratio, h_max)
    # the grading, then r/(r − 1) plateau elements: the graded stretch then has n ≥ r/(r − 1) elements
    # spanning ∫dx/h > n − 1, each of h_max (n − 1)/n at least, within the factor r of the lines' h_max
    reach = (h_max - h_core) / math.log(ratio) + h_max * ratio / (ratio - 1.0)
    start = lines[lines <= a - reach]
    end = lines[lines >= b + reach]
    lo_g = start[-1] if start.size else lo
    hi_g = end[0] if end.size else hi
    return np.concatenate([start[:-1], _equidistributed(lo_g, hi_g, a, b, h_core, ratio, h_max), end[1:]])


def _equidistributed(lo: float, hi: float, a: float, b: float, h_core: float, ratio: float,
                     h_max: float) -> np.ndarray:
    """Nodes on [lo, hi] equidistributing ∫dx/h, h = min(h_max, h_core + ln(ratio)·distance to [a, b])."""
    g = math.log(ratio)
    d_cap = (h_max - h_core) / g         # distance from the region where h reaches h_max
    phi_cap = math.log(h_max / h_core) / g

    def phi(d: float) -> float:          # ∫_0^d ds / h(s), s the distance from the region
        return math.log1p(g * d / h_core) / g if d <= d_cap else phi_cap + (d - d_cap) / h_max

    def dist(p: np.ndarray) -> np.ndarray:   # its inverse
        return np.where(p <= phi_cap, h_core * np.expm1(g * np.minimum(p, phi_cap)) / g,
                        d_cap + (p - phi_cap) * h_max)

    left, core, right = phi(a - lo), (b - a) / h_core, phi(hi - b)
    total = left + core + right
    n = max(1, math.ceil(total * (1.0 - 1e-12)))
    p = total * np.arange(n + 1) / n
    x = np.where(p < left, a - dist(left - p),
                 np.where(p <= left + core, a + (p - left) * h_core, b + dist(p - left - core)))
    x[0], x[-1] = lo, hi
    return x


def graded_grid(wall: WallGrid, deposition: WallDeposition, h_core: float, ratio: float, h_max: float
                ) -> tuple[WallGrid, tuple[tuple[float, float], tuple[float, float]] | None]:
    """The graded grid of ``wall`` (layers of ``h_core``, which must divide the thickness) and the
    resolving region it was graded from: the first of :data:`REGION_FRACTIONS` whose grid fits
    :data:`ELEMENT_STEPS_BUDGET`, or the last (module docstring)."""
    layers = round(wall.thickness / h_core)
    # beyond the grading the case grid's own lines, where they are the plateau's size
    lines = [a if np.allclose(np.diff(a), h_max, rtol=1e-9, atol=0.0) else None for a in (wall.x, wall.z)]
    steps = BUDGET_RUN_US / (STEP_PER_CM_US * h_core)
    for fraction in REGION_FRACTIONS:
        region = resolving_region(wall, deposition, fraction)
        x, z = (graded_nodes(a[0], a[-1], None if region is None else region[axis], h_core, ratio, h_max,
                             lines[axis]) for axis, a in enumerate((wall.x, wall.z)))
        if (x.size - 1) * (z.size - 1) * layers * steps <= ELEMENT_STEPS_BUDGET:
            break
    check_nodes("element_size_cm: mesh nodes", (x.size, layers + 1, z.size))
    return WallGrid(x, np.linspace(wall.y[0], wall.y[-1], layers + 1), z), region


def rebin_deposition(deposition: WallDeposition, source: WallGrid, target: WallGrid) -> WallDeposition:
    """The records of ``deposition`` on ``source``'s face cells split over ``target``'s by overlap area.

    Record r becomes consecutive records, one per target face cell its cell overlaps (in
    target element order), same time, impulse I_r times the overlap's share of the source
    cell's area, so each record's impulse is kept to round-off.  The two face grids must span
    the same rectangle.
    """
    deposition.check_fits(source)
    for name in ("x", "z"):
        s, t = getattr(source, name), getattr(target, name)
        if not np.allclose([t[0], t[-1]], [s[0], s[-1]], rtol=0.0, atol=1e-12 * (s[-1] - s[0])):
            raise InputError(f"wall.{name}: the mesh spans [{t[0]:g}, {t[-1]:g}], the case's grid "
                             f"[{s[0]:g}, {s[-1]:g}]")
    cells, inverse = np.unique(deposition.element, return_inverse=True)
    pieces_element, pieces_share, counts = [], [], np.zeros(cells.size, dtype=np.int64)
    for c, (fine, share) in enumerate(face_overlaps(source, target, cells)):
        pieces_element.append(fine)
        pieces_share.append(share)
        counts[c] = fine.size
    start = np.concatenate([[0], np.cumsum(counts)])
    element_of = np.concatenate(pieces_element) if cells.size else np.zeros(0, dtype=np.int64)
    share_of = np.concatenate(pieces_share) if cells.size else np.zeros(0)
    n = counts[inverse]
    record = np.repeat(np.arange(deposition.element.size), n)
    piece = start[inverse][record] + np.arange(record.size) - np.repeat(np.cumsum(n) - n, n)
    return WallDeposition(element=element_of[piece].astype(np.int64), time=deposition.time[record],
                          impulse=deposition.impulse[record] * share_of[piece][:, None])


def solver_mesh(wall: WallGrid, deposition: WallDeposition, density: float, *, mesh: str = "graded",
                element_size_cm: float | None = None, grading_ratio: float = GRADING_RATIO,
                max_element_size_cm: float | None = None, refinement_thickness: int = 1,
                refinement_plane: int = 1, supports: str = "dyngen") -> WallMesh:
    """The wall stage's mesh of the case's grid ``wall`` under ``deposition`` (on that grid): the nodes of
    :func:`solver_grid`, with ρ₀ = ``density``, the lumped masses and the ``supports``.

    :func:`~._load.nodal_load` takes the deposition on ``wall`` to the mesh's nodes; the deck writers
    take ``mesh.grid`` and the records re-binned onto it (:func:`rebin_deposition`).  Raises
    :class:`InputError` naming the key.
    """
    check_density_supports(density, supports)
    grid = solver_grid(wall, deposition, mesh=mesh, element_size_cm=element_size_cm, grading_ratio=grading_ratio,
                       max_element_size_cm=max_element_size_cm, refinement_thickness=refinement_thickness,
                       refinement_plane=refinement_plane)
    refinement = check_refinements(refinement_thickness, refinement_plane)
    return assemble_mesh(wall, grid, density, supports, refinement=refinement, kind=mesh)


def solver_grid(wall: WallGrid, deposition: WallDeposition, *, mesh: str = "graded",
                element_size_cm: float | None = None, grading_ratio: float = GRADING_RATIO,
                max_element_size_cm: float | None = None, refinement_thickness: int = 1,
                refinement_plane: int = 1) -> WallGrid:
    """The nodes of the wall stage's mesh (:func:`solver_mesh`), without its masses and supports.

    ``mesh`` one of :data:`MESH_KINDS`:

    * ``"graded"`` (module docstring): core elements cubes of edge t/n, n = ⌈t/h⌉ layers with
      h = ``element_size_cm`` (None: :func:`core_element_size`), in the resolving region of
      ``deposition``; in-plane sizes growing by at most ``grading_ratio`` per element up to
      ``max_element_size_cm`` (None: the largest in-plane cell of ``wall``, or h if that is
      smaller); then every element cut into ``refinement_thickness`` layers and
      ``refinement_plane`` × ``refinement_plane`` pieces in the plane, the same mesh refined
      uniformly (the convergence study's "2×").
    * ``"report"``: ``wall`` itself with the refinements (:func:`~._mesh.build_mesh`).
    """
    if mesh not in MESH_KINDS:
        raise InputError(f"mesh: {mesh!r}, expected one of {MESH_KINDS}")
    deposition.check_fits(wall)
    if mesh == "report":
        return refined(wall, *check_refinements(refinement_thickness, refinement_plane))
    thickness = wall.thickness
    check_mesh_sizes(min(wall.x[-1] - wall.x[0], wall.z[-1] - wall.z[0]), element_size_cm, max_element_size_cm)
    h = core_element_size(thickness) if element_size_cm is None else element_size_cm
    if not (isinstance(grading_ratio, (int, float)) and 1.0 < grading_ratio <= MAX_GRADING_RATIO):
        raise InputError(f"grading_ratio: must be in (1, {MAX_GRADING_RATIO}], got {grading_ratio!r}")
    h_core = thickness / math.ceil(thickness / h * (1.0 - 1e-12))
    if max_element_size_cm is None:
        h_max = max(h_core, float(max(np.diff(wall.x).max(), np.diff(wall.z).max())))
    else:
        h_max = float(max_element_size_cm)
        if h_max < h_core:
            raise InputError(f"max_element_size_cm: {h_max:g} cm is below the core element's {h_core:g} cm")
    grid, _ = graded_grid(wall, deposition, h_core, grading_ratio, h_max)
    return refined(grid, *check_refinements(refinement_thickness, refinement_plane))


def check_mesh_sizes(extent_cm: float, element_size_cm: float | None, max_element_size_cm: float | None) -> None:
    """The graded mesh's sizes (None: the rule's) in (0, ``extent_cm``] (the wall's smaller in-plane
    extent), else an InputError naming the key (a case checks them before any stage runs)."""
    extent = float(extent_cm)
    for key, value in (("element_size_cm", element_size_cm), ("max_element_size_cm", max_element_size_cm)):
        if value is not None and (isinstance(value, bool) or not isinstance(value, (int, float))
                                  or not (0.0 < value <= extent)):
            raise InputError(f"{key}: must be in (0, {extent:g}] cm (the wall's smaller in-plane extent), "
                             f"got {value!r}")
