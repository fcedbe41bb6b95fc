"""Material physics shared by the solvers: Mie–Grüneisen EOS and deviatoric strength kernels.

Part of the data model below every solver package: the SPH shield stage and the wall's
finite elements evaluate the same equation of state and the same stress update from the
packed material table of :mod:`impactdyn.materials` entries.  Units cm, g, µs, Mbar, K.

* :mod:`._eos` — ``p(ρ, e)`` about a linear Us–up Hugoniot, sound speed, temperature,
  and :func:`pack_materials`, the float64 table the compiled kernels read (column
  indices ``RHO0`` … ``HAS_JC``).
* :mod:`._strength` — Jaumann rate, von Mises radial return, flow stress
  (perfectly plastic or Johnson–Cook) and a cheap lower bound of it, artificial stress.
* :mod:`._failure` — failure laws: the Johnson–Cook fracture strain with its floor, the
  Tuler–Butcher spall-damage increment, the Grady–Kipp tensile damage and the ductile damage
  of the shield's fragmentation, and :func:`pack_damage`, their constants' table (``DM_*``).
* :mod:`._phase` — melt and vapour on release: a state released along its isentrope to zero
  pressure, its melted and vapour shares from the latent heats, and :func:`pack_phases`.
"""

from impactdyn.constitutive._eos import (
    C0, CV, EPS_FAIL, GAMMA0, HAS_JC, JC_A, JC_B, JC_C, JC_M, JC_N, JC_RATE0, JC_TMELT, JC_TROOM, MU_COLD, N_COLD,
    N_PARAMS, P_SPALL, RHO0, SHEAR, SLOPE, T_ROOM, YIELD, pack_materials, pressure, sound_speed, temperature,
    temperature_bound)
from impactdyn.constitutive._failure import (
    DM_GROWTH, DM_HAS_WEIBULL, DM_K, DM_M, DM_YOUNG, FLAW_M0, FLAW_M1, FLAW_M2, FLAW_M3, FLAW_STRAIN, N_DAMAGE,
    N_FLAW, TRIAXIALITY_CUTOFF, ductile_damage_increment,
    fracture_strain, grady_kipp_damage, largest_principal_stress, pack_damage, tuler_butcher_increment,
    tuler_butcher_rate)
from impactdyn.constitutive._phase import N_PHASE, pack_phases, phase_of_released, release_states, released_energy
from impactdyn.constitutive._strength import (
    artificial_stress, flow_stress, flow_stress_floor, jaumann_rate, radial_return, spin_terms, von_mises)

__all__ = [
    "DM_GROWTH", "DM_HAS_WEIBULL", "DM_K", "DM_M", "DM_YOUNG", "FLAW_M0", "FLAW_M1", "FLAW_M2", "FLAW_M3",
    "FLAW_STRAIN", "N_DAMAGE", "N_FLAW", "TRIAXIALITY_CUTOFF",
    "ductile_damage_increment", "grady_kipp_damage", "largest_principal_stress", "pack_damage",
    "C0", "CV", "EPS_FAIL", "GAMMA0", "HAS_JC", "JC_A", "JC_B", "JC_C", "JC_M", "JC_N", "JC_RATE0", "JC_TMELT",
    "JC_TROOM", "MU_COLD", "N_COLD", "N_PARAMS", "P_SPALL", "RHO0", "SHEAR", "SLOPE", "T_ROOM", "YIELD",
    "N_PHASE", "pack_phases", "phase_of_released", "release_states", "released_energy",
    "artificial_stress", "flow_stress", "flow_stress_floor", "fracture_strain", "jaumann_rate", "pack_materials",
    "pressure", "radial_return", "sound_speed", "spin_terms", "temperature", "temperature_bound",
    "tuler_butcher_increment", "tuler_butcher_rate", "von_mises",
]
