"""The legacy DYNA3D wall deck, as DYNGEN writes it (Fahrenthold 1994, App. G; header App. D).

The deck, in order:

1. Title card: the title in columns 1–72, then ``88 large`` (App. D).
2. Counts card: number of materials (2, i5), nodes and solid elements (i8, the
   "large" format of card 1), and twelve zero counts (i5) (App. D:
   ``2 25763 20001 0 0 0 0 0 0 0 0 0 0 0 0``; the column widths are not legible).
3. ``control_cards``, verbatim.  The other control cards of App. D (termination
   time, output intervals, the number of momentum-deposition cards — apparently
   the ``1619`` there) are illegible in the report's OCR and depend on the DYNA3D
   version, so the caller supplies them.
4. Material cards (App. D), each material a card ``(2i5, e10.3)`` number, type,
   density, a title card and six property cards: material 1 type 13 (isotropic
   elastic–plastic with failure) ``e-p w/failure`` with G, σ_y, E_h, ε_f, p_cut, K
   in the order App. D prints them; material 2 type 1 ``elastic``, density 1.0,
   E 1.0, ν 0.3 — the backing element's.
5. Nodes ``(i8, i5, 3e20.8)``: number, constraint code, x, y, z, in DYNGEN's
   numbering (:class:`WallGrid`); codes 0 free, 1 x, 2 y, 3 z, 4 x y, 5 y z,
   6 z x, 7 all, from :meth:`WallGrid.constrained_dofs` (``clamped_edges``: 7 on
   the three outer edges).  In the OCR a ``go to 761`` stands before the edge
   codes without a comment mark; the same OCR drops the ``c`` of commented-out
   debug lines elsewhere (DCELEM's single-cell filter), and docs/theory/debris.md and the
   report's half model (symmetry plane x = xdmin) want the edge codes, so they
   are written.  Then the 8 nodes of the
   backing element, code 0: the 1 cm cube x ∈ [xd, xd + 1], y ∈ [yd − 2, yd − 1],
   z ∈ [zd, zd + 1] at the wall grid's lower corner (xd, yd, zd), nodes 1–4 on
   y = yd − 1.  (The listing writes ``nnode = ... + 1`` and ``x(1)`` for these
   eight nodes: OCR of the loop index ``l``.)
6. Elements ``(i8, i5, 8i8)``: number, material 1, nodes n5 n6 n7 n8 n1 n2 n3 n4
   (:meth:`WallGrid.element_nodes`), then the backing element, material 2,
   nodes 1–8 in order.  Hence nx+1 · ny+1 · nz+1 + 8 nodes and nx·ny·nz + 1
   elements: 25763 and 20001 for App. C's 51 × 5 × 101 wall grid.
7. DYNGEN's five closing cards (formats 110 and 111)::

       "    1    1   11" / "    1    0" / "    1"
       "    1    1    2" + (idmax+2, idmax+1) in 2i8
       "    1    1" + backing nodes 4 3 2 1 in 4i8

   reproduced as printed; the report does not say what they define (the
   backing element's face as a segment of some interface).  DCPOST counts these
   ``8 + 1 + 5`` lines after the mesh (``ncnt``), which confirms the layout.
8. Momentum-deposition cards as DCPOST appends them ``(i8, 4e10.3)``: element
   (face element + 1, the front-layer solid), px, py, pz, time — one card per
   :class:`WallDeposition` record (DCPOST sums each element's records into one
   card; sum them beforehand for that).

Coordinates: DYNGEN writes the wall nodes at ``(i−1) Δx`` etc. from 0, not from
xdmin (the deposition grid is matched by element number, so only the picture
shifts; the backing element does use xdmin).  The default writes the wall grid's
own coordinates; ``legacy_origin=True`` reproduces DYNGEN.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from impactdyn.materials import AL_6061_T6_MAT13, Mat13Card
from impactdyn.wallgrid import WallDeposition, WallGrid
from impactdyn.io._fortran import format_e, format_i
from impactdyn._runfolder import atomic_output

#: DYNA3D translational constraint code for fixed (x, y, z), indexed by 4 fx + 2 fy + fz.
_CODE = np.array([0, 3, 2, 5, 1, 6, 4, 7])
#: Backing-element node offsets from the wall's lower corner (x, y, z), cm, nodes 1..8 (DYNGEN).
_BACKING = np.array([[0, -1, 0], [1, -1, 0], [1, -1, 1], [0, -1, 1],
                     [0, -2, 0], [1, -2, 0], [1, -2, 1], [0, -2, 1]], dtype=float)


def write_dyna3d_deck(path: str | Path, wall: WallGrid, material: Mat13Card = AL_6061_T6_MAT13,
                      deposition: WallDeposition | None = None, *,
                      title: str = "Debris Cloud Wall Impact Model", control_cards: Sequence[str] = (),
                      clamped_edges: bool = False, legacy_origin: bool = False) -> None:
    """Write the DYNA3D deck of ``wall`` (layout in the module docstring), atomically."""
    if deposition is not None:
        deposition.check_fits(wall)
    lines = [f"{title[:72]:<72s}88 large",
             format_i([2], 5) + format_i([wall.n_nodes + 8, wall.n_elements + 1], 8) + format_i(np.zeros(12), 5),
             *control_cards,
             *_material_cards(1, 13, material.density, "e-p w/failure",
                              [material.shear_modulus, material.yield_stress, material.hardening_modulus,
                               material.failure_strain, material.failure_pressure, material.bulk_modulus]),
             *_material_cards(2, 1, 1.0, "elastic", [1.0, 0.3])]
    corner = np.array([wall.x[0], wall.y[0], wall.z[0]])
    xyz = wall.node_coordinates() - (corner if legacy_origin else 0.0)
    fixed = wall.constrained_dofs(clamped_edges).astype(int)
    codes = _CODE[fixed @ (4, 2, 1)]
    n_wall = wall.n_nodes
    numbers = np.arange(1, n_wall + 9)
    lines += _node_lines(numbers, np.concatenate([codes, np.zeros(8, int)]),
                         np.concatenate([xyz, corner + _BACKING]))
    backing = np.arange(n_wall + 1, n_wall + 9)
    conn = np.concatenate([wall.element_nodes(), backing[None, :]])
    mats = np.concatenate([np.ones(wall.n_elements, int), [2]])
    lines += [format_i([e], 8) + format_i([m], 5) + format_i(c, 8)
              for e, m, c in zip(range(1, len(conn) + 1), mats, conn)]
    idmax = wall.x.size
    lines += ["    1    1   11", "    1    0", "    1",
              "    1    1    2" + format_i([idmax + 2, idmax + 1], 8),
              "    1    1" + format_i(backing[3::-1], 8)]
    if deposition is not None:
        lines += [format_i([e + 1], 8) + format_e([*p, t], 10, 3)
                  for e, p, t in zip(deposition.element, deposition.impulse, deposition.time)]
    with atomic_output(path) as tmp:
        tmp.write_text("\n".join(lines) + "\n", encoding="ascii")


def _material_cards(number: int, mat_type: int, density: float, name: str, props: Sequence[float]) -> list[str]:
    """Material card, title card and the six property cards (blank where unused)."""
    cards = [props[n] if n < len(props) else None for n in range(6)]
    return [format_i([number, mat_type], 5) + f"{density:10.3e}", name] + \
           ["" if v is None else f"{v:10.3e}" for v in cards]


def _node_lines(numbers: np.ndarray, codes: np.ndarray, xyz: np.ndarray) -> list[str]:
    coords = format_e(xyz, 20, 8)
    return [format_i([n], 8) + format_i([c], 5) + coords[60 * r:60 * (r + 1)]
            for r, (n, c) in enumerate(zip(numbers, codes))]
