"""Files and run folders written atomically.

:func:`atomic_output` gives a writer a temporary name beside its target that replaces
the target only when the writer returns; every file writer of the package goes through
it.  A run is assembled in a hidden staging folder beside the target and renamed into
place only when every file is written, so an interrupted run never leaves a folder
that looks complete. An existing run folder is replaced only with ``force=True``.
"""

from __future__ import annotations

import csv
import json
import os
import shutil
import tempfile
import uuid
from collections.abc import Iterable, Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from impactdyn._errors import InputError
from impactdyn._interrupt import shielded


@contextmanager
def atomic_output(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a temporary path beside ``path`` (same suffix); it replaces ``path`` on success.

    On an exception the temporary file is removed and ``path`` is left as it was.
    """
    target = Path(path)
    if target.is_dir():
        raise InputError(f"{target}: is a folder")
    if not target.parent.is_dir():
        raise InputError(f"{target}: folder {target.parent} does not exist")
    tmp = target.with_name(f".{target.stem}.{uuid.uuid4().hex[:8]}.tmp{target.suffix}")
    try:
        yield tmp
        os.replace(tmp, target)
    finally:
        tmp.unlink(missing_ok=True)


def check_target(path: Path, force: bool) -> None:
    """Refuse, before any work, a run folder that exists (unless ``force``) or cannot be made:
    its nearest existing parent must be a folder this process may write into."""
    path = Path(path)
    if path.exists() and not force:
        raise InputError(f"{path}: run folder exists; pass --force to overwrite it")
    if path.exists() and not path.is_dir():
        raise InputError(f"{path}: exists and is not a folder")
    parent = path.absolute().parent
    while not parent.exists():
        parent = parent.parent
    if not parent.is_dir():
        raise InputError(f"{path}: cannot be created, {parent} is a file, not a folder")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise InputError(f"{path}: cannot be created, {parent} is not writable")


class FolderWriter:
    """Writes files under ``path`` (parents created); :meth:`sub` gives a writer for a subfolder."""

    def __init__(self, path: str | os.PathLike):
        self.path = Path(path)

    def sub(self, name: str) -> "FolderWriter":
        """A writer rooted at the subfolder ``name`` (created)."""
        writer = FolderWriter(self.path / name)
        writer.path.mkdir(parents=True, exist_ok=True)
        return writer

    def file(self, name: str) -> Path:
        """Path of ``name`` inside the folder (parents created)."""
        p = self.path / name
        p.parent.mkdir(parents=True, exist_ok=True)
        return p

    def write_text(self, name: str, text: str) -> Path:
        p = self.file(name)
        with atomic_output(p) as tmp:
            tmp.write_text(text)
        return p

    def write_json(self, name: str, obj: Any) -> Path:
        return self.write_text(name, json.dumps(obj, indent=2, default=_json_default) + "\n")

    def write_csv(self, name: str, header: Sequence[str], rows: Iterable[Sequence[Any]]) -> Path:
        p = self.file(name)
        with atomic_output(p) as tmp, tmp.open("w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(header)
            w.writerows(rows)
        return p


class RunFolder(FolderWriter):
    """Staging area for one run; use as a context manager.

    On normal exit the staging folder replaces ``target``; on an exception it is
    removed and ``target`` is left as it was.
    """

    def __init__(self, target: str | os.PathLike, force: bool = False):
        self.target = Path(target)
        check_target(self.target, force)
        self.target.parent.mkdir(parents=True, exist_ok=True)
        super().__init__(tempfile.mkdtemp(prefix=f".{self.target.name}.", dir=self.target.parent))
        umask = os.umask(0)  # mkdtemp makes the folder private; a run folder gets the usual permissions
        os.umask(umask)
        self.path.chmod(0o777 & ~umask)

    def __enter__(self) -> "RunFolder":
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        with shielded():  # an interrupt now would leave the staging folder, or no run folder at all
            if exc_type is not None:
                shutil.rmtree(self.path, ignore_errors=True)
                return
            if self.target.exists():
                old = self.target.with_name(f".{self.target.name}.old")
                shutil.rmtree(old, ignore_errors=True)
                self.target.rename(old)
                self.path.rename(self.target)
                shutil.rmtree(old, ignore_errors=True)
            else:
                self.path.rename(self.target)
            self.path = self.target


def _json_default(obj: Any) -> Any:
    import numpy as np

    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")
