"""Rotating flexible beam with impact (the 1988 report: IMPACTC, IMPACTB, ROOTM, INTEG).

>>> from impactdyn.beam import load_case, simulate
>>> result = simulate(load_case("examples/beam/impactb_sample.toml"))  # doctest: +SKIP
"""

from pathlib import Path

from impactdyn.beam._case import BeamCase
from impactdyn.beam._chain import ChainResult, RigidLinkChain
from impactdyn.beam._contact import CONTACT_LAWS, listing_restitution, register_contact
from impactdyn.beam._model import BeamModel
from impactdyn.beam._modes import ModalIntegrals, eigenvalues, modal_integrals, shapes, sigma
from impactdyn.beam._runfiles import write_run
from impactdyn.beam._simulate import Impact, Result, SimulationError, simulate
from impactdyn.beam._sweep import parse_vary, run_sweep


def load_case(path: str | Path) -> BeamCase:
    """Read and validate a beam case file (raises :class:`impactdyn.InputError`)."""
    from impactdyn._config import load_case as _load

    return _load(BeamCase, path)


__all__ = [
    "BeamCase", "BeamModel", "CONTACT_LAWS", "ChainResult", "Impact", "ModalIntegrals", "Result", "RigidLinkChain",
    "SimulationError", "eigenvalues", "listing_restitution", "load_case", "modal_integrals", "parse_vary",
    "register_contact", "run_sweep", "shapes", "sigma", "simulate", "write_run",
]
