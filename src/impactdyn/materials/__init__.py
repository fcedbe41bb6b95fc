"""Materials of the impact stages: one record per alloy, a registry, the library, and the wall card.

* :class:`Material` (:mod:`._records`) holds everything the stages read of an alloy: the
  Mie–Grüneisen EOS, the strength, and as optional sub-records, each with its source, the
  Johnson–Cook flow stress and damage, Tuler–Butcher spall, Weibull flaws, fracture toughness and the
  melt and phase data.  Units cm, g, µs, Mbar, K (:mod:`impactdyn.units`).
* :func:`register_material` enters a record in :data:`MATERIALS`; :func:`get_material` finds it by
  name.  The library (:mod:`._library`: Al 6061-T6, 2024-T4, 7075-T6, OFHC copper, 304 stainless
  steel, with the sources of every number) registers its alloys at import.
* :data:`MaterialsTable` (:mod:`._case_table`): a case file's ``[materials.NAME]`` tables, validated
  with units in the key names and a ``source`` for each group of constants, and registered.
* :class:`Mat13Card` (:mod:`._mat13`): the DYNA3D type-13 wall card, :func:`mat13_card`.
"""

from impactdyn.materials._records import (
    CRACK_SPEED_FRACTION, OPTIONAL_GROUPS, FractureToughness, JohnsonCook, JohnsonCookDamage, Material, PhaseChange,
    TulerButcher, WeibullFlaws)
from impactdyn.materials._registry import (
    MATERIALS, REPORT_MATERIAL, MaterialName, get_material, register_material)
from impactdyn.materials._library import (
    AL_2024_T4, AL_2024_T351_JC_DAMAGE, AL_6061_T6, AL_6061_T6_JC_DAMAGE, AL_7075_T6, AL_WEIBULL,
    ALUMINIUM_SPALL_RANGE, ALUMINIUM_SPALL_STRENGTH, COPPER_SPALL_STRENGTH, COPPER_SPALL_TOP, CU_OFHC,
    CU_OFHC_JC_DAMAGE, NOTCHED_BAR_TRIAXIALITY, SPHERAL_ALUMINIUM_WEIBULL, SS_304, TB_EXPONENT, TB_STRESS_RATE,
    weibull_from_spall)
from impactdyn.materials._mat13 import AL_6061_T6_MAT13, Mat13Card, mat13_card
from impactdyn.materials._case_table import MaterialTable, MaterialsTable, without_material_echoes

__all__ = [
    "AL_2024_T351_JC_DAMAGE", "AL_2024_T4", "AL_6061_T6", "AL_6061_T6_JC_DAMAGE", "AL_6061_T6_MAT13", "AL_7075_T6",
    "AL_WEIBULL", "ALUMINIUM_SPALL_RANGE", "ALUMINIUM_SPALL_STRENGTH", "COPPER_SPALL_STRENGTH", "COPPER_SPALL_TOP",
    "CRACK_SPEED_FRACTION", "CU_OFHC", "CU_OFHC_JC_DAMAGE", "MATERIALS", "NOTCHED_BAR_TRIAXIALITY",
    "OPTIONAL_GROUPS", "REPORT_MATERIAL", "SPHERAL_ALUMINIUM_WEIBULL", "SS_304", "TB_EXPONENT", "TB_STRESS_RATE",
    "FractureToughness", "JohnsonCook", "JohnsonCookDamage", "Mat13Card", "Material", "MaterialName", "MaterialTable",
    "MaterialsTable", "PhaseChange",
    "TulerButcher", "WeibullFlaws", "get_material", "mat13_card", "register_material", "weibull_from_spall",
    "without_material_echoes",
]
