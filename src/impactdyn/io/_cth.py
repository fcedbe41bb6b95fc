"""CTH rezone packages, as DC3D's CTHOUT writes them for itype = 1 (Fahrenthold 1994, App. G).

One package per particle, inserted into a CTH mesh as a pyramid (tetrahedron)::

     package   i,   j,   k,   l
       material   1
       numsub  49
       density =   ρ_out
       xvel = … / yvel = … / zvel = …           (cm/s)
       insert pyramid
         point = x, y, z    (three times)
         vertex = x, y, z
       endinsert
     endpackage

ρ_out = ρ_ref / det F, and the vertices are c + s F (x_k⁰ − c⁰) with
s = ((1 − φ) ρ/ρ_ref)^{1/3}, which shrinks the tetrahedron so that ρ_out times
its volume is the particle's mass (the listing's c3).  (The listing skips the
``+ c`` with a ``go to 301`` whose label is commented out in the OCR; a pyramid
about the origin is meaningless, so the centroid is added.)  Indices i, j, k
are 1-based cell indices of the grid, l the tetrahedron 1…5.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from impactdyn import units
from impactdyn.debris._deposit import arrival_points
from impactdyn.debris._particle import F_SLICE, P_SLICE
from impactdyn.io._registry import atomic_output


def write_cth_packages(path: str | Path, cloud, states: np.ndarray, rho_ref: float, *,
                       material: int = 1, numsub: int = 49) -> None:
    """Write one package per particle of ``cloud`` (a :class:`ParticleCloud`) in ``states (N, 33)``."""
    detF = np.linalg.det(states[:, F_SLICE].reshape(-1, 3, 3))
    v = units.cm_us_to_cm_s(states[:, P_SLICE] / cloud.mass[:, None])
    corners = arrival_points(states, cloud.vertices, np.cbrt((1.0 - cloud.void_fraction) * cloud.density_ratio))

    def xyz(p) -> str:
        return ", ".join(f"{q:15.6e}" for q in p)

    lines = []
    for n in range(len(cloud)):
        i, j, k = cloud.cell[n] + 1
        lines += [f"     package {i:3d}, {j:3d}, {k:3d}, {cloud.tet[n] + 1:3d}",
                  f"       material {material:3d}", f"       numsub {numsub:3d}",
                  f"       density = {rho_ref / detF[n]:20.8e}",
                  f"       xvel = {v[n, 0]:20.8e}", f"       yvel = {v[n, 1]:20.8e}", f"       zvel = {v[n, 2]:20.8e}",
                  "       insert pyramid",
                  *(f"         point = {xyz(corners[n, m])}" for m in range(3)),
                  f"         vertex = {xyz(corners[n, 3])}",
                  "       endinsert", "     endpackage"]
    with atomic_output(path) as tmp:
        tmp.write_text("\n".join(lines) + "\n", encoding="ascii")


def read_cth_packages(path: str | Path) -> dict[str, np.ndarray]:
    """Read packages written by :func:`write_cth_packages`: index ``(n, 4)``, density ``(n,)``,
    velocity ``(n, 3)`` (cm/s) and corners ``(n, 4, 3)`` (cm)."""
    from impactdyn._errors import InputError
    from impactdyn.io._fortran import parse_real, read_lines

    path = Path(path)
    index, density, velocity, corners = [], [], [], []
    for no, line in enumerate(read_lines(path), start=1):
        key, _, value = line.strip().partition("=" if "=" in line else " ")
        key = key.strip()
        try:
            if key == "package":
                index.append([int(t) for t in value.split(",")])
                velocity.append([])
                corners.append([])
            elif key == "density":
                density.append(parse_real(value))
            elif key in ("xvel", "yvel", "zvel"):
                velocity[-1].append(parse_real(value))
            elif key in ("point", "vertex"):
                corners[-1].append([parse_real(t) for t in value.split(",")])
        except (ValueError, IndexError):
            raise InputError(f"{path}:{no}: cannot read {line.strip()!r}") from None
    return {"index": np.array(index, dtype=int).reshape(-1, 4), "density": np.array(density),
            "velocity": np.array(velocity).reshape(-1, 3), "corners": np.array(corners).reshape(-1, 4, 3)}
