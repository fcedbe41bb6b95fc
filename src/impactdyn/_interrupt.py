"""How a command stops: Ctrl-C and SIGTERM alike, in the main process only, with the clean-up shielded.

The contract (every command that runs work): the first Ctrl-C or SIGTERM stops submitting
work, cancels what runs, stops the workers and exits with 130 and one line saying what was
kept.  Three pieces make it:

* :func:`terminate_as_interrupt`: SIGTERM raises ``KeyboardInterrupt`` in the main thread, so a
  ``kill`` takes the same path as Ctrl-C (Python's default for SIGTERM ends the process at once,
  leaving staging folders and worker processes behind).
* :func:`ignore_interrupts`: the initializer of every worker process.  A terminal's Ctrl-C goes to
  the whole process group; a worker that died of it mid-task made the pool replace it and go on
  with the queue, so only the main process reacts and it stops the workers itself.
* :func:`shielded`: a second Ctrl-C while the main process tidies up (stops the workers, removes
  staging folders, writes the table so far) would leave the half-tidied state the contract forbids;
  it is ignored until the tidying is done.
* :func:`deferred`: a Ctrl-C that comes while a finished member is being recorded (its row, the
  table, the count the stop message reports) is held until the record is complete, then raised.
* :func:`caused_by_interrupt`: a Ctrl-C whose handler runs just as a compiled numba kernel returns
  reaches Python as ``SystemError: CPUDispatcher(...) returned a result with an exception set``, the
  ``KeyboardInterrupt`` its cause; the console script takes such an error for the interrupt it is.
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager

STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)


def _raise_interrupt(signum, frame) -> None:
    raise KeyboardInterrupt(signal.Signals(signum).name)


@contextmanager
def terminate_as_interrupt() -> Iterator[None]:
    """SIGTERM raises ``KeyboardInterrupt`` inside the block (main thread only; elsewhere a no-op)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGTERM, _raise_interrupt)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


def ignore_interrupts() -> None:
    """Worker-process initializer: Ctrl-C is the main process's to handle; SIGTERM (sent by the
    main process when it stops the pool) keeps its default, immediate end."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)


@contextmanager
def shielded() -> Iterator[None]:
    """Ignore Ctrl-C and SIGTERM inside the block: the command is stopping already, and its tidying
    must run to the end."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {sig: signal.signal(sig, signal.SIG_IGN) for sig in STOP_SIGNALS}
    try:
        yield
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)


@contextmanager
def deferred() -> Iterator[None]:
    """Hold Ctrl-C and SIGTERM until the block is done, then raise ``KeyboardInterrupt``: for a step
    that an interrupt must not cut half-way, and that must not swallow the interrupt either."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    caught: list[int] = []
    previous = {sig: signal.signal(sig, lambda signum, frame: caught.append(signum)) for sig in STOP_SIGNALS}
    try:
        yield
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
    if caught:
        raise KeyboardInterrupt(signal.Signals(caught[0]).name)


def caused_by_interrupt(err: BaseException) -> bool:
    """Whether ``err`` is, or was raised because of, a ``KeyboardInterrupt`` (its ``__cause__`` or
    ``__context__``, followed down the chain)."""
    seen: set[int] = set()
    link: BaseException | None = err
    while link is not None and id(link) not in seen:
        if isinstance(link, KeyboardInterrupt):
            return True
        seen.add(id(link))
        link = link.__cause__ or link.__context__
    return False
