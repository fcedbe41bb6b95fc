"""The wall's verdict and continuous measures, from the state at the end of the run.

Definitions (elements are face-connected when they share a face: 6-connectivity on the
brick grid; the front layer is j = 0, the rear layer j = ny − 1; y points from the front
face into the wall and out of the rear face):

* **failed** element: one that a failure criterion of its material model has failed
  (``flags[e, FAILED]`` ≠ 0, the criterion's code of :data:`impactdyn.wall._state.FAILURE_CAUSES`:
  ductile damage, ductile damage at the fracture-strain floor, tensile pressure, plastic strain,
  spall damage).  Failure is for good.  A failed element carries no deviatoric stress and no
  tension, only compressive pressure; it holds no material together across it.  **eroded**:
  removed from the force computation (at once on failure when the model erodes, else when its
  step collapses or its volume inverts, :mod:`._step`).
* **damaged** element: failed or eroded.  The verdict treats both alike: a failed element that
  still pushes back in compression is rubble, not wall — material held only through it is not
  held.
* **anchored** material: the intact (not damaged) elements face-connected, through intact
  elements, to an intact element with a node whose y translation is fixed (the supported
  edges).  Without such supports (``"free"``, ``"uniaxial"``), the largest face-connected
  set of intact elements.  A node is a **wall** node when it belongs to an anchored
  element, an **orphan** when all its elements are eroded, otherwise a **fragment** node
  (it moves with detached material only).
* **perforation** when (a) a face-connected set of damaged elements reaches from the front
  layer to the rear layer (a flood fill of the damaged elements from the front layer), or
  (b) rear-face material leaves the wall: a rear-face node that belongs to a damaged
  element (or is an orphan) moves outward (v_y) faster than the escape velocity
  (``WallOptions.escape_velocity_km_s``, default 1 km/s, faster than the spall scabs of
  aluminium plates, whose free surfaces move at a few hundred m/s) at the end of the run.
* **detached spall** when there is no perforation and rear-face material has separated: a
  rear-face node that is not a wall node (it is held by failed, eroded or cut-off material
  only) moves outward (v_y > 0) at the end of the run.  This is the stage's own criterion, not
  a solver's: LS-DYNA, like this solver, does not delete solids that spall (they keep
  compressive pressure), so a spall layer is "detached" here by topology (no intact
  face-connected path to the supports) and motion (moving away), not by a gap opening in the
  mesh.
* **no perforation** otherwise.  Failed material inside the wall (an internal spall plane, a
  damaged crater floor) with intact material holding the whole rear face is no perforation.

Continuous measures (end of the run unless said otherwise; displacements u = x − X₀):

* ``crater_depth_cm`` = max(thinning, damage depth): thinning = the largest loss of wall
  thickness, u_y(front node) − u_y(rear node) of one node column (i, k), over the columns
  whose front and rear nodes are both wall nodes and whose adjacent elements are intact
  through the whole thickness (across a failed or eroded element the front and rear nodes
  are no longer held apart: the solver has no contact between the pieces, and their
  difference can exceed the thickness); damage depth = y_{j+1} − y₀ of the deepest
  layer j reached by damaged material face-connected to the front layer (0 if the front
  layer is intact).  ``crater_depth_ratio`` = crater depth / wall thickness; ``crater_resolved``:
  the crater is at least one element layer deep (the front layer's thickness), the least depth
  the mesh can show; a shallower crater is not resolved, and two meshes that both leave it
  unresolved agree on it whatever its number (docs/vv/convergence.md).  The thinning,
  not the front face's displacement, because a thin wall's front face moves mostly with the
  wall's bulge; the largest front-face displacement of a wall node is reported as
  ``front_dent_cm`` (bulge plus crater).
* ``failed_mass_g`` (failed, not eroded), ``eroded_mass_g``, ``damaged_mass_g``.
* ``failed_mass_by_cause_g``: the damaged mass (failed or eroded) split by the criterion that
  failed each element (:func:`failed_mass_by_cause`; the criteria of
  :data:`impactdyn.wall._state.FAILURE_CAUSES`: ductile damage, ductile damage at the
  fracture-strain floor, tensile pressure, plastic strain): what made the wall fail.
* ``rear_bulge_cm``: the rear bulge at the end of the run: the largest outward u_y of a
  rear-face wall node, averaged over the last quarter of the time after the last arrival
  (the wall still rings elastically when the run ends); ``rear_bulge_end_cm``: the same at
  the end of the run.  A permanent bulge only if the wall has come to rest (``ended_by`` is
  "decay"): a run that ends at the ``max_time_us`` ceiling leaves the wall in its first
  swings, and the value is that moment's deflection (docs/vv/convergence.md, "The wall: Table 2 at the default mesh and at twice its resolution":
  the 7b wall's is 0.16 cm at 100 µs, 0.23 cm at 300 µs, and the plate has swung back to
  under 0.001 cm by 600 µs).
* ``peak_rear_bulge_cm`` and ``peak_rear_bulge_time_us``: the largest of those over the run's
  history samples, and when.
* ``ended_by``: how the run ended (:data:`impactdyn.wall.ENDINGS`: "decay", "end_time" or
  "ceiling"); ``kinetic_left_fraction``: the wall's kinetic energy at the end over its peak.
* ``peak_rear_velocity_km_s``: the largest outward rear-face node velocity over the run.
* ``spall_mass_g``: mass of the detached elements (damaged, or intact not anchored) that
  touch the rear layer.
* the energy balance of :mod:`._solver` (work of the load, kinetic, internal = elastic +
  plastic, hourglass, bulk viscous, eroded) and its error.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage

from impactdyn.wall._mesh import WallMesh
from impactdyn.wall._state import FAILURE_CAUSES

PERFORATION = "perforation"
DETACHED_SPALL = "detached spall"
NO_PERFORATION = "no perforation"
VERDICTS = (PERFORATION, DETACHED_SPALL, NO_PERFORATION)

#: Node categories (:func:`node_categories`).
WALL, FRAGMENT, ORPHAN = 0, 1, 2


def _grid(mesh: WallMesh, a: np.ndarray) -> np.ndarray:
    """Element array in number order → (ny, nz, nx) [j, k, i]."""
    nx, ny, nz = mesh.shape
    return np.asarray(a).reshape(ny, nz, nx)


def _intact_node_columns(mesh: WallMesh, damaged: np.ndarray) -> np.ndarray:
    """Node columns (NK, NI) [k, i] whose adjacent element columns hold no damaged element."""
    damaged_column = np.pad(_grid(mesh, damaged).any(axis=0), 1)
    return ~(damaged_column[:-1, :-1] | damaged_column[:-1, 1:] | damaged_column[1:, :-1] | damaged_column[1:, 1:])


def through_path(mesh: WallMesh, damaged: np.ndarray) -> np.ndarray:
    """Elements of the face-connected damaged sets that reach from the front to the rear layer, (ne,) bool."""
    labels, _ = ndimage.label(_grid(mesh, damaged))
    through = np.intersect1d(labels[0][labels[0] > 0], labels[-1][labels[-1] > 0])
    return np.isin(labels, through).ravel()


def front_connected(mesh: WallMesh, damaged: np.ndarray) -> np.ndarray:
    """Damaged elements face-connected (through damaged elements) to the front layer, (ne,) bool."""
    labels, _ = ndimage.label(_grid(mesh, damaged))
    front = np.unique(labels[0][labels[0] > 0])
    return np.isin(labels, front).ravel()


def anchored_elements(mesh: WallMesh, damaged: np.ndarray) -> np.ndarray:
    """Intact elements connected to the supports through intact elements (module docstring), (ne,) bool."""
    intact = ~np.asarray(damaged, dtype=bool)
    labels, n = ndimage.label(_grid(mesh, intact))
    flat = labels.ravel()
    if n == 0:
        return np.zeros(flat.size, dtype=bool)
    held = mesh.fixed[:, 1][mesh.connectivity].any(axis=1) & intact
    if held.any():
        keep = np.unique(flat[held])
    else:
        counts = np.bincount(flat, minlength=n + 1)
        counts[0] = 0
        keep = np.array([int(np.argmax(counts))])
    return np.isin(flat, keep)


def node_categories(mesh: WallMesh, failed: np.ndarray, eroded: np.ndarray) -> np.ndarray:
    """WALL (0), FRAGMENT (1) or ORPHAN (2) for every node (module docstring), (n_nodes,) int8."""
    failed = np.asarray(failed, dtype=bool)
    eroded = np.asarray(eroded, dtype=bool)
    anchored = anchored_elements(mesh, failed | eroded)
    conn = mesh.connectivity
    cat = np.full(mesh.n_nodes, ORPHAN, dtype=np.int8)
    cat[conn[~eroded].ravel()] = FRAGMENT
    cat[conn[anchored].ravel()] = WALL
    return cat


def classify(mesh: WallMesh, failed: np.ndarray, eroded: np.ndarray, velocity: np.ndarray,
             escape_velocity: float) -> tuple[str, dict]:
    """The verdict (module docstring) and the evidence: which criterion, how many elements or nodes.

    velocity (n_nodes, 3) cm/µs at the end of the run; escape_velocity cm/µs.
    """
    failed = np.asarray(failed, dtype=bool)
    eroded = np.asarray(eroded, dtype=bool)
    damaged = failed | eroded
    path = through_path(mesh, damaged)
    rear = mesh.face_nodes("rear").ravel()
    cat = node_categories(mesh, failed, eroded)
    on_damaged = np.zeros(mesh.n_nodes, dtype=bool)
    on_damaged[mesh.connectivity[damaged].ravel()] = True
    on_damaged |= cat == ORPHAN
    vy = velocity[rear, 1]
    escaping = rear[on_damaged[rear] & (vy > escape_velocity)]
    separating = rear[(cat[rear] != WALL) & (vy > 0.0)]
    evidence = {"through_path_elements": int(path.sum()), "escaping_rear_nodes": int(escaping.size),
                "separating_rear_nodes": int(separating.size)}
    if path.any():
        return PERFORATION, {**evidence, "criterion": "through-thickness path of failed or eroded elements"}
    if escaping.size:
        return PERFORATION, {**evidence, "criterion": "rear-face material attached to failed material "
                                                      "leaving faster than the escape velocity"}
    if separating.size:
        return DETACHED_SPALL, {**evidence, "criterion": "rear-face material separated from the wall, moving outward"}
    return NO_PERFORATION, {**evidence, "criterion": "none met"}


def measures(mesh: WallMesh, failed: np.ndarray, eroded: np.ndarray, displacement: np.ndarray) -> dict:
    """The geometric and mass measures at the end of the run (module docstring)."""
    failed = np.asarray(failed, dtype=bool)
    eroded = np.asarray(eroded, dtype=bool)
    damaged = failed | eroded
    mass = mesh.element_mass
    cat = node_categories(mesh, failed, eroded)
    front = mesh.face_nodes("front").ravel()
    front = front[cat[front] == WALL]
    dent = float(max(displacement[front, 1].max(), 0.0)) if front.size else 0.0
    front_g, rear_g = mesh.face_nodes("front"), mesh.face_nodes("rear")
    both = (cat[front_g] == WALL) & (cat[rear_g] == WALL) & _intact_node_columns(mesh, damaged)
    thinning = displacement[front_g, 1] - displacement[rear_g, 1]
    thinning = float(max(thinning[both].max(), 0.0)) if both.any() else 0.0
    deep = _grid(mesh, front_connected(mesh, damaged))
    layers = np.flatnonzero(deep.any(axis=(1, 2)))
    y = mesh.grid.y
    damage_depth = float(y[layers.max() + 1] - y[0]) if layers.size else 0.0
    rear = mesh.face_nodes("rear").ravel()
    rear_wall = rear[cat[rear] == WALL]
    bulge = float(max(displacement[rear_wall, 1].max(), 0.0)) if rear_wall.size else 0.0
    anchored = anchored_elements(mesh, damaged)
    rear_layer = np.zeros(mesh.n_elements, dtype=bool)
    rear_layer[mesh.layer_elements(mesh.shape[1] - 1).ravel()] = True
    detached = ~anchored
    labels, _ = ndimage.label(_grid(mesh, detached))
    rear_labels = np.unique(labels[-1][labels[-1] > 0])
    spall = np.isin(labels, rear_labels).ravel() & detached
    crater = max(thinning, damage_depth)
    return {
        "crater_depth_cm": crater,
        "crater_depth_ratio": crater / mesh.thickness,
        "crater_resolved": bool(crater >= y[1] - y[0]),
        "thinning_cm": thinning,
        "front_dent_cm": dent,
        "damage_depth_cm": damage_depth,
        "failed_mass_g": float(mass[failed & ~eroded].sum()),
        "eroded_mass_g": float(mass[eroded].sum()),
        "damaged_mass_g": float(mass[damaged].sum()),
        "failed_elements": int((failed & ~eroded).sum()),
        "eroded_elements": int(eroded.sum()),
        "rear_bulge_end_cm": bulge,
        "spall_mass_g": float(mass[spall].sum()),
    }


def failed_mass_by_cause(mesh: WallMesh, failure_cause: np.ndarray) -> dict[str, float]:
    """{criterion: mass (g) of the elements it failed} over :data:`FAILURE_CAUSES` (zeros included).

    failure_cause : (n_elements,) codes, 0 intact, else 1 + the criterion's index.
    """
    code = np.asarray(failure_cause)
    mass = mesh.element_mass
    return {name: float(mass[code == i + 1].sum()) for i, name in enumerate(FAILURE_CAUSES)}
