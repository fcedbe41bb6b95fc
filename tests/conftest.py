"""Fixtures shared by the test folders: a console command run in its own process group."""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

CLI = [sys.executable, "-c", "import sys; from impactdyn.cli import main; sys.exit(main())"]


def _as_a_terminal_starts_it() -> None:
    """Run in the child before it execs: SIGINT at its default, as a shell in a terminal starts a command.
    A suite run as a background job (``nohup pytest &``) has SIGINT ignored, every child inherits that
    through exec, and the interrupt tests' Ctrl-C would then do nothing."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


class Command:
    """``impactdyn ARGS`` started in a session of its own, so a signal can go to its whole process group
    as a terminal's Ctrl-C does, and "no process left" means "no process in that group"."""

    def __init__(self, args: list[str], cwd: Path):
        self.proc = subprocess.Popen(CLI + args, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                     text=True, start_new_session=True, preexec_fn=_as_a_terminal_starts_it)

    def wait_for(self, condition, timeout: float, what: str) -> None:
        """Poll ``condition()`` until true; fail if the command ends first or ``timeout`` passes."""
        end = time.monotonic() + timeout
        while not condition():
            if self.proc.poll() is not None:
                pytest.fail(f"the command ended (exit {self.proc.returncode}) before {what}:\n"
                            f"{self.proc.stderr.read()}")
            if time.monotonic() > end:
                os.killpg(self.proc.pid, signal.SIGKILL)
                pytest.fail(f"no {what} within {timeout:g} s")
            time.sleep(0.2)

    def interrupt(self, sig: int = signal.SIGINT) -> tuple[float, str]:
        """Send ``sig`` to the process group; (seconds until the command exited, its stderr)."""
        sent = time.monotonic()
        os.killpg(self.proc.pid, sig)
        try:
            _, err = self.proc.communicate(timeout=60)
        except subprocess.TimeoutExpired:
            os.killpg(self.proc.pid, signal.SIGKILL)
            pytest.fail(f"still running 60 s after {signal.Signals(sig).name}")
        return time.monotonic() - sent, err

    @property
    def returncode(self) -> int | None:
        return self.proc.returncode

    def group_is_empty(self, grace: float = 5.0) -> bool:
        """No live process left in the group.  A zombie is dead already (an orphan waits there for an
        init that reaps it, which a container may lack); multiprocessing's resource tracker ends on
        its own just after its parent, so it is allowed a moment."""
        end = time.monotonic() + grace
        while _live_members(self.proc.pid):
            if time.monotonic() > end:
                return False
            time.sleep(0.1)
        return True


def _live_members(pgid: int) -> list[str]:
    """``pid command`` of each process of the group ``pgid`` that is not a zombie (from /proc)."""
    members = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            text = stat.read_text()
        except OSError:  # the process ended meanwhile
            continue
        name_end = text.rindex(")")
        state, _, group = text[name_end + 2:].split()[:3]
        if int(group) == pgid and state != "Z":
            members.append(f"{stat.parent.name} {text[text.index('(') + 1:name_end]}")
    return members


class CommandLine:
    """What a test of the console commands needs: start one, run one to its end, look for leftovers."""

    def __init__(self):
        self.started: list[Command] = []

    def start(self, args: list[str], cwd: Path) -> Command:
        """``impactdyn ARGS`` started in the background (killed at teardown if still running)."""
        self.started.append(Command(args, cwd))
        return self.started[-1]

    @staticmethod
    def run(args: list[str], cwd: Path, timeout: float = 600) -> subprocess.CompletedProcess:
        """``impactdyn ARGS`` run to its end."""
        return subprocess.run(CLI + args, cwd=cwd, capture_output=True, text=True, timeout=timeout)

    @staticmethod
    def finished(folder: Path, members: str) -> list[Path]:
        """The member runs in place under ``folder/members`` (e.g. ``runs``), by their summary files.

        A member's hidden staging folder holds its summary before it is renamed into place, and
        ``Path.glob``'s ``*`` matches hidden names: such a folder is not a finished member."""
        return sorted(p.parent for p in Path(folder).glob(f"{members}/*/summary.json")
                      if not p.parent.name.startswith("."))

    @staticmethod
    def hidden(folder: Path) -> list[Path]:
        """Staging folders and temporary files (their names start with a dot) anywhere under ``folder``."""
        return list(Path(folder).rglob(".*"))


@pytest.fixture
def cli():
    """A :class:`CommandLine`; the commands it started and that still run are killed at teardown."""
    commands = CommandLine()
    yield commands
    for command in commands.started:
        if command.proc.poll() is None:
            os.killpg(command.proc.pid, signal.SIGKILL)
            command.proc.wait()
