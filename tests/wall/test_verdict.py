"""The verdict and measures on hand-made fields of failed and eroded elements."""

import numpy as np
import pytest

from impactdyn import wall
from impactdyn.wall._verdict import FRAGMENT, ORPHAN, WALL, node_categories
from impactdyn.wallgrid import WallGrid

GRID = WallGrid.uniform((0.0, 0.8), (0.0, 0.4), (-0.4, 0.4), (9, 5, 9))      # 8 × 4 × 8 elements
MESH = wall.build_mesh(GRID, 2.703)
ESCAPE = 0.1                                                                # cm/µs (1 km/s)


def field(cells):
    """Element flags from (i, j, k) triples."""
    nx, _, nz = MESH.shape
    out = np.zeros(MESH.n_elements, dtype=bool)
    for i, j, k in cells:
        out[i + nx * k + nx * nz * j] = True
    return out


def still():
    return np.zeros((MESH.n_nodes, 3))


def verdict(failed, eroded=None, velocity=None):
    eroded = np.zeros_like(failed) if eroded is None else eroded
    return wall.classify(MESH, failed, eroded, still() if velocity is None else velocity, ESCAPE)


def test_intact_wall():
    v, evidence = verdict(np.zeros(MESH.n_elements, dtype=bool))
    assert v == wall.NO_PERFORATION and evidence["through_path_elements"] == 0


def test_straight_and_winding_paths_perforate():
    straight = field([(1, j, 3) for j in range(4)])
    assert verdict(straight)[0] == wall.PERFORATION
    winding = field([(1, 0, 3), (1, 1, 3), (2, 1, 3), (2, 1, 4), (2, 2, 4), (3, 2, 4), (3, 3, 4)])
    assert verdict(winding)[0] == wall.PERFORATION
    # eroded elements count as well as failed ones, mixed along the path
    assert verdict(field([(1, 0, 3), (1, 1, 3)]), field([(1, 2, 3), (1, 3, 3)]))[0] == wall.PERFORATION


def test_edge_contact_is_not_a_path():
    # consecutive layers touch along an edge only: no face-connected path
    diagonal = field([(1, 0, 3), (2, 1, 3), (3, 2, 3), (4, 3, 3)])
    assert verdict(diagonal)[0] == wall.NO_PERFORATION
    # a path that stops one layer short of the rear face
    assert verdict(field([(1, j, 3) for j in range(3)]))[0] == wall.NO_PERFORATION


def test_crater_measures():
    failed = field([(i, j, k) for i in range(2) for j in range(2) for k in range(3, 5)])
    u = still()
    front = MESH.face_nodes("front").ravel()
    u[front[5], 1] = 0.03                                 # a dent at an intact front node
    m = wall.measures(MESH, failed, np.zeros_like(failed), u)
    assert m["damage_depth_cm"] == pytest.approx(0.2)     # two of four 0.1 cm layers
    assert m["crater_depth_ratio"] == pytest.approx(0.5)
    assert m["front_dent_cm"] == pytest.approx(0.03)
    assert m["failed_mass_g"] == pytest.approx(8 * 2.703 * 0.1 ** 3)
    assert m["eroded_mass_g"] == 0.0
    assert verdict(failed)[0] == wall.NO_PERFORATION


def test_thinning_is_measured_across_intact_columns_only():
    # an eroded element inside column (2, 5) lets its front node pass its rear node (no contact
    # between the pieces): that column is not a thinning of the wall, a plastic one next to it is
    eroded = field([(2, 1, 5)])
    front, rear = MESH.face_nodes("front"), MESH.face_nodes("rear")
    u = still()
    u[front[5, 2], 1] = 0.9                               # 2.25 wall thicknesses past its rear node
    u[front[2, 6], 1] = 0.05                              # away from the eroded element: counted
    m = wall.measures(MESH, np.zeros_like(eroded), eroded, u)
    assert m["thinning_cm"] == pytest.approx(0.05)
    assert m["damage_depth_cm"] == 0.0                   # the eroded element is not reached from the front
    assert m["crater_depth_ratio"] == pytest.approx(0.05 / 0.4)
    assert m["front_dent_cm"] == pytest.approx(0.9)
    u[rear[2, 6], 1] = 0.05                               # the same column moving as a whole: no thinning
    assert wall.measures(MESH, np.zeros_like(eroded), eroded, u)["thinning_cm"] == 0.0


def spall_field():
    """A failed layer under a patch at j = 2 and a failed ring at j = 3: the patch's rear part is cut off."""
    patch = [(i, 2, k) for i in range(4) for k in range(1, 7)]
    ring = [(i, 3, k) for i in range(4) for k in range(1, 7) if i == 3 or k in (1, 6)]
    return field(patch + ring)


def test_detached_spall():
    failed = spall_field()
    eroded = np.zeros_like(failed)
    cat = node_categories(MESH, failed, eroded)
    scab = field([(i, 3, k) for i in range(3) for k in range(2, 6)])
    scab_nodes = np.unique(MESH.connectivity[scab])
    rear = MESH.face_nodes("rear").ravel()
    inner = np.intersect1d(scab_nodes, rear)
    # the scab's inner rear nodes are held only by the cut-off material
    assert np.all(cat[np.intersect1d(inner, np.unique(MESH.connectivity[~(failed | scab)]), assume_unique=True)]
                  == WALL)
    loose = np.setdiff1d(inner, np.unique(MESH.connectivity[~(failed | scab)]))
    assert loose.size and np.all(cat[loose] == FRAGMENT)
    v = still()
    assert verdict(failed, velocity=v)[0] == wall.NO_PERFORATION          # not moving away: still in place
    v[loose, 1] = 0.02                                                    # moving off at 200 m/s
    assert verdict(failed, velocity=v)[0] == wall.DETACHED_SPALL
    v[loose, 1] = -0.02                                                   # moving back into the wall
    assert verdict(failed, velocity=v)[0] == wall.NO_PERFORATION
    m = wall.measures(MESH, failed, eroded, still())
    assert m["spall_mass_g"] == pytest.approx((failed.sum() + scab.sum()) * 2.703 * 0.1 ** 3)


def test_rear_material_leaving_faster_than_escape_perforates():
    failed = field([(1, 3, 3), (1, 2, 3)])                       # failed at the rear, no through path
    v = still()
    node = np.intersect1d(MESH.connectivity[field([(1, 3, 3)])], MESH.face_nodes("rear").ravel())[0]
    v[node, 1] = 0.5 * ESCAPE
    assert verdict(failed, velocity=v)[0] != wall.PERFORATION
    v[node, 1] = 2.0 * ESCAPE
    v_, evidence = verdict(failed, velocity=v)
    assert v_ == wall.PERFORATION and evidence["escaping_rear_nodes"] == 1


def test_orphan_nodes():
    eroded = field([(i, j, k) for i in range(2) for j in range(4) for k in (3, 4)])
    cat = node_categories(MESH, np.zeros_like(eroded), eroded)
    # the nodes inside the eroded column (x ≤ 0.1, z = 0 between its two element rows) belong to nothing else
    orphan = np.flatnonzero(cat == ORPHAN)
    assert orphan.size == 2 * 5
    np.testing.assert_allclose(MESH.coordinates[orphan, 2], 0.0, atol=1e-12)
    assert np.all(MESH.coordinates[orphan, 0] <= 0.1 + 1e-12)
    assert verdict(np.zeros_like(eroded), eroded)[0] == wall.PERFORATION
