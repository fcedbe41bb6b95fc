"""What the console script says of itself: its version, and help that reads as a user expects."""

import pytest
import typer.main

import impactdyn
from impactdyn.cli import app, main


def _command_paths(command, path=()):
    yield path
    for name, sub in getattr(command, "commands", {}).items():
        yield from _command_paths(sub, path + (name,))


PATHS = list(_command_paths(typer.main.get_command(app)))


def test_version(capsys):
    assert main(["--version"]) == 0
    assert capsys.readouterr().out.strip() == f"impactdyn {impactdyn.__version__}"


@pytest.mark.parametrize("path", PATHS, ids=lambda p: " ".join(p) or "impactdyn")
def test_flags_show_as_flags_in_help(path, capsys):
    assert main([*path, "--help"]) == 0
    out = capsys.readouterr().out
    assert "--help" in out and "<bool>" not in out, out


def test_whipple_run_help_names_the_wall_stage_and_its_verdict(capsys):
    assert main(["whipple", "run", "--help"]) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert "the wall's finite-element response and its verdict" in out
