"""Particle state and run history of the SPH shield stage (units cm, g, µs, Mbar)."""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from impactdyn._errors import InputError

#: Order of the 6 components of a symmetric tensor.
TENSOR_COMPONENTS = ("xx", "yy", "zz", "xy", "yz", "zx")

_SHAPES = {
    "position": (3,), "velocity": (3,), "mass": (), "density": (), "pressure": (), "specific_energy": (),
    "deviatoric_stress": (6,), "plastic_strain": (), "failed": (), "smoothing_length": (), "sound_speed": (),
    "temperature": (), "material": (), "damage": (), "failure_strain_rate": (),
}


@dataclass(frozen=True, eq=False)
class Particles:
    """SPH particle state at one time (arrays stored read-only).

    Attributes
    ----------
    position, velocity : (N, 3)
        cm, cm/µs.
    mass : (N,)
        g.
    density : (N,)
        g/cm³.
    pressure : (N,)
        Mbar (negative: tension).
    specific_energy : (N,)
        Specific internal energy, cm²/µs² (0 in the reference state ρ₀, p = 0).
    deviatoric_stress : (N, 6)
        S, Mbar, components (xx, yy, zz, xy, yz, zx).
    plastic_strain : (N,)
        Equivalent plastic strain εₚ.
    failed : (N,) bool
        Failed particles carry no tension (p ≥ 0) and no deviatoric stress.
    damage : (N,) in [0, 1], optional
        D: the particle carries (1 − D) of its tension and deviatoric stress (D = 1: failed);
        None (a state written before damage was recorded): 1 where failed, else 0.
    failure_strain_rate : (N,) ≥ 0, optional
        µs⁻¹: the largest principal stretching rate of a failed particle on the first step it was failed
        and expanded beyond its reference density ρ₀ (what sizes the fragments of failed material,
        :func:`impactdyn.shield.grady_fragments`); 0 where it did not fail in the run, or has not
        expanded since.  None (a state written before it was recorded): 0.
    smoothing_length : (N,)
        h, cm (kernel support 2h).
    sound_speed : (N,)
        cm/µs.
    temperature : (N,)
        K, estimated from (ρ, e) with a constant specific heat (:mod:`impactdyn.constitutive`).
    material : (N,) int
        Index into ``materials``.
    materials : tuple[str, ...]
        Material names.
    time : float
        µs.
    """

    position: np.ndarray
    velocity: np.ndarray
    mass: np.ndarray
    density: np.ndarray
    pressure: np.ndarray
    specific_energy: np.ndarray
    deviatoric_stress: np.ndarray
    plastic_strain: np.ndarray
    failed: np.ndarray
    smoothing_length: np.ndarray
    sound_speed: np.ndarray
    temperature: np.ndarray
    material: np.ndarray
    materials: tuple[str, ...]
    time: float = 0.0
    damage: np.ndarray | None = None
    failure_strain_rate: np.ndarray | None = None

    def __post_init__(self) -> None:
        n = np.shape(self.mass)[0] if np.ndim(self.mass) == 1 else -1
        if self.damage is None:
            object.__setattr__(self, "damage", np.asarray(self.failed, dtype=float))
        if self.failure_strain_rate is None:
            object.__setattr__(self, "failure_strain_rate", np.zeros(max(n, 0)))
        for name, tail in _SHAPES.items():
            dtype = bool if name == "failed" else np.int64 if name == "material" else np.float64
            a = np.array(getattr(self, name), dtype=dtype)
            if a.shape != (n,) + tail:
                raise InputError(f"Particles.{name}: shape {a.shape}, expected {(n,) + tail}")
            if dtype is np.float64 and not np.all(np.isfinite(a)):
                raise InputError(f"Particles.{name}: not finite")
            a.flags.writeable = False
            object.__setattr__(self, name, a)
        if n and not np.all((self.damage >= 0.0) & (self.damage <= 1.0)):
            raise InputError("Particles.damage: outside [0, 1]")
        if n and np.any(self.failure_strain_rate < 0.0):
            raise InputError("Particles.failure_strain_rate: negative")
        if n and (self.material.min() < 0 or self.material.max() >= len(self.materials)):
            raise InputError("Particles.material: index outside the material list")
        object.__setattr__(self, "materials", tuple(self.materials))
        object.__setattr__(self, "time", float(self.time))

    def __len__(self) -> int:
        return self.mass.size

    def total_mass(self) -> float:
        """Σ m, g."""
        return float(self.mass.sum())

    def total_momentum(self) -> np.ndarray:
        """Σ m v, g·cm/µs, (3,)."""
        return self.mass @ self.velocity

    def kinetic_energy(self) -> float:
        """Σ ½ m |v|², g·cm²/µs²."""
        return float(0.5 * self.mass @ np.einsum("nd,nd->n", self.velocity, self.velocity))

    def internal_energy(self) -> float:
        """Σ m e, g·cm²/µs²."""
        return float(self.mass @ self.specific_energy)

    def select(self, keep) -> "Particles":
        """The particles where the boolean mask ``keep`` (N,) is true, in their order."""
        keep = np.asarray(keep, dtype=bool)
        if keep.shape != (len(self),):
            raise InputError(f"Particles.select: a mask of shape {keep.shape}, expected ({len(self)},)")
        return self.replace(**{name: getattr(self, name)[keep] for name in _SHAPES})

    def replace(self, **changes) -> "Particles":
        """A copy with some fields replaced."""
        values = {f.name: getattr(self, f.name) for f in fields(self)}
        values.update(changes)
        return Particles(**values)

    def __repr__(self) -> str:
        return (f"Particles(n={len(self)}, time={self.time} us, materials={self.materials}, "
                f"mass={self.total_mass():.6g} g)")


@dataclass(frozen=True, eq=False)
class History:
    """Conserved totals after every step (row 0: the initial state).

    time (S,) µs; mass (S,) g; momentum (S, 3) g·cm/µs; kinetic, internal (S,) g·cm²/µs².
    """

    time: np.ndarray
    mass: np.ndarray
    momentum: np.ndarray
    kinetic: np.ndarray
    internal: np.ndarray

    @property
    def total_energy(self) -> np.ndarray:
        return self.kinetic + self.internal


@dataclass(frozen=True, eq=False)
class RunResult:
    """Outcome of :func:`impactdyn.shield.run`.

    state: the particles at t_end; history: the totals per step;
    snapshots: the particles at each requested snapshot time; steps: number of steps.
    """

    state: Particles
    history: History
    snapshots: tuple[Particles, ...]
    steps: int
