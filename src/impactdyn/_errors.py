"""The one exception type that means "the user's input is wrong".

The CLI turns it into a one-line message on stderr and exit code 2, without a
traceback; library callers can catch it like any other ``ValueError``.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path


class InputError(ValueError):
    """Invalid user input (a case file, a legacy deck, a command-line value).

    The message names the file, line or key at fault.
    """


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
