"""``impactdyn materials``: the registered materials (the library, and a case's own with ``--case``),
every constant with its unit and source.

Values are printed in the package's units (cm, g, µs, Mbar, K); a bad ``--case`` or an unknown name
is an :class:`~impactdyn.InputError` (exit code 2, no traceback).
"""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path
from typing import Any, Optional

import typer

app = typer.Typer(help="The material library and a case's own materials, every constant with its source.",
                  no_args_is_help=True)

#: The unit of each field of a material and its sub-records (package units).
UNITS = {"rho0": "g/cm³", "c0": "cm/µs", "shear_modulus": "Mbar", "yield_stress": "Mbar",
         "specific_heat": "cm²/(µs²·K)", "spall_strength": "Mbar", "tensile_yield": "Mbar", "A": "Mbar", "B": "Mbar", "t_melt": "K",
         "t_room": "K", "reference_strain_rate": "1/µs", "solidus": "K", "liquidus": "K", "boiling": "K",
         "latent_fusion": "cm²/µs²", "latent_vaporisation": "cm²/µs²", "sigma0": "Mbar", "K": "Mbar^λ·µs",
         "k": "1/cm³", "K_Ic": "Mbar·cm^½"}

_CASE_HELP = "A Whipple case file: its [materials.NAME] tables are listed too."
_JSON_HELP = "Print JSON instead of a table."


def _registered(case: Path | None) -> dict:
    """The registry, after registering the case's own materials."""
    from impactdyn.materials import MATERIALS

    if case is not None:
        from impactdyn.whipple import load_whipple_case

        load_whipple_case(case)
    return MATERIALS


def _described(material) -> dict[str, Any]:
    """Every constant of ``material`` with its unit: ``{field: value}`` and ``units``."""
    data = dataclasses.asdict(material)
    return data | {"units": {k: v for k, v in UNITS.items() if _has(data, k)}}


def _has(data: dict, key: str) -> bool:
    return key in data or any(isinstance(v, dict) and _has(v, key) for v in data.values())


def _rows(data: dict, indent: str = "") -> list[str]:
    lines = []
    for key, value in data.items():
        if isinstance(value, dict):
            lines += [f"{indent}{key}:"] + _rows(value, indent + "  ")
        elif value is not None and key != "units":
            unit = f" {UNITS[key]}" if key in UNITS else ""
            lines.append(f"{indent}{key:<22} {value:.6g}{unit}" if isinstance(value, float)
                         else f"{indent}{key:<22} {value}")
        elif value is None:
            lines.append(f"{indent}{key:<22} none")
    return lines


@app.command("list")
def list_materials(case: Optional[Path] = typer.Option(None, "--case", help=_CASE_HELP),
                   as_json: bool = typer.Option(False, "--json", help=_JSON_HELP)) -> None:
    """The registered materials: name, density, and which optional groups each has."""
    from impactdyn.materials import OPTIONAL_GROUPS

    materials = _registered(case)
    rows = {name: {"rho0_g_cm3": m.rho0, "groups": [g for g in OPTIONAL_GROUPS if getattr(m, g) is not None]}
            for name, m in materials.items()}
    if as_json:
        typer.echo(json.dumps(rows, indent=1))
        return
    for name, row in rows.items():
        typer.echo(f"{name:<14} rho0 {row['rho0_g_cm3']:<6g} g/cm³  {', '.join(row['groups']) or '-'}")


@app.command("show")
def show(name: str = typer.Argument(..., help="The material's name (case and separators ignored)."),
         case: Optional[Path] = typer.Option(None, "--case", help=_CASE_HELP),
         as_json: bool = typer.Option(False, "--json", help=_JSON_HELP)) -> None:
    """Every constant of one material, with its unit and source."""
    from impactdyn.materials import get_material

    _registered(case)
    data = _described(get_material(name))
    typer.echo(json.dumps(data, indent=1) if as_json else "\n".join(_rows(data)))
