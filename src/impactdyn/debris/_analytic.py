"""An analytic debris cloud on a HydroGrid: the debris stage without a hydrocode.

Behind a Whipple bumper the debris of a perforating projectile forms an
expanding, translating bubble whose material lies in a thin shell, densest at the
front (Piekutowski 1996; the report's Figures 9–18).  The model here: a spherical
shell of radius R and thickness δ around the centre c, cut to a cap of half-angle
α about the flight direction n̂, filled with material of density ρ and void
fraction φ (fragments), moving with the homologous (self-similar) velocity field

    v(x) = v_c + v_e (x − c) / R,

i.e. translating at v_c and expanding so that the shell's mid-surface grows at
v_e.  Units cm, g, µs.  The grid covers the half model x ≥ 0 (the symmetry plane
of the oblique impact, docs/theory/shield.md).

Cells are filled by sub-sampling: each cell is split into ``subsamples³``
points; the fraction f inside the shell gives the cell's material, mass
f (1 − φ) ρ V and void fraction 1 − f (1 − φ), and its velocity is the mean of v
over the points inside.
"""

from __future__ import annotations

from typing import Annotated

import numpy as np
from pydantic import Field

from impactdyn._config import MAX_REACH, NonNegative, Positive, Section, checked, rule
from impactdyn._errors import InputError
from impactdyn.hydrogrid import DC3D_CELL_CM, HydroGrid, check_cells

# A vector of three components; tuples, lists and arrays alike.
Vector = Annotated[tuple[float, float, float], Field(strict=False)]


def check_shell(radius: float, thickness: float, velocity, names: tuple[str, str, str] = (
        "radius", "thickness", "velocity")) -> None:
    """The shell is no thicker than its radius and moves (a validator's ValueError naming ``names`` otherwise).

    :class:`ShellCloud`'s rule, called by the case's ``[grid.shell]`` table too.
    """
    if thickness > radius:
        raise ValueError(f"{names[1]} = {thickness} exceeds {names[0]} = {radius}")
    if not np.linalg.norm(velocity) > 0:
        raise ValueError(f"{names[2]} = {list(velocity)}: the cloud must move (its direction is the cap's axis)")


class ShellCloud(Section):
    """Parameters of the analytic cloud (module docstring); cm, µs, g/cm³, cm/µs.

    centre (3,): c at hand-off; velocity (3,): v_c, not zero; expansion_velocity: v_e;
    radius: R of the shell's outer surface; thickness: δ ≤ R (:func:`check_shell`);
    cap_half_angle_deg: α (180 = the whole shell); density: ρ; void_fraction: φ;
    sound_speed: for the grid's c field; time: the hand-off time.  The one home of
    these defaults and bounds (the case's ``[grid.shell]`` table takes them with
    :func:`~impactdyn._config.field_of`).
    """

    centre: Vector
    velocity: Vector
    expansion_velocity: NonNegative
    radius: Positive
    thickness: Positive
    cap_half_angle_deg: Annotated[float, Field(gt=0, le=180)] = 180.0
    density: Positive = 2.703
    void_fraction: Annotated[float, Field(ge=0, lt=1)] = 0.5
    sound_speed: NonNegative = 0.524
    time: float = 0.0

    _shell = rule(check_shell, "radius", "thickness", "velocity")

    def velocity_at(self, x: np.ndarray) -> np.ndarray:
        """v(x) = v_c + v_e (x − c)/R for points ``(..., 3)``."""
        return np.asarray(self.velocity) + self.expansion_velocity * (x - np.asarray(self.centre)) / self.radius

    def contains(self, x: np.ndarray) -> np.ndarray:
        """Points ``(..., 3)`` inside the shell's cap, bool ``(...)``."""
        d = x - np.asarray(self.centre)
        r = np.linalg.norm(d, axis=-1)
        n = np.asarray(self.velocity) / np.linalg.norm(self.velocity)
        with np.errstate(invalid="ignore", divide="ignore"):
            cos_angle = np.where(r > 0, d @ n / r, 1.0)
        return ((r <= self.radius) & (r >= self.radius - self.thickness)
                & (cos_angle >= np.cos(np.radians(self.cap_half_angle_deg)) - 1e-15))


def grid_box(centre, radius: float, cell_size: float,
             names: tuple[str, str, str] = ("centre", "radius", "cell_size")) -> tuple[np.ndarray, tuple[int, ...]]:
    """The lower corner and the cell counts of :func:`shell_cloud_grid`'s grid, if its cells are no
    wider than the shell, this machine holds them and their nodes resolve them (an
    :class:`InputError` naming ``names`` otherwise).

    The grid covers the half (x ≥ 0) bounding box of the sphere of ``radius`` about ``centre``.
    """
    c = np.asarray(centre, dtype=float)
    lo = np.array([max(0.0, c[0] - radius), c[1] - radius, c[2] - radius])
    hi = c + radius
    if not cell_size <= 2.0 * radius:
        raise InputError(f"{names[2]} = {cell_size:g} exceeds the shell's diameter 2 {names[1]} = {2.0 * radius:g}: "
                         "the grid would not resolve the cloud")
    reach = max(np.abs(lo).max(), np.abs(hi).max()) / cell_size
    if not reach <= MAX_REACH:
        raise InputError(f"{names[0]} = {c.tolist()}, {names[1]} = {radius:g}: the grid reaches {reach:.4g} cells "
                         f"of {names[2]} = {cell_size:g} from the origin, more than {MAX_REACH} (its nodes "
                         "would not resolve the cells)")
    n = np.maximum(1, np.ceil((hi - lo) / cell_size - 1e-9).astype(int))
    check_cells(f"{names[2]} = {cell_size:g} for the {radius:g} cm shell", n)
    return lo, tuple(int(v) for v in n)


@checked
def shell_cloud_grid(cloud: ShellCloud, cell_size: Positive = DC3D_CELL_CM,
                     subsamples: Annotated[int, Field(ge=1, le=8)] = 3) -> HydroGrid:
    """The cloud on a uniform cell-centred HydroGrid covering its half (x ≥ 0) bounding box.

    cell_size: the cubic cells' edge, cm; subsamples: points per cell edge (module docstring).
    """
    lo, shape = grid_box(cloud.centre, cloud.radius, cell_size)
    x, y, z = (lo[d] + cell_size * np.arange(shape[d] + 1) for d in range(3))
    s = (np.arange(subsamples) + 0.5) / subsamples * cell_size  # sub-sample offsets in a cell
    inside = np.zeros(shape)
    v_sum = np.zeros(shape + (3,))
    # one z-plane of cells at a time keeps the sub-sample arrays small
    for kz in range(shape[2]):
        pts = np.stack(np.meshgrid(
            (x[:-1, None] + s).ravel(), (y[:-1, None] + s).ravel(), (z[kz] + s),
            indexing="ij"), axis=-1)  # (nx·m, ny·m, m, 3)
        m = subsamples
        pts = pts.reshape(shape[0], m, shape[1], m, m, 3)
        hit = cloud.contains(pts)
        inside[:, :, kz] = hit.sum(axis=(1, 3, 4))
        v_sum[:, :, kz] = (cloud.velocity_at(pts) * hit[..., None]).sum(axis=(1, 3, 4))
    frac = inside / subsamples**3
    with np.errstate(over="ignore"):  # too large a cell for its mass to be a number: HydroGrid refuses it
        volume = np.float64(cell_size) ** 3
    solid = frac * (1.0 - cloud.void_fraction)
    with np.errstate(invalid="ignore", divide="ignore"):
        velocity = np.where(inside[..., None] > 0, v_sum / inside[..., None], 0.0)
    has = solid > 0
    return HydroGrid(
        x=x, y=y, z=z,
        density=np.where(has, cloud.density, 0.0),
        void_fraction=1.0 - solid,
        mass=solid * cloud.density * volume,
        pressure=np.zeros(shape),
        temperature=np.where(has, 298.0, 0.0),
        specific_energy=np.zeros(shape),
        sound_speed=np.where(has, cloud.sound_speed, 0.0),
        velocity=velocity,
        staggered=False,
        time=cloud.time,
    )
