"""Unit conversions, in one place.

The impact stages work in cm, g, µs, as DC3D did (Fahrenthold 1994, App. G):

========================  ==================  =========================
quantity                  internal unit       equals
========================  ==================  =========================
length                    cm                  1e-2 m
mass                      g                   1e-3 kg
time                      µs                  1e-6 s
velocity                  cm/µs               10 km/s = 1e6 cm/s
pressure, stress          Mbar = g/(cm·µs²)   100 GPa = 1e12 dyn/cm²
specific energy           cm²/µs²             1e12 erg/g = 1e8 J/kg
energy                    g·cm²/µs²           1e12 erg = 1e5 J
force                     g·cm/µs²            1e12 dyn = 1e7 N
momentum, impulse         g·cm/µs             1e6 g·cm/s = 10 N·s
========================  ==================  =========================

Hydrocode dumps (CTH) are cgs; the literature quotes km/s, GPa, ksi and inches.
Every conversion between those and the internal units goes through this module,
as a named factor ``A_PER_B`` (multiply a value in B to get A) or a function
``b_to_a``.  The beam model is SI throughout and needs none of these.
"""

from __future__ import annotations

from typing import TypeVar

import numpy as np

T = TypeVar("T", float, np.ndarray)

# Factors: multiply a value in the unit after PER to get the unit before it.
CM_PER_INCH = 2.54
US_PER_S = 1.0e6
CM_US_PER_CM_S = 1.0e-6  # CTH velocities (cm/s) -> cm/µs; RDAVS divides by 1e6
CM_US_PER_KM_S = 0.1
KM_S_PER_CM_US = 10.0  # exact; 1/CM_US_PER_KM_S is not (0.1 has no binary representation)
MBAR_PER_DYN_CM2 = 1.0e-12  # CTH pressures (dyn/cm²) -> Mbar; RDAVS divides by 1e12
MBAR_PER_GPA = 1.0e-2
MBAR_PER_MPA = 1.0e-3 * MBAR_PER_GPA
MBAR_PER_PA = 1.0e-11
MBAR_PER_KSI = 6.894757293168361e6 * MBAR_PER_PA  # 1 ksi = 6.894757 MPa (exact lbf/in² definition)
CM2_US2_PER_ERG_G = 1.0e-12  # CTH specific internal energy (erg/g) -> cm²/µs²
CM2_US2_PER_J_G = 1.0e-5  # 1 J/g = 1e3 J/kg = 1e-5 cm²/µs² (1 cm²/µs² = 1e8 J/kg)
MBAR_SQRT_CM_PER_MPA_SQRT_M = 1.0e-4  # fracture toughness: 1 MPa·√m = 1e6 Pa · 10 √cm = 1e-4 Mbar·√cm
PER_US_PER_PER_S = 1.0e-6  # strain rates: 1 s⁻¹ = 1e-6 µs⁻¹
N_S_PER_G_CM_US = 10.0  # momentum, impulse: 1 g·cm/µs = 1e-3 kg · 1e-2 m / 1e-6 s = 10 N·s

# The units people read, spelled once for the reports' tables, the plots' axes and the command lines.
#: Areal momentum (impulse per area), in N·s/cm² = N_S_PER_G_CM_US × g/(cm·µs): the unit of the literature's
#: and the docs' tables (docs/vv/), so a printed peak is compared without a conversion.
AREAL_MOMENTUM_UNIT = "N·s/cm²"


def inch_to_cm(x: T) -> T:
    return x * CM_PER_INCH


def cm_s_to_cm_us(v: T) -> T:
    """cgs velocity (cm/s) -> cm/µs."""
    return v * CM_US_PER_CM_S


def cm_us_to_cm_s(v: T) -> T:
    return v / CM_US_PER_CM_S


def km_s_to_cm_us(v: T) -> T:
    return v * CM_US_PER_KM_S


def cm_us_to_km_s(v: T) -> T:
    return v * KM_S_PER_CM_US


def dyn_cm2_to_mbar(p: T) -> T:
    """cgs pressure (dyn/cm²) -> Mbar."""
    return p * MBAR_PER_DYN_CM2


def mbar_to_dyn_cm2(p: T) -> T:
    return p / MBAR_PER_DYN_CM2


def gpa_to_mbar(p: T) -> T:
    return p * MBAR_PER_GPA


def mbar_to_gpa(p: T) -> T:
    return p / MBAR_PER_GPA


def ksi_to_mbar(p: T) -> T:
    return p * MBAR_PER_KSI


def erg_g_to_cm2_us2(e: T) -> T:
    """cgs specific energy (erg/g) -> cm²/µs²."""
    return e * CM2_US2_PER_ERG_G


def cm2_us2_to_erg_g(e: T) -> T:
    return e / CM2_US2_PER_ERG_G


def s_to_us(t: T) -> T:
    return t * US_PER_S


def us_to_s(t: T) -> T:
    return t / US_PER_S
