"""What the validation sets say of the default simulated verdict: one record, shipped with the package.

``data/validation_record.json`` holds, for each validation set run with the current default of the
wall stage, how many test shots it has and how many of them perforated, how many the simulated
verdict and the JSC 2011 equation called right, how many perforations each called safe
(false-safe) and how many holds each called perforated (false alarm), the shots' diameters and
speeds, the hash of the set's selection rule and the command that produced the numbers.  The
README, the docs' landing page, each run's caution and the report's banner take their figures
from here (``tests/whipple/test_validation_record.py`` checks the README and the landing page
against it), so the figures are written once and follow the default when the sets are rerun.

When a set is rerun, its entry is rebuilt from the ``whipple validate`` folder, never typed::

    from impactdyn.whipple import record_validation
    record_validation("runs/validate-set-2",
                      "impactdyn whipple validate --select set-2 --workers 2 -o runs/validate-set-2")
"""

from __future__ import annotations

import csv
import json
from dataclasses import asdict, dataclass
from pathlib import Path

from impactdyn._errors import InputError

#: The record shipped with the package.
RECORD_PATH = Path(__file__).resolve().parent / "data" / "validation_record.json"


@dataclass(frozen=True)
class Score:
    """One verdict's score on a set of shots: shots called right, perforations called safe (the
    dangerous error), holds called perforated."""

    right: int
    false_safe: int
    false_alarm: int

    def __add__(self, other: Score) -> Score:
        return Score(self.right + other.right, self.false_safe + other.false_safe,
                     self.false_alarm + other.false_alarm)


@dataclass(frozen=True)
class SetRecord:
    """One validation set as run: its rule, the command, its shots and both verdicts' scores."""

    name: str
    rule_sha256: str
    command: str
    shots: int
    perforated: int
    diameter_cm: tuple[float, float]
    velocity_km_s: tuple[float, float]
    simulated: Score
    jsc: Score


@dataclass(frozen=True)
class ValidationRecord:
    """The validation sets of the current default, and their totals."""

    verdict: str
    sets: tuple[SetRecord, ...]

    @property
    def shots(self) -> int:
        return sum(s.shots for s in self.sets)

    @property
    def perforated(self) -> int:
        return sum(s.perforated for s in self.sets)

    @property
    def simulated(self) -> Score:
        return sum((s.simulated for s in self.sets), Score(0, 0, 0))

    @property
    def jsc(self) -> Score:
        return sum((s.jsc for s in self.sets), Score(0, 0, 0))

    @property
    def diameter_cm(self) -> tuple[float, float]:
        return min(s.diameter_cm[0] for s in self.sets), max(s.diameter_cm[1] for s in self.sets)

    @property
    def velocity_km_s(self) -> tuple[float, float]:
        return min(s.velocity_km_s[0] for s in self.sets), max(s.velocity_km_s[1] for s in self.sets)

    @property
    def set_names(self) -> str:
        """"sets 1–3" for set-1, set-2, set-3; the names listed where they do not run on."""
        numbers = [s.name.removeprefix("set-") for s in self.sets]
        if len(numbers) == 1:
            return f"set {numbers[0]}"
        if all(n.isdigit() for n in numbers) and [int(n) for n in numbers] == list(
                range(int(numbers[0]), int(numbers[0]) + len(numbers))):
            return f"sets {numbers[0]}–{numbers[-1]}"
        return "sets " + ", ".join(numbers[:-1]) + f" and {numbers[-1]}"


def validation_record(path: str | Path = RECORD_PATH) -> ValidationRecord:
    """The record at ``path`` (default: the one shipped with the package)."""
    raw = _read_json(Path(path))
    try:
        sets = tuple(_set_record(entry) for entry in raw["sets"])
        return ValidationRecord(verdict=raw["verdict"], sets=sets)
    except (KeyError, TypeError, ValueError) as err:
        raise InputError(f"{path}: not a validation record ({type(err).__name__}: {err})") from None


def _set_record(entry: dict) -> SetRecord:
    return SetRecord(**{**entry, "diameter_cm": tuple(entry["diameter_cm"]),
                        "velocity_km_s": tuple(entry["velocity_km_s"]),
                        "simulated": Score(**entry["simulated"]), "jsc": Score(**entry["jsc"])})


def perforations_called_safe(record: ValidationRecord) -> str:
    """How many tested perforations the simulated verdict called safe, in words."""
    missed, of = record.simulated.false_safe, record.perforated
    if missed == of:
        return f"called every tested perforation safe ({missed} of {of})"
    return f"called {missed} of {of} tested perforations safe"


def limit_statement(record: ValidationRecord | None = None) -> str:
    """The limit of the simulated verdict in words, with the record's figures: what a user reads first."""
    r = validation_record() if record is None else record
    (d_lo, d_hi), (v_lo, v_hi) = r.diameter_cm, r.velocity_km_s
    return (f"On validation {r.set_names} ({r.shots} test shots, {d_lo:.2f}–{d_hi:.2f}-cm aluminium spheres at "
            f"{v_lo:.1f}–{v_hi:.1f} km/s) the simulated wall verdict {perforations_called_safe(r)} and was right "
            f"on {r.simulated.right} of {r.shots}; the JSC 2011 equation was right on {r.jsc.right} of {r.shots} "
            f"and called {r.jsc.false_safe} of {r.perforated} perforations safe.  The simulated wall is loaded by "
            "the debris cloud's momentum alone, without the solid fragments whose craters perforate real walls: "
            "its \"no perforation\" is not evidence that a shield holds; design with the equation's verdict.")


def quoted_figures(record: ValidationRecord | None = None) -> tuple[str, ...]:
    """The figures every statement of the limit quotes, as it writes them ("18 of 18", …)."""
    r = validation_record() if record is None else record
    return (f"{r.simulated.false_safe} of {r.perforated}", f"{r.simulated.right} of {r.shots}",
            f"{r.jsc.right} of {r.shots}", f"{r.jsc.false_safe} of {r.perforated}")


def set_entry(folder: str | Path, command: str) -> SetRecord:
    """A set's entry rebuilt from a finished ``whipple validate`` folder (``family.json``,
    ``scores.json``, ``validation.csv``); ``command``: the command that wrote the folder."""
    folder = Path(folder)
    family = _read_json(folder / "family.json")
    if family.get("command") != "whipple validate" or not family.get("complete"):
        raise InputError(f"{folder / 'family.json'}: not a finished `whipple validate` folder "
                         "(rerun it, or --resume it to the end)")
    scores = _read_json(folder / "scores.json")
    try:
        rule = scores["selection"].get("rule")
        if rule is None:
            raise InputError(f"{folder / 'scores.json'}: the shots were chosen by --lines, not by a selection "
                             "rule: a validation set is a fixed rule's shots")

        def score(who: str) -> Score:
            overall = scores[who]["overall"]
            return Score(overall["accuracy"]["count"], overall["false_safe"]["count"],
                         overall["false_alarm"]["count"])

        simulated, jsc = score("simulated"), score("jsc")
        shots, perforated = scores["n_shots"], scores["simulated"]["overall"]["false_safe"]["of"]
        sha256 = scores["selection"]["sha256"]
    except (KeyError, TypeError, AttributeError) as err:
        raise InputError(f"{folder / 'scores.json'}: not the scores of `whipple validate` "
                         f"({type(err).__name__}: {err})") from None
    diameters, velocities = _ranges(folder / "validation.csv", shots)
    return SetRecord(name=rule, rule_sha256=sha256, command=command, shots=shots, perforated=perforated,
                     diameter_cm=diameters, velocity_km_s=velocities, simulated=simulated, jsc=jsc)


def _ranges(table: Path, shots: int) -> tuple[tuple[float, float], tuple[float, float]]:
    """The shots' diameters and speeds, (lowest, highest) of each, from ``validation.csv``."""
    try:
        with table.open(newline="") as f:
            rows = list(csv.DictReader(f))
        d = [float(r["diameter_cm"]) for r in rows]
        v = [float(r["velocity_km_s"]) for r in rows]
    except FileNotFoundError:
        raise InputError(f"{table}: missing; a `whipple validate` folder has it") from None
    except (KeyError, TypeError, ValueError) as err:
        raise InputError(f"{table}: not a `whipple validate` table ({type(err).__name__}: {err})") from None
    if len(rows) != shots:
        raise InputError(f"{table}: {len(rows)} shots, the scores count {shots}")
    return (min(d), max(d)), (min(v), max(v))


def record_validation(folder: str | Path, command: str, path: str | Path = RECORD_PATH) -> ValidationRecord:
    """Put the set that the ``whipple validate`` folder ``folder`` ran into the record at ``path``
    (replacing that set's entry, the sets kept in name order); returns the new record."""
    from impactdyn._runfolder import atomic_output

    entry = set_entry(folder, command)
    record = validation_record(path)
    sets = sorted([s for s in record.sets if s.name != entry.name] + [entry], key=lambda s: s.name)
    raw = {"verdict": record.verdict, "sets": [asdict(s) for s in sets]}
    with atomic_output(path) as tmp:
        tmp.write_text(json.dumps(raw, indent=2) + "\n")
    return validation_record(path)


def _read_json(path: Path) -> dict:
    try:
        return json.loads(path.read_text())
    except FileNotFoundError:
        raise InputError(f"{path}: missing") from None
    except json.JSONDecodeError as err:
        raise InputError(f"{path}: line {err.lineno}: not JSON ({err.msg})") from None
