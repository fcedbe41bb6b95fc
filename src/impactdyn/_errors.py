"""The package's error contract: two exception types, each with its own exit code.

* :class:`InputError` (a ``ValueError``): the user's input is wrong — a case key, a
  file, a command-line value, a library argument.  The CLI prints it as
  ``error: …`` and exits with 2; nothing is written.
* :class:`SimulationError` (a ``RuntimeError``): a solver could not carry a valid
  input through (the beam's endless chattering, an SPH or wall-solver breakdown).
  Every solver's failure type derives from it; the CLI prints
  ``simulation failed: …`` and exits with 1, and no run folder is left behind.

An ``OSError`` while writing results (an unwritable output folder, a full disk) is
reported by the CLI with the path it concerns and exit code 2.  An interrupt (Ctrl-C, or
SIGTERM, which the CLI turns into one) ends a command with exit code 130 and one line
saying what was kept: :class:`Interrupted` carries that line where something was.  Any
other exception is a bug and keeps its traceback.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path


class InputError(ValueError):
    """Invalid user input (a case file, a legacy deck, a command-line value).

    The message names the file, line or key at fault.
    """


class SimulationError(RuntimeError):
    """A run that cannot continue: the message says where and why (time, step, quantity)."""


class Interrupted(BaseException):
    """Raised in place of the ``KeyboardInterrupt`` by a command that tidied up after it and kept
    something (a family of runs keeps its finished runs and their table, :mod:`impactdyn._family`);
    the message says what.  Not a ``KeyboardInterrupt``: typer turns those into a bare exit code and
    the message would be lost; catch both where a script must go on after an interrupt."""


@contextmanager
def reading(path: str | Path, what: str = "file") -> Iterator[None]:
    """Turn the OS errors of opening ``path`` into an :class:`InputError` naming it.

    ``what`` names the kind of file in the folder message ("is a folder, not a case file").
    """
    try:
        yield
    except FileNotFoundError:
        raise InputError(f"{path}: no such file") from None
    except IsADirectoryError:
        raise InputError(f"{path}: is a folder, not a {what}") from None
    except PermissionError:
        raise InputError(f"{path}: cannot be read (permission denied)") from None
