"""The one exception type that means "the user's input is wrong".

The CLI turns it into a one-line message on stderr and exit code 2, without a
traceback; library callers can catch it like any other ``ValueError``.
"""

from __future__ import annotations


class InputError(ValueError):
    """Invalid user input (a case file, a legacy deck, a command-line value).

    The message names the file, line or key at fault.
    """
