"""A shot of the test database as a Whipple case: the shot's shield and projectile on a base case's numerics.

:func:`database_shot` finds a shot of the test database (:func:`impactdyn.ble.read_database`)
by its line in the file or by its shot ID; :func:`database_shot_case` turns it into the raw
dict of a :class:`~impactdyn.whipple.WhippleCase`: the base case (the Table 2 7a example,
``examples/whipple/table2_7a.toml``, unless another is named) with the shot's projectile
(material, diameter, speed, obliquity), bumper (material, thickness) and wall (material,
thickness, yield stress, stand-off S) put in.  Nothing else of the base changes except what the
geometry forces, by these rules (S₀, d₀: the base case's stand-off and projectile diameter):

* **wall extent**: ``wall.x_cm`` and ``wall.z_cm`` × S/S₀, so the debris cloud's footprint,
  which grows in proportion to the distance it flies, covers the same share of the wall grid;
  the node counts along x and z scale with the extent (``round((n − 1)·S/S₀) + 1``), so the
  elements keep the base case's size (the report's 0.16 cm on the example);
* **SPH spacing**: ``shield.spacing_cm`` × min(1, d/d₀), so a projectile smaller than the base
  case's keeps at least its particles across (as ``whipple limit`` and ``campaign`` resolve theirs);
  a larger one keeps the base spacing;
* **arrival window**: ``filter.t_cut_us`` × max(1, S/S₀), so that the cloud, whose flight
  to the wall takes S/V, still reaches the wall inside the window at a longer stand-off.
  Without it the example's 25 µs left a 20.32 cm shot at 7 km/s with no load at all (its cloud
  arrives after ~28 µs).

The shot's speed stretches neither the window nor the hand-off time ``shield.handoff_us``,
unlike the speed families' :func:`~impactdyn.whipple._shots.shot_variant` (× V₀/V for a slower
shot): these are the rules the validation sets' shots were run with, and the cases are kept
reproducible (``tests/whipple/test_database_shot.py`` checks validation set 1's twelve).  On those
shots (6.2–7.5 km/s) the window is at least 0.88 of the example's window per flight time
t_cut·V/S.  A slow shot at a long stand-off is not so covered: where S/V approaches t_cut
(10.16 cm at 4 km/s: 25 µs, the example's whole window) its cloud arrives late or not at all
and the wall sees too little load; raise ``filter.t_cut_us`` in the base case for such shots.

The database names its alloys; the case needs library materials (:data:`ALLOYS`, the one table
of the mapping).  An alloy without one is refused, naming the shot's line.  Every shot of the
packaged database has a yield stress (the reader refuses a missing one), so ``wall.yield_stress_ksi``
is always the shot's.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from impactdyn._config import load_toml, set_dotted, validate
from impactdyn._errors import InputError
from impactdyn.ble import ShotDatabase, read_database
from impactdyn.whipple._case import DatabaseShotSection, WhippleCase

#: The Table 2 7a example, the base case of a shot unless another is named.  It lives in the
#: source tree's ``examples/``, not in an installed package: there name a base case.
EXAMPLE_CASE = Path(__file__).resolve().parents[3] / "examples" / "whipple" / "table2_7a.toml"

#: Database alloy → library material (:data:`impactdyn.materials.MATERIALS`): the alloy itself, or where
#: the library lacks it the nearest alloy it has (:data:`SUBSTITUTED` says why).  Pure and annealed
#: aluminium (AA1100-O, 99.9 %) has no library entry.
ALLOYS = {"AA2017-T4": "al2024-t4", "AA2024-T3": "al2024-t4", "AA2024-T4": "al2024-t4",
          "AA2024-T351": "al2024-t4", "AA6061-T6": "al6061-t6"}

#: Why each database alloy that :data:`ALLOYS` maps to another alloy's material is modelled so: said
#: where the case is written and printed, so that no substitution goes unseen.
SUBSTITUTED = {"AA2017-T4": "the same Al-Cu family, 2.79 against 2.785 g/cm³",
               "AA2024-T3": "the same alloy in the T4 temper",
               "AA2024-T351": "the same alloy in the T4 temper; its damage constants are 2024-T351's"}

#: Significant figures of the SPH particle pitch in a written case: 4 keep it within 0.05 % of the scaled
#: value, far below the resolution the pitch sets, and readable.
PITCH_FIGURES = 4


@dataclass(frozen=True)
class DatabaseShot:
    """One test shot (literature units); ``alloys``: part (projectile, bumper, wall) → the database's
    alloy name; ``perforated``: the rear wall was perforated or spalled (result P)."""

    database: str
    line: int
    source: str
    shot_id: str
    alloys: dict[str, str]
    diameter_cm: float
    velocity_km_s: float
    obliquity_deg: float
    bumper_thickness_cm: float
    wall_thickness_cm: float
    spacing_cm: float
    wall_yield_ksi: float
    perforated: bool

    @property
    def record(self) -> DatabaseShotSection:
        """The case's ``[test_shot]`` table of the shot: the database file by its name, and the test's outcome."""
        return DatabaseShotSection(database=Path(self.database).name, line=self.line, source=self.source,
                                   shot_id=self.shot_id, perforated=self.perforated)

    @property
    def name(self) -> str:
        """The shot as a reader finds it: source, ID and file line."""
        return self.record.name

    @property
    def outcome(self) -> str:
        return self.record.outcome


def database_shot(key: int | str, database: ShotDatabase | None = None) -> DatabaseShot:
    """The shot of ``database`` (default: the packaged one) that ``key`` names.

    ``key``: an ``int`` is a line of the file; a ``str`` is ``line:N``, ``id:X``, or bare: a shot
    ID, or a line where it is a whole number.  A whole number that is both a line and some shot's
    ID is refused as ambiguous (195 of the packaged shots have numeric IDs), as is an ID that
    several shots share (the message lists their lines to choose from).
    """
    db = read_database() if database is None else database
    lines = {int(n): i for i, n in enumerate(db.line)}
    where = db.path
    if isinstance(key, str):
        text = key.strip()
        if text.startswith("line:"):
            key = _line_number(text[5:], key)
        elif text.startswith("id:"):
            return _shot_at(db, _index_of_id(db, text[3:].strip()))
        elif text.isdigit() and int(text) in lines and np.any(db.shot_id == text):
            raise InputError(f"{where}: '{text}' is both line {text} and the ID of the shot(s) at line(s) "
                             f"{_lines_of(db, text)}; pass line:{text} or id:{text}")
        elif text.isdigit() and int(text) in lines:
            key = int(text)
        else:
            return _shot_at(db, _index_of_id(db, text))
    if key not in lines:
        raise InputError(f"{where}: no shot at line {key} (shots are on lines {min(lines)}-{max(lines)})")
    return _shot_at(db, lines[key])


def _line_number(text: str, key: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise InputError(f"{key!r}: expected line:N with N a line of the database file") from None


def _lines_of(db: ShotDatabase, shot_id: str) -> str:
    return ", ".join(str(n) for n in db.line[db.shot_id == shot_id])


def _index_of_id(db: ShotDatabase, shot_id: str) -> int:
    found = np.flatnonzero(db.shot_id == shot_id)
    if len(found) == 0:
        raise InputError(f"{db.path}: no shot with ID {shot_id!r}")
    if len(found) > 1:
        raise InputError(f"{db.path}: shot ID {shot_id!r} is on {len(found)} lines ({_lines_of(db, shot_id)}); "
                         "pass one of those line numbers")
    return int(found[0])


def _shot_at(db: ShotDatabase, i: int) -> DatabaseShot:
    line = int(db.line[i])
    return DatabaseShot(
        database=db.path, line=line, source=str(db.source[i]), shot_id=str(db.shot_id[i]),
        alloys={"projectile": str(db.projectile_material[i]), "bumper": str(db.bumper_material[i]),
                "wall": str(db.wall_material[i])}, diameter_cm=float(db.diameter_cm[i]),
        velocity_km_s=float(db.velocity_km_s[i]), obliquity_deg=float(db.obliquity_deg[i]),
        bumper_thickness_cm=float(db.bumper_thickness_cm[i]), wall_thickness_cm=float(db.wall_thickness_cm[i]),
        spacing_cm=float(db.spacing_cm[i]), wall_yield_ksi=float(db.wall_yield_ksi[i]),
        perforated=bool(db.perforated[i]))


def _material(shot: DatabaseShot, part: str) -> str:
    alloy = shot.alloys[part]
    if alloy not in ALLOYS:
        raise InputError(f"{shot.database}:{shot.line}: shot {shot.shot_id}: {part} alloy {alloy!r} has no library "
                         f"material (known: {', '.join(sorted(ALLOYS))})")
    return ALLOYS[alloy]


def alloy_substitutions(shot: DatabaseShot) -> dict[str, str]:
    """Part → a line saying which library material stands for the shot's alloy and why, for each part whose
    alloy the library lacks (:data:`SUBSTITUTED`)."""
    return {part: f"{part}: {alloy} modelled as {ALLOYS[alloy]}, the library's nearest alloy ({SUBSTITUTED[alloy]})"
            for part, alloy in shot.alloys.items() if alloy in SUBSTITUTED}


def database_shot_case_text(shot: DatabaseShot, raw: dict, base: str | Path | None = None) -> str:
    """The TOML of ``raw`` (:func:`database_shot_case` of ``shot``) as ``whipple shot --write-case`` writes it: the
    test's outcome in its header, each substituted alloy said where its material is set, and the SPH pitch
    rounded to :data:`PITCH_FIGURES` figures with how it was derived."""
    import tomli_w

    _, base_case = load_base_case(base)
    pitch = raw["shield"]["spacing_cm"]
    rounded = float(f"{pitch:.{PITCH_FIGURES}g}")
    ratio = shot.diameter_cm / base_case.projectile.diameter_cm
    derivation = (f"SPH particle pitch: the base case's {base_case.shield.spacing_cm:g} cm" + (
        f" × d/d₀ = {shot.diameter_cm:g}/{base_case.projectile.diameter_cm:g} = {pitch:.7g} cm, rounded (the projectile "
        "keeps the base case's particles across; `whipple shot -o` and `validate` run the unrounded value)"
        if ratio < 1.0 else " (the projectile is no smaller than the base case's)"))
    notes = {("shield", "spacing_cm"): derivation}
    notes |= {(part, "material"): note for part, note in alloy_substitutions(shot).items()}
    text = tomli_w.dumps(set_dotted(raw, "shield.spacing_cm", rounded))
    lines, section = [], None
    for line in text.splitlines():
        if line.startswith("["):
            section = line.strip("[]")
        key = line.split(" = ")[0]
        if (section, key) in notes:
            lines.append(f"# {notes[section, key]}")
        lines.append(line)
    header = [f"# {raw['title']}, on {base or 'the Table 2 7a example'} (impactdyn whipple shot)",
              f"# the test: {shot.outcome}", ""]
    return "\n".join(header + lines) + "\n"


def database_shot_case(shot: DatabaseShot, base: str | Path | None = None) -> dict:
    """The raw case dict of ``shot`` on the case file ``base`` (default :data:`EXAMPLE_CASE`), by the
    module's rules; it is checked as a :class:`WhippleCase` (an :class:`InputError` names the shot)."""
    raw, case = load_base_case(base)
    for key, value in shot_settings(shot, case).items():
        raw = set_dotted(raw, key, value)
    validate(WhippleCase, raw, source=f"test shot {shot.name} on {base or EXAMPLE_CASE}")
    return raw


def load_base_case(base: str | Path | None = None) -> tuple[dict, WhippleCase]:
    """The raw dict of the case file ``base`` (default :data:`EXAMPLE_CASE`) and its :class:`WhippleCase`."""
    path = EXAMPLE_CASE if base is None else Path(base)
    if base is None and not path.is_file():
        raise InputError(f"{path}: the Table 2 7a example is not installed with the package; name a base case")
    raw = load_toml(path)
    return raw, validate(WhippleCase, raw, source=str(path))


def shot_settings(shot: DatabaseShot, case: WhippleCase) -> dict:
    """Dotted key → value of every setting that ``shot`` gives its case on the base case ``case``: the shot's
    own, and those the module's rules derive from them."""
    scale = shot.spacing_cm / case.wall.spacing_cm
    nx, ny, nz = case.wall.nodes
    return {
        "title": f"test shot {shot.name}",
        "test_shot": shot.record.model_dump(),
        "projectile.material": _material(shot, "projectile"),
        "projectile.diameter_cm": shot.diameter_cm,
        "projectile.velocity_km_s": shot.velocity_km_s,
        "projectile.obliquity_deg": shot.obliquity_deg,
        "bumper.material": _material(shot, "bumper"),
        "bumper.thickness_cm": shot.bumper_thickness_cm,
        "wall.material": _material(shot, "wall"),
        "wall.thickness_cm": shot.wall_thickness_cm,
        "wall.yield_stress_ksi": shot.wall_yield_ksi,
        "wall.spacing_cm": shot.spacing_cm,
        "wall.x_cm": [x * scale for x in case.wall.x_cm],
        "wall.z_cm": [z * scale for z in case.wall.z_cm],
        "wall.nodes": [round((nx - 1) * scale) + 1, ny, round((nz - 1) * scale) + 1],
        "shield.spacing_cm": case.shield.spacing_cm * min(1.0, shot.diameter_cm / case.projectile.diameter_cm),
        "filter.t_cut_us": case.filter.t_cut_us * max(1.0, scale),
    }
