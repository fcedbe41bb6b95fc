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
from impactdyn.io._fortran import parse_int, parse_real, read_lines


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
    velocity ``(n, 3)`` (cm/s) and corners ``(n, 4, 3)`` (cm).

    Each package needs its four indices (cells from 1, tetrahedron 1…5), one density, the
    three velocities and four points of three coordinates; an :class:`InputError` names the
    line of the value that is wrong, or of the package that lacks one.
    """
    path = Path(path)
    packages: list[dict] = []
    for no, line in enumerate(read_lines(path), start=1):
        key, _, value = line.strip().partition("=" if "=" in line else " ")
        key = key.strip()
        if key not in ("package", "density", "xvel", "yvel", "zvel", "point", "vertex"):
            continue
        if key != "package" and not packages:
            raise InputError(f"{path}:{no}: {key} outside a package")
        try:
            if key == "package":
                index = [parse_int(t) for t in value.split(",")]  # CTH's Fortran integers: 32 bits
                if len(index) != 4 or not (all(1 <= i < 2**31 for i in index[:3]) and 1 <= index[3] <= 5):
                    raise ValueError(f"expected cell indices i, j, k >= 1 and a tetrahedron 1..5, got {value.strip()}")
                packages.append({"line": no, "index": index, "density": [], "velocity": {}, "corners": []})
            elif key == "density":
                packages[-1]["density"].append(parse_real(value))
            elif key in ("xvel", "yvel", "zvel"):
                packages[-1]["velocity"][key] = parse_real(value)
            else:
                point = [parse_real(t) for t in value.split(",")]
                if len(point) != 3:
                    raise ValueError(f"expected x, y, z, got {value.strip()}")
                packages[-1]["corners"].append(point)
        except ValueError as err:
            raise InputError(f"{path}:{no}: cannot read {line.strip()!r}: {err}") from None
    for p in packages:
        if len(p["density"]) != 1 or len(p["velocity"]) != 3 or len(p["corners"]) != 4:
            raise InputError(f"{path}:{p['line']}: the package has {len(p['density'])} densities, "
                             f"{len(p['velocity'])} of xvel, yvel, zvel and {len(p['corners'])} points and vertices; "
                             "expected 1, 3 and 4")
    return {"index": np.array([p["index"] for p in packages], dtype=int).reshape(-1, 4),
            "density": np.array([p["density"][0] for p in packages]),
            "velocity": np.array([[p["velocity"][k] for k in ("xvel", "yvel", "zvel")] for p in packages]
                                 ).reshape(-1, 3),
            "corners": np.array([p["corners"] for p in packages]).reshape(-1, 4, 3)}
