"""Grids shared by the io tests (as fixtures: test modules do not import each other)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from impactdyn import units
from impactdyn.hydrogrid import HydroGrid


def _three_digits(rng: np.random.Generator, shape, lo_exp: int, hi_exp: int, signed: bool = True) -> np.ndarray:
    """Random values with 3 significant digits (what avsout's e11.3 holds), in a decade range."""
    mant = rng.integers(100, 1000, size=shape) / 1000.0
    sign = rng.choice([-1.0, 1.0], size=shape) if signed else 1.0
    return sign * mant * 10.0 ** rng.integers(lo_exp, hi_exp + 1, size=shape)


def _representable_grid(rng: np.random.Generator, shape=(3, 4, 5), time: float = 4.0) -> HydroGrid:
    """A staggered, uniform grid whose cgs values every format holds exactly (3 significant digits)."""
    nx, ny, nz = shape
    c = lambda lo, hi, signed=True: _three_digits(rng, shape, lo, hi, signed)  # noqa: E731
    return HydroGrid(
        x=0.5 + 0.25 * np.arange(nx + 1), y=-11.5 + 0.125 * np.arange(ny + 1), z=-1.0 + 0.5 * np.arange(nz + 1),
        velocity=units.cm_s_to_cm_us(_three_digits(rng, shape + (3,), 3, 6)),
        pressure=units.dyn_cm2_to_mbar(c(8, 12)),
        temperature=c(2, 4, False),
        density=c(-1, 1, False),
        specific_energy=units.erg_g_to_cm2_us2(c(9, 11)),
        mass=c(-6, -3, False),
        void_fraction=_three_digits(rng, shape, -1, -1, False),
        sound_speed=units.cm_s_to_cm_us(c(5, 6, False)),
        staggered=True,
        time=time,
    )


def _assert_same_grid(a: HydroGrid, b: HydroGrid, rtol: float = 1e-12) -> None:
    assert a.shape == b.shape
    assert a.staggered == b.staggered
    assert a.time == pytest.approx(b.time, rel=rtol)
    for name in ("x", "y", "z", "density", "void_fraction", "mass", "pressure", "temperature",
                 "specific_energy", "sound_speed", "velocity"):
        u, v = getattr(a, name), getattr(b, name)
        np.testing.assert_allclose(u, v, rtol=rtol, atol=rtol * np.max(np.abs(v)), err_msg=name)


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(20240501)


@pytest.fixture
def representable_grid():
    """``make(rng, shape=(3, 4, 5), time=4.0)``: a staggered uniform grid exact in every format."""
    return _representable_grid


@pytest.fixture
def assert_same_grid():
    """``check(a, b, rtol=1e-12)``: every array, the flag and the time agree."""
    return _assert_same_grid


@pytest.fixture
def example_dc3din() -> Path:
    """The Appendix C input file shipped in examples/."""
    return Path(__file__).resolve().parents[2] / "examples" / "debris" / "legacy" / "dc3din"
