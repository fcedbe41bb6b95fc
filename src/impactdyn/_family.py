"""The folder of a family of runs (a beam sweep, a Whipple campaign, a limit search): kept as it grows.

A single run is staged and renamed into place when complete (:class:`~impactdyn._runfolder.RunFolder`).
A family can take hours, so its folder is written in place instead, and every piece of it
is complete when it appears: each member run is staged and renamed into place by its own
writer, and the family's table is rewritten (atomically) after each member finishes.  What an
interrupt leaves is therefore the finished members and their table, which ``--resume`` picks
up: a member whose folder is there is read back, not run again.

``family.json`` records the command and its settings (the validated base case, the values
swept, the search options): a resume under other settings would mix two families in one
table, so it is refused, naming the settings that differ.  ``complete`` turns true when
the family's last table and plot are written.

On leaving the block by an exception (Ctrl-C, SIGTERM, a failed member) the workers have
already been stopped (:func:`impactdyn._parallel.run_tasks`); what a stopped member was
staging is removed here, so no hidden folder is left, and an interrupt is re-raised as
:class:`~impactdyn._errors.Interrupted` with the line saying what was kept.
"""

from __future__ import annotations

import json
import shutil
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from impactdyn._errors import InputError, Interrupted
from impactdyn._interrupt import deferred, shielded
from impactdyn._runfolder import FolderWriter, check_target
from impactdyn._sweep import run_all

RECORD = "family.json"


class FamilyFolder(FolderWriter):
    """The family folder ``target`` for ``command`` run with ``settings`` (JSON-serialisable);
    use as a context manager.  ``table`` (the table's file) and ``member`` (what one run is called:
    shot, case) word the interrupt message; the caller counts the members in :attr:`finished`.

    Made before any work: an existing ``target`` is refused unless ``force`` (it is removed)
    or ``resume`` (its settings must be these; what an earlier stop left staging is removed).
    """

    def __init__(self, target: str | Path, command: str, settings: dict[str, Any], *, table: str,
                 member: str = "run", force: bool = False, resume: bool = False):
        target = Path(target)
        if force and resume:
            raise InputError("--force and --resume: give one (--force starts over, --resume goes on)")
        check_target(target, force or resume)
        super().__init__(target)
        self.command, self.table, self.member = command, table, member
        self.settings = json.loads(json.dumps(settings))  # as it reads back from the record
        self.finished = 0
        if target.exists() and resume:
            self._check_resumable()
            remove_staging(target)
        elif target.exists():
            shutil.rmtree(target)
        target.mkdir(parents=True, exist_ok=True)
        self._write_record(complete=False)

    def __enter__(self) -> "FamilyFolder":
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        if exc_type is None:
            self._write_record(complete=True)
            return
        with shielded():
            remove_staging(self.path)
        if issubclass(exc_type, KeyboardInterrupt):
            plural = "s" if self.finished != 1 else ""
            kept = (f"{self.finished} finished {self.member}{plural} and {self.table} kept in {self.path}; "
                    "the same command with --resume finishes it" if self.finished
                    else f"no {self.member} had finished; {self.path} holds the settings only")
            raise Interrupted(kept) from None

    def _check_resumable(self) -> None:
        record = self.path / RECORD
        try:
            earlier = json.loads(record.read_text())
        except FileNotFoundError:
            raise InputError(f"{self.path}: not a folder of `{self.command}` ({RECORD} is missing); "
                             "nothing to resume") from None
        except (OSError, ValueError) as err:
            raise InputError(f"{record}: cannot be read ({err}); nothing to resume") from None
        if earlier.get("command") != self.command:
            raise InputError(f"{self.path}: a folder of `{earlier.get('command')}`, not of `{self.command}`")
        differ = _differences(earlier.get("settings", {}), self.settings)
        if differ:
            raise InputError(f"{self.path}: started with other settings ({', '.join(differ[:6])}"
                             f"{', …' if len(differ) > 6 else ''}); --resume needs the same case and options "
                             "(or start over with --force)")

    def _write_record(self, complete: bool) -> None:
        self.write_json(RECORD, {"command": self.command, "complete": complete, "settings": self.settings})


def run_members(fn: Callable[[Any], Any], summaries: Sequence[Path], make_tasks: Callable[[list[int]], list],
                record: Callable[[int, dict], None], **schedule: Any) -> None:
    """Bring every member ``k`` of a family to an end and ``record(k, summary)`` it, in the main process.

    A member whose summary file ``summaries[k]`` exists is read back, not run (a resume); the
    others run as ``fn`` of the tasks ``make_tasks(pending)`` builds for them, scheduled as
    :func:`impactdyn._sweep.run_all` takes ``schedule``, and are recorded as they finish.  A member
    run writes its summary file itself (or ``record`` does).  On a stop, a member that finished
    while the others were being stopped (its folder renamed into place before its result reached
    this process) is read back and recorded too, so the table holds every finished member; an
    interrupt that comes while a member is being recorded waits for the record to be whole.
    """
    recorded: set[int] = set()
    pending: list[int] = []

    def take(k: int, summary: dict) -> None:
        # an interrupt in the middle of a record would leave a row without its count (or the
        # reverse): it waits until the member is recorded whole
        with deferred():
            record(k, summary)
            recorded.add(k)

    try:
        for k, path in enumerate(summaries):
            if path.exists():
                take(k, json.loads(path.read_text()))
            else:
                pending.append(k)
        run_all(fn, make_tasks(pending), on_result=lambda i, summary: take(pending[i], summary), **schedule)
    except BaseException:
        with shielded():
            for k, path in enumerate(summaries):
                if k not in recorded and path.exists():
                    record(k, json.loads(path.read_text()))
        raise


def remove_staging(folder: Path) -> None:
    """Remove every hidden entry under ``folder``: the staging folders and temporary files of
    writers that were stopped (:mod:`impactdyn._runfolder` names them with a leading dot)."""
    for path in sorted(Path(folder).rglob(".*"), key=lambda p: len(p.parts)):
        if path.is_dir() and not path.is_symlink():
            shutil.rmtree(path, ignore_errors=True)
        else:
            path.unlink(missing_ok=True)


def _differences(earlier: Any, now: Any, key: str = "") -> list[str]:
    """Dotted keys whose values differ between two settings records."""
    if isinstance(earlier, dict) and isinstance(now, dict):
        return [d for k in sorted(set(earlier) | set(now), key=str)
                for d in _differences(earlier.get(k), now.get(k), f"{key}.{k}" if key else str(k))]
    return [] if earlier == now else [key or "settings"]
