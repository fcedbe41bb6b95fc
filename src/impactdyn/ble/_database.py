"""The Whipple-shield test database: reader, checks, and the shots near a configuration.

The packaged file is pyBLOSSUM's ``database_whipple_pyBLOSSUM.csv`` (1135 light-gas-gun
shots on aluminium Whipple shields, MIT licence: ``data/LICENSE`` and ``data/README.md``
beside this module).  Layout: a header row, a units row, then one shot per row.  The reader
needs the columns of :data:`COLUMNS` with exactly those units (others may be present and
are ignored) and refuses anything malformed with an :class:`~impactdyn.InputError` that
names the file and line.

Twins: one firing reported twice
--------------------------------
Some shots are in the file twice, from two reports of one test programme (AFML-TR-67-324
and AFML-TR-68-257 share 15 shot IDs; Piekutowski 2011 and 2013 one; ELC 87-163 and
NASA/TP-2003-210788 one), sometimes with different transcriptions of the target.  Records
are *twins* when they have the same shot ID and agree on what the gun fired:

    |d₁/d₂ − 1| ≤ 10 %,   |V₁/V₂ − 1| ≤ 10 %,   |θ₁ − θ₂| ≤ 5°

(:data:`TWIN_TOLERANCE`, :data:`TWIN_OBLIQUITY_DEG`).  The target (t_b, t_w, S) is not
compared: it is where the reports of one firing disagree (shot 2067: bumper 1.575 cm in
one, 0.16 cm in the other).  The bounds sit in a wide gap of the packaged file: records of
one firing differ by at most 7 % in d (0.2593 and 0.2779 cm) and 5.4 % in V, while records
that merely share an ID (different laboratories numbering from 1) differ by a factor of 2
or more in d.  Twins must stay on one side of any split of the shots into fitting and
checking sets (:meth:`ShotDatabase.with_twins`); twins with opposite outcomes are
*conflicting* (the file cannot say what the shot did).  The same firing filed under two
different IDs is not detected.
"""

from __future__ import annotations

import csv
import io
from dataclasses import dataclass, fields, replace
from pathlib import Path

import numpy as np

from impactdyn._errors import InputError, reading
from impactdyn.ble import _check

#: The packaged database.
DATABASE_PATH = Path(__file__).parent / "data" / "database_whipple_pyBLOSSUM.csv"

#: column: (unit in the units row, ShotDatabase attribute); the numeric ones are > 0,
#: except ``angle`` (0 ≤ θ < 90).
COLUMNS = {
    "source": ("-", "source"),
    "shotID": ("-", "shot_id"),
    "proj_density": ("g/cm3", "projectile_density_g_cm3"),
    "proj_diam": ("cm", "diameter_cm"),
    "angle": ("deg", "obliquity_deg"),
    "velocity": ("km/s", "velocity_km_s"),
    "bumper_density": ("g/cm3", "bumper_density_g_cm3"),
    "bumper_thick": ("cm", "bumper_thickness_cm"),
    "standoff": ("cm", "spacing_cm"),
    "wall_density": ("g/cm3", "wall_density_g_cm3"),
    "wall_yield": ("ksi", "wall_yield_ksi"),
    "wall_thick": ("cm", "wall_thickness_cm"),
    "proj_mat": ("-", "projectile_material"),
    "bumper_mat": ("-", "bumper_material"),
    "wall_mat": ("-", "wall_material"),
    "result": ("-", "perforated"),
    "perforated_class": ("-", "perforated"),
}
_TEXT = ("source", "shotID", "proj_mat", "bumper_mat", "wall_mat")
_NUMERIC = tuple(c for c in COLUMNS if c not in (*_TEXT, "result", "perforated_class"))
_OUTCOMES = {"P": ("1", True), "NP": ("0", False)}
#: Twins agree on projectile diameter and speed within this relative bound (module docstring).
TWIN_TOLERANCE = 0.10
#: ... and on obliquity within this many degrees.
TWIN_OBLIQUITY_DEG = 5.0


@dataclass(frozen=True)
class ShotDatabase:
    """Test shots as arrays, one element per shot (literature units).

    The five shield attributes have the names of :class:`~impactdyn.ble.WhippleShield`'s,
    so the Whipple equations evaluate every shot with its own bumper, wall, stand-off,
    yield stress and densities.  ``perforated``: the rear wall was perforated or spalled
    (result P); ``line``: the shot's line in ``path``; ``*_material``: the alloy names as
    written in the file.  ``twin_group``: a label per shot, shared by twins (module
    docstring) and unique otherwise (the index of the group's first shot in the file as
    read); ``twin_conflict``: the shot's twin group holds both outcomes.  A subset keeps the
    labels of the file it came from.
    """

    path: str
    line: np.ndarray
    source: np.ndarray
    shot_id: np.ndarray
    projectile_density_g_cm3: np.ndarray
    diameter_cm: np.ndarray
    obliquity_deg: np.ndarray
    velocity_km_s: np.ndarray
    bumper_density_g_cm3: np.ndarray
    bumper_thickness_cm: np.ndarray
    spacing_cm: np.ndarray
    wall_density_g_cm3: np.ndarray
    wall_yield_ksi: np.ndarray
    wall_thickness_cm: np.ndarray
    perforated: np.ndarray
    projectile_material: np.ndarray
    bumper_material: np.ndarray
    wall_material: np.ndarray
    twin_group: np.ndarray
    twin_conflict: np.ndarray

    def __len__(self) -> int:
        return len(self.line)

    def subset(self, mask) -> ShotDatabase:
        """The shots where ``mask`` (a boolean array, one element per shot) is true."""
        return replace(self, **{f.name: getattr(self, f.name)[mask] for f in fields(self) if f.name != "path"})

    def with_twins(self, mask) -> np.ndarray:
        """``mask`` grown so that a shot's twins are selected whenever it is.

        Every twin group is then wholly in or wholly out, so no firing is both fitted and
        checked against.  ``mask``: boolean, one element per shot.
        """
        mask = np.asarray(mask, dtype=bool)
        return np.isin(self.twin_group, self.twin_group[mask])


def twin_groups(shot_id, diameter_cm, velocity_km_s, obliquity_deg) -> np.ndarray:
    """The twin-group label of each shot (module docstring): the index of its group's first shot.

    Records with one ID that pairwise agree join one group, and groups are closed under
    agreement (a shot agreeing with any member joins).
    """
    label = np.arange(len(shot_id))
    by_id: dict[str, list[int]] = {}
    for i, sid in enumerate(shot_id):
        by_id.setdefault(sid, []).append(i)
    for members in by_id.values():
        for k, i in enumerate(members):
            for j in members[:k]:
                if (abs(diameter_cm[i] / diameter_cm[j] - 1.0) <= TWIN_TOLERANCE
                        and abs(velocity_km_s[i] / velocity_km_s[j] - 1.0) <= TWIN_TOLERANCE
                        and abs(obliquity_deg[i] - obliquity_deg[j]) <= TWIN_OBLIQUITY_DEG):
                    old, new = max(label[i], label[j]), min(label[i], label[j])
                    label[label == old] = new
    return label


def conflicting(twin_group: np.ndarray, perforated: np.ndarray) -> np.ndarray:
    """Per shot: its twin group holds a perforation and a non-perforation."""
    groups = np.unique(twin_group)
    both = [g for g in groups if perforated[twin_group == g].any() and not perforated[twin_group == g].all()]
    return np.isin(twin_group, both)


def _number(path, line: int, column: str, cell: str) -> float:
    try:
        x = float(cell)
    except ValueError:
        raise InputError(f"{path}:{line}: column {column!r}: {cell!r} is not a number") from None
    ok = 0.0 <= x < 90.0 if column == "angle" else x > 0.0
    if not (np.isfinite(x) and ok):
        need = "in [0, 90) degrees from the target normal" if column == "angle" else "a finite number > 0"
        raise InputError(f"{path}:{line}: column {column!r}: {cell!r} must be {need}")
    return x


def _outcome(path, line: int, result: str, klass: str) -> bool:
    if result not in _OUTCOMES:
        raise InputError(f"{path}:{line}: column 'result': {result!r} must be P or NP")
    expected, perforated = _OUTCOMES[result]
    if klass != expected:
        raise InputError(f"{path}:{line}: column 'perforated_class': {klass!r} contradicts result {result} "
                         f"(expected {expected})")
    return perforated


def _header(path, rows) -> tuple[dict[str, int], int]:
    """Column positions by name and the number of header cells, after checking both rows."""
    header = next(rows, None)
    if header is None:
        raise InputError(f"{path}:1: empty file; expected a header row naming the columns")
    index = {name.strip(): i for i, name in enumerate(header)}
    missing = [c for c in COLUMNS if c not in index]
    if missing:
        raise InputError(f"{path}:1: missing column(s) {', '.join(map(repr, missing))} in the header row")
    units = next(rows, None)
    if units is None:
        raise InputError(f"{path}:2: no units row after the header")
    for column, (unit, _) in COLUMNS.items():
        got = units[index[column]].strip() if index[column] < len(units) else ""
        if got != unit:
            raise InputError(f"{path}:2: units row: column {column!r} has unit {got!r}, expected {unit!r}")
    return index, len(header)


def read_database(path: str | Path | None = None) -> ShotDatabase:
    """Read and check a test database (``None``: the packaged 1135-shot file).

    Every malformed thing (missing column, wrong or missing unit, wrong cell count,
    non-numeric or out-of-range cell, result not P/NP or contradicting perforated_class,
    no shots) raises :class:`~impactdyn.InputError` naming the file and line.
    """
    path = DATABASE_PATH if path is None else Path(path)
    with reading(path, "database file"):
        raw = path.read_bytes()
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as err:
        raise InputError(f"{path}: not UTF-8 text ({err.reason} at byte {err.start})") from None
    reader = csv.reader(io.StringIO(text, newline=""))
    rows = iter(reader)
    index, width = _header(path, rows)
    values: dict[str, list] = {c: [] for c in (*_TEXT, *_NUMERIC)}
    perforated, lines = [], []
    for row in rows:
        line = reader.line_num
        if not any(cell.strip() for cell in row):
            continue
        if len(row) != width:
            raise InputError(f"{path}:{line}: {len(row)} cells, expected {width} (one per header column)")
        cell = {c: row[index[c]].strip() for c in COLUMNS}
        for c in _TEXT:
            values[c].append(cell[c])
        for c in _NUMERIC:
            values[c].append(_number(path, line, c, cell[c]))
        perforated.append(_outcome(path, line, cell["result"], cell["perforated_class"]))
        lines.append(line)
    if not lines:
        raise InputError(f"{path}:{reader.line_num + 1}: no shots after the header and units rows")
    arrays = {COLUMNS[c][1]: np.array(values[c], dtype=object if c in _TEXT else float) for c in values}
    twins = twin_groups(arrays["shot_id"], arrays["diameter_cm"], arrays["velocity_km_s"], arrays["obliquity_deg"])
    perforated = np.array(perforated)
    return ShotDatabase(path=str(path), line=np.array(lines), perforated=perforated, twin_group=twins,
                        twin_conflict=conflicting(twins, perforated), **arrays)


def nearby_shots(shield, obliquity_deg: float | None = None, database: ShotDatabase | None = None,
                 band: float = 0.10, obliquity_band_deg: float = 10.0) -> ShotDatabase:
    """The test shots on a shield like ``shield`` (the packaged database by default).

    A shot is near when its bumper thickness t_b, wall thickness t_w and stand-off S are
    each within ``band`` (relative, default ±10 %: |x/x_shield − 1| ≤ band) of the
    shield's, and, if ``obliquity_deg`` is given, its obliquity within
    ``obliquity_band_deg`` (default ±10°) of it.  Materials, yield stress and densities are
    not compared (the database is aluminium throughout).
    """
    band = _check.positive("band", band)
    db = read_database() if database is None else database
    near = np.ones(len(db), dtype=bool)
    for attr in ("bumper_thickness_cm", "wall_thickness_cm", "spacing_cm"):
        near &= np.abs(getattr(db, attr) / getattr(shield, attr) - 1.0) <= band
    if obliquity_deg is not None:
        theta = _check.scalar_obliquity(obliquity_deg)
        near &= np.abs(db.obliquity_deg - theta) <= _check.positive("obliquity_band_deg", obliquity_band_deg)
    return db.subset(near)
