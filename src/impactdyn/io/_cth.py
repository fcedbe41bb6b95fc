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

Indices i, j, k are 1-based cell indices of the grid, l the tetrahedron 1…5.  The
writer takes the packages' arrays; :func:`impactdyn.debris.cth_packages` computes
them from the particles (density, velocity and the shrunk tetrahedron of CTHOUT).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from impactdyn._errors import InputError
from impactdyn._runfolder import atomic_output
from impactdyn.io._fortran import parse_real, read_lines


def write_cth_packages(path: str | Path, index: np.ndarray, density: np.ndarray, velocity_cm_s: np.ndarray,
                       corners: np.ndarray, *, material: int = 1, numsub: int = 49) -> None:
    """Write one package per row, the layout :func:`read_cth_packages` reads back.

    index : (n, 4) int — 1-based cell indices i, j, k and tetrahedron l (1…5).
    density : (n,) — ρ_out, g/cm³.
    velocity_cm_s : (n, 3) — cm/s, CTH's unit.
    corners : (n, 4, 3) — the three base points and the vertex of the pyramid, cm.
    """
    index, density = np.asarray(index), np.asarray(density)
    velocity_cm_s, corners = np.asarray(velocity_cm_s), np.asarray(corners)
    n = len(index)
    if index.shape != (n, 4) or density.shape != (n,) or velocity_cm_s.shape != (n, 3) or corners.shape != (n, 4, 3):
        raise ValueError(f"write_cth_packages: shapes index {index.shape}, density {density.shape}, velocity "
                         f"{velocity_cm_s.shape}, corners {corners.shape}; expected (n, 4), (n,), (n, 3), (n, 4, 3)")

    def xyz(p) -> str:
        return ", ".join(f"{q:15.6e}" for q in p)

    lines = []
    for (i, j, k, tet), rho, v, c in zip(index, density, velocity_cm_s, corners):
        lines += [f"     package {i:3d}, {j:3d}, {k:3d}, {tet:3d}",
                  f"       material {material:3d}", f"       numsub {numsub:3d}",
                  f"       density = {rho:20.8e}",
                  f"       xvel = {v[0]:20.8e}", f"       yvel = {v[1]:20.8e}", f"       zvel = {v[2]:20.8e}",
                  "       insert pyramid",
                  *(f"         point = {xyz(c[m])}" for m in range(3)),
                  f"         vertex = {xyz(c[3])}",
                  "       endinsert", "     endpackage"]
    with atomic_output(path) as tmp:
        tmp.write_text("\n".join(lines) + "\n", encoding="ascii")


def read_cth_packages(path: str | Path) -> dict[str, np.ndarray]:
    """Read packages written by :func:`write_cth_packages`: index ``(n, 4)``, density ``(n,)``,
    velocity ``(n, 3)`` (cm/s) and corners ``(n, 4, 3)`` (cm)."""
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
