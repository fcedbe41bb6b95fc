"""Fragments of the debris cloud: friends-of-friends over the intact SPH particles (units cm, g, µs).

After the shield impact a fragment is a connected region of intact material.
Two intact particles p, q are linked when

    |r_p − r_q| < b                                          (b: the link length, cm)

and the fragments are the connected components of this link graph
(friends-of-friends, Davis, Efstathiou, Frenk & White 1985, ApJ 292, 371). The links are the
pairs of a k-d tree search (``scipy.spatial.cKDTree.query_pairs``) and the
components come from ``scipy.sparse.csgraph.connected_components``: O(N log N)
and O(N + links). Damaged particles belong to no fragment: they are the fine spray. An
intact particle with no intact neighbour is a fragment of one particle (callers
filter by size). The usual choice b ≈ 1.5 Δ (Δ the initial particle spacing)
links the 18 nearest lattice neighbours (distances Δ, √2 Δ), and one missing (or
damaged) layer of particles separates: across it the nearest are 2 Δ apart.

Per fragment f with particles p (mass m, position r, velocity v, solid volume V =
m/ρ₀, so that the size does not depend on how far the material has expanded)::

    M = Σ m,   r_c = Σ m r / M,   v_c = Σ m v / M,   d = r − r_c,   u = v − v_c
    D = (6 Σ V / π)^{1/3}                                    (equivalent-sphere diameter)

Each particle stands for a small sphere of its solid volume, radius
a = (3V/4π)^{1/3}, with the second moment a²/5 per axis. The second-moment
tensor of the fragment and its inertia tensor are::

    C = Σ m d dᵀ + Σ m a²/5 𝟙,     I = tr(C) 𝟙 − C = Σ m (|d|² 𝟙 − d dᵀ) + Σ (2/5) m a² 𝟙

``axes_cm``: the uniform ellipsoid with the same mass and the same C has
C = M/5 diag(a₁², a₂², a₃²), so its principal half-lengths are

    a_k = √(5 λ_k(C) / M),   sorted a₁ ≥ a₂ ≥ a₃

(a box of sides L_x, L_y, L_z filled by a lattice comes out with the box's inertia
M/12 (L_y² + L_z²), …, to 0.08 Δ²/L²: the sphere's a²/5 = 0.077 Δ² per axis against
the lattice cell's Δ²/12 = 0.083 Δ²; without the particles' own term it would be
Δ²/L² off).

``spin``: the angular momentum about the centre of mass, L = Σ m d × u, with each
particle's own sphere turning with the fragment, gives I ω = L + Σ (2/5) m a² ω, i.e.

    I_pts ω = L,    I_pts = Σ m (|d|² 𝟙 − d dᵀ)

the least-squares rigid rotation (minimises Σ m |u − ω × d|²): for a rigid body
v = v_c + ω × d it returns ω to round-off. The SPH particles carry no spin of
their own, so L has no term of it. Along a principal direction where I_pts has no
inertia (a one-particle fragment; particles on a line, the direction of the line;
eigenvalue ≤ 10⁻⁹ of the largest eigenvalue of I) the rotation cannot be seen in
the velocities and its component is reported as 0.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, fields
from pathlib import Path

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from impactdyn._config import Positive, checked
from impactdyn._errors import InputError
from impactdyn.shield._melt import solid_particles

#: A principal direction of I_pts with an eigenvalue at most this fraction of I's largest is not
#: resolved by the particles (module docstring, ``spin``); its spin component is reported as 0.
UNRESOLVED = 1e-9

_FIELDS = {"mass": (), "position": (3,), "velocity": (3,), "spin": (3,), "diameter_cm": (), "axes_cm": (3,),
           "count": (), "from_failed": ()}
_DTYPES = {"count": np.int64, "from_failed": np.bool_}


@dataclass(frozen=True, eq=False)
class Fragments:
    """The fragments of a particle set, largest mass first (arrays stored read-only).

    Attributes
    ----------
    mass : (F,)
        M = Σ m, g.
    position : (F, 3)
        Centre of mass r_c, cm.
    velocity : (F, 3)
        Centre-of-mass velocity v_c, cm/µs.
    spin : (F, 3)
        Angular velocity ω about the centre of mass, rad/µs (module docstring).
    diameter_cm : (F,)
        Equivalent-sphere diameter (6 Σ V / π)^{1/3} of the solid volume, cm.
    axes_cm : (F, 3)
        Principal half-lengths a₁ ≥ a₂ ≥ a₃ of the uniform ellipsoid with the fragment's
        second moments, cm: the shape (a₃/a₁ = 1 a sphere, ≪ 1 a plate or a rod).
    count : (F,) int
        Particles in each fragment.
    ptr : (F + 1,) int, members : (M,) int
        The particle indices of fragment f are ``members[ptr[f]:ptr[f + 1]]`` (ascending), M = Σ count.
    from_failed : (F,) bool, optional
        True: a fragment of failed material, sized by Grady's energy balance
        (:func:`impactdyn.shield.grady_fragments`); False (the default): an intact region.
    """

    mass: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    spin: np.ndarray
    diameter_cm: np.ndarray
    axes_cm: np.ndarray
    count: np.ndarray
    ptr: np.ndarray
    members: np.ndarray
    from_failed: np.ndarray | None = None

    def __post_init__(self) -> None:
        n = np.shape(self.mass)[0] if np.ndim(self.mass) == 1 else -1
        if self.from_failed is None:
            object.__setattr__(self, "from_failed", np.zeros(max(n, 0), dtype=bool))
        for name, tail in _FIELDS.items():
            a = np.array(getattr(self, name), dtype=_DTYPES.get(name, np.float64))
            if a.shape != (n,) + tail:
                raise InputError(f"Fragments.{name}: shape {a.shape}, expected {(n,) + tail}")
            a.flags.writeable = False
            object.__setattr__(self, name, a)
        for name in ("ptr", "members"):
            a = np.array(getattr(self, name), dtype=np.int64)
            a.flags.writeable = False
            object.__setattr__(self, name, a)
        if self.ptr.shape != (n + 1,) or self.ptr[0] != 0 or np.any(np.diff(self.ptr) != self.count) \
                or self.members.shape != (self.ptr[-1],):
            raise InputError("Fragments.ptr, members: not the CSR index of the fragments' particles")

    def __len__(self) -> int:
        return self.mass.size

    def total_mass(self) -> float:
        """Σ M, g."""
        return float(self.mass.sum())

    def momentum(self) -> np.ndarray:
        """Σ M v_c = Σ m v over the fragments' particles, g·cm/µs, (3,)."""
        return self.mass @ self.velocity

    def indices(self, f: int) -> np.ndarray:
        """The particle indices of fragment ``f`` (ascending)."""
        return self.members[self.ptr[f]:self.ptr[f + 1]]

    def largest(self, n: int) -> "Fragments":
        """The ``n`` most massive fragments (all of them if there are fewer)."""
        n = max(0, min(int(n), len(self)))
        values = {f.name: getattr(self, f.name)[:n] for f in fields(self) if f.name in _FIELDS}
        return Fragments(**values, ptr=self.ptr[:n + 1], members=self.members[:self.ptr[n]])

    def select(self, keep) -> "Fragments":
        """The fragments where the boolean mask ``keep`` (F,) is true, in their order."""
        keep = np.asarray(keep, dtype=bool)
        if keep.shape != (len(self),):
            raise InputError(f"Fragments.select: a mask of shape {keep.shape}, expected ({len(self)},)")
        values = {f.name: getattr(self, f.name)[keep] for f in fields(self) if f.name in _FIELDS}
        members = [self.indices(f) for f in np.flatnonzero(keep)]
        return Fragments(**values, ptr=np.concatenate([[0], np.cumsum(self.count[keep])]),
                         members=np.concatenate(members) if members else np.zeros(0, dtype=np.int64))

    def __repr__(self) -> str:
        top = f", largest {self.mass[0]:.6g} g" if len(self) else ""
        return f"Fragments(n={len(self)}, mass={self.total_mass():.6g} g{top})"


def _array(name: str, value, tail: tuple[int, ...], n: int | None) -> np.ndarray:
    a = np.asarray(value, dtype=np.float64)
    if a.ndim != 1 + len(tail) or a.shape[1:] != tail or (n is not None and a.shape[0] != n):
        expected = ("N" if n is None else str(n),) + tuple(map(str, tail))
        raise InputError(f"find_fragments: {name}: shape {a.shape}, expected ({', '.join(expected)})")
    if not np.all(np.isfinite(a)):
        raise InputError(f"find_fragments: {name}: not finite")
    return a


@checked
def find_fragments(position, velocity, mass, volume, intact, *, link_length_cm: Positive) -> Fragments:
    """The fragments of the intact particles by friends-of-friends (module docstring).

    Parameters
    ----------
    position, velocity : (N, 3)
        cm, cm/µs.
    mass : (N,)
        g, > 0.
    volume : (N,)
        Solid volume m/ρ₀ of each particle, cm³, > 0.
    intact : (N,) bool
        Undamaged particles; the others belong to no fragment.
    link_length_cm : float
        b: intact particles closer than b are in the same fragment.

    Returns
    -------
    Fragments
        Sorted by mass, largest first (equal masses: by their lowest particle index).

    Raises
    ------
    InputError
        Naming the argument: a shape that does not fit, a value not finite, a mass or
        volume ≤ 0, an ``intact`` that is not a boolean mask, b not finite or ≤ 0.
    """
    position = _array("position", position, (3,), None)
    n = position.shape[0]
    velocity = _array("velocity", velocity, (3,), n)
    mass = _array("mass", mass, (), n)
    volume = _array("volume", volume, (), n)
    for name, a in (("mass", mass), ("volume", volume)):
        if np.any(a <= 0):
            raise InputError(f"find_fragments: {name}: every value must be > 0")
    intact = np.asarray(intact)
    if intact.dtype != bool or intact.shape != (n,):
        raise InputError(f"find_fragments: intact: expected a boolean mask of shape ({n},), "
                         f"got {intact.dtype} of shape {intact.shape}")
    idx = np.flatnonzero(intact)
    return fragments_of_groups(position, velocity, mass, volume, idx,
                               linked_groups(position[idx], float(link_length_cm)))


def with_images(vectors: np.ndarray) -> np.ndarray:
    """(2N, 3): the vectors (N, 3) of a half model, then their mirror images across the plane x = 0."""
    return np.concatenate([vectors, vectors * np.array([-1.0, 1.0, 1.0])])


def linked_groups(x: np.ndarray, b: float) -> np.ndarray:
    """(k,) int: the friends-of-friends group of each point of x (k, 3): the connected components of the
    links |x_p − x_q| < b (module docstring), numbered from 0."""
    k = x.shape[0]
    if k == 0:
        return np.zeros(0, dtype=np.int64)
    pairs = cKDTree(x).query_pairs(b, output_type="ndarray")
    if len(pairs):  # query_pairs keeps distance ≤ b; the link is < b
        pairs = pairs[np.einsum("nd,nd->n", x[pairs[:, 0]] - x[pairs[:, 1]],
                                x[pairs[:, 0]] - x[pairs[:, 1]]) < b * b]
    graph = coo_matrix((np.ones(len(pairs), dtype=np.int8), (pairs[:, 0], pairs[:, 1])), shape=(k, k))
    return connected_components(graph, directed=False)[1].astype(np.int64)


def fragments_of_groups(position, velocity, mass, volume, idx: np.ndarray, group: np.ndarray, *,
                        from_failed: bool = False) -> Fragments:
    """The :class:`Fragments` whose particles are ``idx`` (k,) grouped by ``group`` (k,) ≥ 0 (a group
    number per particle; the numbers need not be consecutive): the module docstring's figures."""
    k = idx.size
    if k == 0:
        return Fragments(mass=np.empty(0), position=np.empty((0, 3)), velocity=np.empty((0, 3)),
                         spin=np.empty((0, 3)), diameter_cm=np.empty(0), axes_cm=np.empty((0, 3)),
                         count=np.empty(0, dtype=np.int64), ptr=np.zeros(1, dtype=np.int64),
                         members=np.empty(0, dtype=np.int64))
    _, label = np.unique(group, return_inverse=True)
    label = label.reshape(-1)
    n_frag = int(label.max()) + 1
    x = position[idx]
    m, v_p, V = mass[idx], velocity[idx], volume[idx]
    M = np.bincount(label, weights=m, minlength=n_frag)
    first = np.full(n_frag, k, dtype=np.int64)
    np.minimum.at(first, label, np.arange(k))
    order = np.lexsort((first, -M))  # heaviest first; ties by the lowest particle index
    rank = np.empty(n_frag, dtype=np.int64)
    rank[order] = np.arange(n_frag)
    label = rank[label]
    M = M[order]

    def total(q: np.ndarray) -> np.ndarray:  # Σ over each fragment's particles of q (k, …)
        flat = q.reshape(k, -1)
        return np.stack([np.bincount(label, weights=flat[:, j], minlength=n_frag)
                         for j in range(flat.shape[1])], axis=-1).reshape((n_frag,) + q.shape[1:])

    r_c = total(m[:, None] * x) / M[:, None]
    v_c = total(m[:, None] * v_p) / M[:, None]
    d = x - r_c[label]
    u = v_p - v_c[label]
    c_pts = total(m[:, None, None] * d[:, :, None] * d[:, None, :])  # Σ m d dᵀ, (F, 3, 3)
    own = total(m * (3.0 * V / (4.0 * np.pi)) ** (2.0 / 3.0) / 5.0)  # Σ m a²/5
    eye = np.eye(3)
    c_full = c_pts + own[:, None, None] * eye
    i_pts = np.trace(c_pts, axis1=1, axis2=2)[:, None, None] * eye - c_pts
    ang = total(m[:, None] * np.cross(d, u))  # L, (F, 3)

    lam, vec = np.linalg.eigh(i_pts)
    i_max = lam[:, -1] + 2.0 * own  # largest eigenvalue of I = I_pts + Σ (2/5) m a² 𝟙
    proj = np.einsum("fdk,fd->fk", vec, ang)
    resolved = lam > UNRESOLVED * i_max[:, None]
    coef = np.divide(proj, lam, out=np.zeros_like(proj), where=resolved)
    spin = np.einsum("fdk,fk->fd", vec, coef)

    axes = np.sqrt(5.0 * np.clip(np.linalg.eigvalsh(c_full)[:, ::-1], 0.0, None) / M[:, None])
    diameter = (6.0 * total(V) / np.pi) ** (1.0 / 3.0)
    count = np.bincount(label, minlength=n_frag)
    members = idx[np.argsort(label, kind="stable")]
    ptr = np.concatenate([[0], np.cumsum(count)])
    return Fragments(mass=M, position=r_c, velocity=v_c, spin=spin, diameter_cm=diameter, axes_cm=axes,
                     count=count, ptr=ptr, members=members, from_failed=np.full(n_frag, from_failed))


def join_fragments(*parts: Fragments) -> Fragments:
    """The fragments of ``parts`` (of one particle set, disjoint) in one record, largest mass first
    (equal masses: by their lowest particle index)."""
    values = {name: np.concatenate([getattr(p, name) for p in parts]) for name in _FIELDS}
    members = [p.indices(f) for p in parts for f in range(len(p))]
    first = np.array([m[0] if m.size else -1 for m in members], dtype=np.int64)
    order = np.lexsort((first, -values["mass"]))
    members = [members[f] for f in order]
    return Fragments(**{name: a[order] for name, a in values.items()},
                     ptr=np.concatenate([[0], np.cumsum(values["count"][order])]),
                     members=np.concatenate(members) if members else np.zeros(0, dtype=np.int64))


def cumulative_number(fragments: Fragments) -> tuple[np.ndarray, np.ndarray]:
    """The cumulative number N(≥ m) of fragments of mass at least m, at each fragment's mass.

    Returns ``(mass, n_at_least)``, both (F,), mass descending (g) and N non-decreasing;
    fragments of equal mass all get the count that includes every one of them.
    """
    m = np.asarray(fragments.mass)[np.argsort(-np.asarray(fragments.mass), kind="stable")]
    return m, np.searchsorted(-m, -m, side="right")


def cumulative_mass(fragments: Fragments, part: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The cumulative mass M(≥ m) in fragments of mass at least m, at each fragment's mass.

    ``part`` (F,): the share of each fragment's mass to count (g; e.g. its projectile material,
    :func:`origin_masses`); None: all of it.  Returns ``(mass, M_at_least)``, mass descending (g);
    fragments of equal mass all get the sum that includes every one of them.
    """
    mass = np.asarray(fragments.mass)
    order = np.argsort(-mass, kind="stable")
    m = mass[order]
    counted = np.cumsum((mass if part is None else np.asarray(part, float))[order])
    return m, counted[np.searchsorted(-m, -m, side="right") - 1] if m.size else counted


def origin_masses(fragments: Fragments, particle_mass: np.ndarray, projectile: np.ndarray) -> np.ndarray:
    """(F,) the mass of each fragment that was projectile material, g (the rest is the bumper's).

    particle_mass, projectile : (N,) the SPH particles' masses and which were the projectile's
    (``impactdyn.whipple``: those moving at t = 0).  A fragment's members are particles and, for a
    half model's fragments, their mirror images (indices N … 2N − 1), which share their particle's
    origin and mass.
    """
    n = len(particle_mass)
    if len(fragments) == 0:
        return np.zeros(0)
    member = np.asarray(fragments.members) % n
    weights = np.asarray(particle_mass, float)[member] * np.asarray(projectile, bool)[member]
    return np.add.reduceat(weights, np.asarray(fragments.ptr[:-1]))


FRAGMENT_COLUMNS = ("rank", "mass_g", "diameter_cm", "count", "x_cm", "y_cm", "z_cm",
                    "vx_cm_per_us", "vy_cm_per_us", "vz_cm_per_us", "spin_rad_per_us", "b_over_a", "c_over_a",
                    "origin", "projectile_share")
"""The columns of :func:`fragment_rows`: rank 1 the most massive; spin |ω|; b/a, c/a the ratios of ``axes_cm``;
origin "intact" (a region the cracks did not reach) or "failed" (failed material, :func:`grady_fragments`);
projectile_share the share of its mass that was projectile material (:func:`origin_masses`), blank where
not known."""


def fragment_rows(fragments: Fragments, n: int | None = None, from_projectile_g: np.ndarray | None = None
                  ) -> tuple[tuple[str, ...], list[list]]:
    """``(header, rows)`` of the ``n`` most massive fragments (all if None) for ``FolderWriter.write_csv``;
    ``from_projectile_g`` (F,) each fragment's projectile mass (:func:`origin_masses`), if known."""
    f = fragments if n is None else fragments.largest(n)
    spin = np.linalg.norm(f.spin, axis=1)
    ratio = f.axes_cm[:, 1:] / f.axes_cm[:, :1]
    share = [""] * len(f) if from_projectile_g is None else \
        [float(x) for x in np.asarray(from_projectile_g)[:len(f)] / f.mass]
    rows = [[i + 1, float(f.mass[i]), float(f.diameter_cm[i]), int(f.count[i]),
             *map(float, f.position[i]), *map(float, f.velocity[i]), float(spin[i]), *map(float, ratio[i]),
             "failed" if f.from_failed[i] else "intact", share[i]]
            for i in range(len(f))]
    return FRAGMENT_COLUMNS, rows


def plot_fragment_masses(path: str | os.PathLike, fragments: Fragments, *, projectile_mass_g: float | None = None,
                         from_projectile_g: np.ndarray | None = None,
                         title: str = "Fragments of the debris cloud") -> Path:
    """Two panels against fragment mass m (log): the cumulative number N(≥ m) (log); and the cumulative mass
    M(≥ m) in fragments at least that heavy (:func:`cumulative_mass`), split by origin where
    ``from_projectile_g`` (F,) gives each fragment's projectile mass (:func:`origin_masses`; the rest is
    the bumper's).  The five largest are listed beside the panels, where no data lies under them.

    With ``projectile_mass_g`` a second mass axis (top) gives m as a percentage of the projectile.
    Written atomically to ``path`` (format from the suffix); returns the path.
    """
    from impactdyn._plotting import save_figure

    if projectile_mass_g is not None and not (np.isfinite(projectile_mass_g) and projectile_mass_g > 0):
        raise InputError(f"plot_fragment_masses: projectile_mass_g = {projectile_mass_g!r}: must be finite and > 0")
    return save_figure(fragment_mass_figure(fragments, projectile_mass_g, from_projectile_g, title), path, dpi=110)


def fragment_mass_figure(fragments: Fragments, projectile_mass_g: float | None = None,
                         from_projectile_g: np.ndarray | None = None, title: str = "Fragments of the debris cloud"):
    """The figure of :func:`plot_fragment_masses` (its axes: N(≥ m), M(≥ m), then the list of the largest)."""
    from impactdyn._plotting import pyplot

    plt = pyplot()
    fig, (ax, ax_mass, ax_list) = plt.subplots(1, 3, figsize=(13, 4.8), width_ratios=(1, 1, 0.38),
                                               constrained_layout=True)
    ax_list.axis("off")
    m, count = cumulative_number(fragments)
    if len(m):
        ax.step(m, count, where="post", color="C0", label=f"{len(m)} fragment{'s' if len(m) != 1 else ''}, {m.sum():.4g} g")
        ax.plot(m, count, "o", ms=3, color="C0")
        top = fragments.largest(5)
        shares = (None if from_projectile_g is None else np.asarray(from_projectile_g)[:len(top)] / top.mass)
        lines = ["the largest fragments:", f"g, diameter cm, c/a{', projectile' if shares is not None else ''}"] + [
            f"{i + 1}. {top.mass[i]:.3g}, {top.diameter_cm[i]:.3g}, {top.axes_cm[i, 2] / top.axes_cm[i, 0]:.2f}"
            + ("" if shares is None else f", {shares[i]:.0%}") for i in range(len(top))]
        ax_list.text(0.0, 1.0, "\n".join(lines), transform=ax_list.transAxes, ha="left", va="top", fontsize=8,
                     family="monospace")
        ax.legend(loc="lower left", fontsize=8)
        parts = {"all": None}
        if from_projectile_g is not None:
            projectile = np.asarray(from_projectile_g, float)
            parts |= {"projectile": projectile, "bumper": np.asarray(fragments.mass) - projectile}
        for (label, part), colour in zip(parts.items(), ("C0", "C1", "C2")):
            mass, total = cumulative_mass(fragments, part)
            ax_mass.step(mass, total, where="post", color=colour, label=f"{label}: {total[-1]:.4g} g")
        ax_mass.legend(loc="lower left", fontsize=8)
        ax.set_yscale("log")
        ax_mass.set_ylim(bottom=0.0)         # M(≥ m) on a linear axis: a part that is 0 at large m shows as 0
        for axis in (ax, ax_mass):
            axis.set_xscale("log")
            if projectile_mass_g is not None:
                _projectile_share_axis(axis, float(projectile_mass_g))
    else:
        for axis in (ax, ax_mass):
            axis.text(0.5, 0.5, "no fragments", transform=axis.transAxes, ha="center")
    for axis, label in ((ax, "N(≥ m)"), (ax_mass, "mass in fragments of ≥ m, M(≥ m) (g)")):
        axis.set_xlabel("fragment mass m (g)")
        axis.set_ylabel(label)
        axis.grid(True, which="both", alpha=0.3)
    fig.suptitle(title)
    return fig


def _projectile_share_axis(axis, projectile_mass_g: float) -> None:
    """A top axis of m as a percentage of the projectile's mass, labelled at 1, 2 and 5 of each decade: over
    the less than two decades the fragments span, the log axis's default labels every minor tick too, in
    scientific notation, and they run into one another."""
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    top = axis.secondary_xaxis("top", functions=(lambda x: 100.0 * x / projectile_mass_g,
                                                 lambda x: x * projectile_mass_g / 100.0))
    top.xaxis.set_major_locator(LogLocator(base=10.0, subs=(1.0, 2.0, 5.0)))
    top.xaxis.set_major_formatter(FuncFormatter(lambda x, _: f"{x:g}"))
    top.xaxis.set_minor_formatter(NullFormatter())
    top.set_xlabel("m / projectile mass (%)")


def fragments_of(particles, *, link_length_cm: float, damage_threshold: float = 1.0,
                 mirror_x0: bool = True) -> Fragments:
    """The fragments of an SPH state (:class:`impactdyn.shield.Particles`).

    Intact: damage D < ``damage_threshold`` and less than half melted on release
    (:func:`impactdyn.shield.released_phase`, the latent heat counted; a material without phase data is
    never melted): a liquid
    particle is spray, not part of a solid fragment.  Volumes m/ρ₀ of the library material.
    ``mirror_x0``: the state is the half model of a symmetry plane x = 0 (the shield stage's sphere on
    plate): the image particles (−x, y, z) are added first, so a fragment across the plane is found
    whole, with its full mass, and each one beside it once on each side.
    """
    from impactdyn.materials import get_material

    if not (0.0 < damage_threshold <= 1.0):
        raise InputError(f"damage_threshold = {damage_threshold}: must lie in (0, 1]")
    mats = [get_material(name) for name in particles.materials]
    rho0 = np.array([m.rho0 for m in mats])[particles.material]
    intact = (particles.damage < damage_threshold) & solid_particles(particles)
    position, velocity, mass = particles.position, particles.velocity, particles.mass
    if mirror_x0:
        position, velocity = with_images(position), with_images(velocity)
        mass, rho0, intact = (np.concatenate([a, a]) for a in (mass, rho0, intact))
    return find_fragments(position, velocity, mass, mass / rho0, intact, link_length_cm=link_length_cm)
