"""Console script ``impactdyn``: one module per command group.

Heavy imports (numba kernels, matplotlib) happen inside the commands, so
``impactdyn --help`` is instant.  The error contract of :mod:`impactdyn._errors`:
an :class:`~impactdyn.InputError` or a usage error → a message on stderr and exit
code 2; a :class:`~impactdyn.SimulationError` → "simulation failed: …" and exit 1;
an ``OSError`` (an output folder that cannot be written) → a message naming the path
and exit 2; Ctrl-C or SIGTERM → the work stopped and tidied, one line saying what was kept,
and exit 130 (:mod:`impactdyn._interrupt`).  None of them prints a traceback.
"""

from __future__ import annotations

import os
import sys

# Idle OpenMP threads of the numba kernels sleep instead of spinning: on a shared or
# oversubscribed machine spinning made each parallel kernel call cost ~8 ms instead of
# ~6 µs (measured on the SPH stage).  A user's own setting wins.
os.environ.setdefault("OMP_WAIT_POLICY", "passive")

import typer  # noqa: E402

from impactdyn._errors import InputError, Interrupted, SimulationError
from impactdyn._interrupt import caused_by_interrupt, terminate_as_interrupt
from impactdyn.cli import beam, ble, debris, materials, whipple

app = typer.Typer(
    name="impactdyn",
    help="Impact dynamics: rotating beam with impact, Whipple-shield debris clouds.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    # click's plain help: typer's rich panels print every flag, --help included, as taking a <bool>
    rich_markup_mode=None,
)
app.add_typer(beam.app, name="beam")
app.add_typer(debris.app, name="debris")
app.add_typer(ble.app, name="ble")
app.add_typer(whipple.app, name="whipple")
app.add_typer(materials.app, name="materials")


def _print_version(value: bool) -> None:
    if value:
        from impactdyn import __version__

        typer.echo(f"impactdyn {__version__}")
        raise typer.Exit()


@app.callback()
def _options(version: bool = typer.Option(False, "--version", is_eager=True, callback=_print_version,
                                          help="Print impactdyn's version and exit.")) -> None:
    """The options of ``impactdyn`` itself; the work is done by the commands of each group."""


def main(argv: list[str] | None = None) -> int:
    """Entry point; returns the exit code (0 ok, 1 simulation failed, 2 bad input or unwritable output,
    130 interrupted)."""
    try:
        with terminate_as_interrupt():
            code = app(args=argv, standalone_mode=False)
    except Interrupted as err:
        print(f"interrupted: {err}", file=sys.stderr)
        return 130
    except KeyboardInterrupt:  # raised outside a command (typer takes those raised inside: code 130)
        code = 130
    except InputError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    except SimulationError as err:
        print(f"simulation failed: {err}", file=sys.stderr)
        return 1
    except OSError as err:
        where = err.filename if err.filename is not None else "output"
        print(f"error: {where}: {err.strerror or err}", file=sys.stderr)
        return 2
    except typer.Exit as e:  # pragma: no cover - click passes exit codes this way
        return e.exit_code
    except typer.Abort:  # click's word for an interrupt in its own prompts
        code = 130
    except SystemError as err:
        if not caused_by_interrupt(err):
            raise
        code = 130  # Ctrl-C as a compiled kernel returned (impactdyn._interrupt.caused_by_interrupt)
    except Exception as err:  # usage errors carry their own exit code
        if _is_usage_error(err):
            err.show()
            return err.exit_code
        raise
    if code == 130:
        # every writer stages its files and removes them when stopped (impactdyn._runfolder)
        print("interrupted: nothing was written", file=sys.stderr)
    return code if isinstance(code, int) else 0


def _is_usage_error(err: Exception) -> bool:
    """A click exception: from the copy bundled with newer typer releases, or from click itself
    with older ones (click is typer's dependency there, not ours: import it only if present)."""
    import importlib

    kinds = []
    for module in ("typer._click.exceptions", "click.exceptions"):
        try:
            kinds.append(importlib.import_module(module).ClickException)
        except ImportError:
            continue
    return isinstance(err, tuple(kinds))


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
