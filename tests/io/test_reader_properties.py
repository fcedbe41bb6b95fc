"""The error contract over the legacy readers: a mutated file gives a result or an InputError naming
the file and the line, never another exception.

Each file starts valid (the Appendix C dc3din of examples/, a small dc3din with its avsout dump
as ``debris legacy`` reads them, a dump written by :func:`write_avsout`, CTH rezone packages)
and gets one to three mutations: a line deleted, duplicated or two swapped, a token replaced
by garbage or by a number out of range (huge, negative, zero, Fortran's ``1.0D+400``, NaN
spelled out), the file truncated at any byte, or bytes inserted that are no ASCII.  The
dc3din and avsout pair goes through ``debris legacy`` (:func:`run_legacy`) up to the moment
its propagation would start.  The round trips and the named errors of each reader are
``test_dc3din.py`` and ``test_legacy_avs.py``; the Fortran E fields' round trip is there too.
"""

from __future__ import annotations

import os
import re
from pathlib import Path
from unittest import mock

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from impactdyn._errors import InputError
from impactdyn.debris import _propagate, run_legacy
from impactdyn.hydrogrid import HydroGrid
from impactdyn.io import AvsLayout, read_avsout, read_cth_packages, read_dc3din, write_avsout, write_cth_packages

EXAMPLES = int(os.environ.get("IMPACTDYN_EXAMPLES_PER_FILE", 150))
"""Mutated files per reader and base file (the environment variable searches longer)."""

APPENDIX_C = Path(__file__).resolve().parents[2] / "examples" / "debris" / "legacy" / "dc3din"

#: The debris CLI tests' small dc3din (an 8 x 6 x 8 cell dump), its run type to fill in.
SMALL_DC3DIN = (Path(__file__).parents[1] / "data" / "small_dc3din.txt").read_text()
SMALL_LAYOUT = AvsLayout(2, 9, 2, 7, 2, 9, 0.0, 0.1, -1.0, 0.1, 0.0, 0.1)


def _block(layout: AvsLayout) -> HydroGrid:
    """Aluminium filling the layout's cells, flying at the wall (+y) at 5 km/s."""
    ones = np.ones(layout.shape)
    return HydroGrid(*layout.nodes(), density=2.7 * ones, void_fraction=0.0 * ones, mass=2.7e-3 * ones,
                     pressure=0 * ones, temperature=300 * ones, specific_energy=0 * ones, sound_speed=0.5 * ones,
                     velocity=np.broadcast_to([0.0, 0.5, 0.0], layout.shape + (3,)), staggered=True)


GARBAGE = st.one_of(st.sampled_from(["", "*", "abc", "1.0.0", "--1", "1e", "E5", ",", "nan", "inf", "-inf", "NaN",
                                     "1.0D+400", "1e999", "-1e999", "0", "-0", "-1", "-1.0", "1e-400", "2147483648",
                                     "99999999999999999999", "-99999999999", "0.123-400", "1+5", "\t"]),
                    st.text(st.characters(codec="latin-1"), max_size=6))
NUMBERS = st.one_of(st.integers(-10**20, 10**20).map(str), st.floats().map(repr),
                    st.floats(-1e6, 1e6).map(lambda v: f"{v:15.6e}"))
RAW = st.lists(st.one_of(st.integers(0x80, 0xFF), st.just(0)), min_size=1, max_size=4).map(bytes)  # no ASCII
INDEX = st.integers(0, 10**6)  # taken modulo the size it indexes

FACTORS = st.sampled_from([-1.0, 0.0, 1e-300, 1e-9, 0.5, 2.0, 10.0, 1e9, 1e300])
NUMBER = re.compile(rb"[+-]?(\d+\.?\d*|\.\d+)([eEdD][+-]?\d+)?")

MUTATIONS = st.one_of(
    st.tuples(st.just("delete"), INDEX),
    st.tuples(st.just("duplicate"), INDEX),
    st.tuples(st.just("swap"), INDEX, INDEX),
    st.tuples(st.just("token"), INDEX, INDEX, st.one_of(GARBAGE, NUMBERS)),
    st.tuples(st.just("number"), INDEX, INDEX, NUMBERS),  # a value out of its range, on a line of numbers
    st.tuples(st.just("scale"), INDEX, INDEX, FACTORS),  # a value negated, zeroed, shrunk, grown
    st.tuples(st.just("truncate"), INDEX),
    st.tuples(st.just("bytes"), INDEX, RAW),
)


def _mutated(text: bytes, mutations: list[tuple]) -> bytes:
    """``text`` with each mutation applied in turn (the indices taken modulo what they index)."""
    for kind, *args in mutations:
        lines = text.split(b"\n")
        if kind == "truncate":
            text = text[:args[0] % (len(text) + 1)]
            continue
        if kind == "bytes":
            at = args[0] % (len(text) + 1)
            text = text[:at] + args[1] + text[at:]
            continue
        if kind in ("number", "scale"):
            text = _renumbered(lines, kind, *args)
            continue
        i = args[0] % len(lines)
        if kind == "delete":
            del lines[i]
        elif kind == "duplicate":
            lines.insert(i, lines[i])
        elif kind == "swap":
            j = args[1] % len(lines)
            lines[i], lines[j] = lines[j], lines[i]
        else:
            tokens = re.split(rb"(\s+|,|=)", lines[i])
            words = [k for k, t in enumerate(tokens) if t.strip() and t not in (b",", b"=")]
            new = args[2].encode("latin-1")
            if words:
                tokens[words[args[1] % len(words)]] = new
            else:
                tokens.append(new)
            lines[i] = b"".join(tokens)
        text = b"\n".join(lines)
    return text


def _renumbered(lines: list[bytes], kind: str, line: int, token: int, value) -> bytes:
    """The lines with one number replaced by ``value`` ("number") or scaled by it ("scale")."""
    numeric = [i for i, text in enumerate(lines) if NUMBER.search(text)]
    if numeric:
        i = numeric[line % len(numeric)]
        found = list(NUMBER.finditer(lines[i]))
        m = found[token % len(found)]
        if kind == "number":
            new = value.encode()
        else:
            old = float(m.group().replace(b"D", b"e").replace(b"d", b"e"))
            new = (str(int(old * value)) if m.group(1).isdigit() and not m.group(2) and abs(old * value) < 1e30
                   else repr(old * value)).encode()
        lines[i] = lines[i][:m.start()] + new + lines[i][m.end():]
    return b"\n".join(lines)


def _assert_names_a_line(err: InputError, *paths: Path) -> None:
    """The message begins with one of ``paths`` and the number of a line in it (or a range of lines)."""
    message = str(err)
    assert any(re.match(rf"{re.escape(str(p))}:\d+(-\d+)?: ", message) for p in paths), message


class _Started(Exception):
    """The legacy run reached its propagation: everything before it took the files."""


def _seed_then_stop(grid, wall, material, *, seed_filter, seed_options, window, **options):
    _propagate.seed_and_select(grid, wall, material, seed_filter, seed_options, window)
    raise _Started


@pytest.fixture(scope="module")
def small_legacy(tmp_path_factory) -> tuple[Path, bytes, bytes]:
    """The folder, the dc3din (2/1) and the avsout dump of ``debris legacy``'s small inputs."""
    folder = tmp_path_factory.mktemp("legacy")
    write_avsout(folder / "avsout", _block(SMALL_LAYOUT), SMALL_LAYOUT)
    return folder, SMALL_DC3DIN.format(itype=2, jtype=1).encode(), (folder / "avsout").read_bytes()


@pytest.mark.parametrize("itype, jtype", [(2, 1), (2, 3), (1, 1)])
def test_the_small_legacy_inputs_run(small_legacy, itype, jtype):
    folder, _, avsout = small_legacy
    (folder / "dc3din").write_text(SMALL_DC3DIN.format(itype=itype, jtype=jtype))
    (folder / "avsout").write_bytes(avsout)
    with mock.patch.object(_propagate, "run_debris", _seed_then_stop), \
            mock.patch.object(_propagate, "propagate_chunked", mock.Mock(side_effect=_Started)):
        if jtype == 1:
            with pytest.raises(_Started):
                run_legacy(folder / "dc3din", folder / "avsout", folder / "out", force=True, echo=lambda _: None)
        else:
            assert run_legacy(folder / "dc3din", None, folder / "out", force=True, echo=lambda _: None)["wall_nodes"]


@pytest.mark.parametrize("target", ["dc3din", "avsout"])
@settings(max_examples=EXAMPLES, deadline=None, database=None)
@given(mutations=st.lists(MUTATIONS, min_size=1, max_size=3), run_type=st.sampled_from([(2, 1), (2, 2), (1, 1)]))
def test_debris_legacy_takes_mutated_inputs(small_legacy, target, mutations, run_type):
    """``debris legacy`` with a mutated dc3din or avsout: stopped at its propagation, or an InputError."""
    folder, dc3din, avsout = small_legacy
    dc3din = SMALL_DC3DIN.format(itype=run_type[0], jtype=run_type[1]).encode()
    (folder / "dc3din").write_bytes(_mutated(dc3din, mutations) if target == "dc3din" else dc3din)
    (folder / "avsout").write_bytes(_mutated(avsout, mutations) if target == "avsout" else avsout)
    with mock.patch.object(_propagate, "run_debris", _seed_then_stop), \
            mock.patch.object(_propagate, "propagate_chunked", mock.Mock(side_effect=_Started)):
        try:
            run_legacy(folder / "dc3din", folder / "avsout", folder / "out", force=True, echo=lambda _: None)
        except _Started:
            pass
        except InputError as err:
            _assert_names_a_line(err, folder / "dc3din", folder / "avsout")


@settings(max_examples=EXAMPLES, deadline=None, database=None)
@given(mutations=st.lists(MUTATIONS, min_size=1, max_size=3))
def test_appendix_c_dc3din_mutated(tmp_path_factory, mutations):
    path = tmp_path_factory.getbasetemp() / "appendix_c_dc3din"
    path.write_bytes(_mutated(APPENDIX_C.read_bytes(), mutations))
    try:
        d = read_dc3din(path)
    except InputError as err:
        _assert_names_a_line(err, path)
    else:
        d.dyngen_wall  # noqa: B018 - the grid DYNGEN writes, from the records alone


@settings(max_examples=EXAMPLES, deadline=None, database=None)
@given(mutations=st.lists(MUTATIONS, min_size=1, max_size=3))
def test_avsout_with_its_header_layout_mutated(small_legacy, mutations):
    """A dump written by impactdyn, read with the layout of its own header lines."""
    folder, _, avsout = small_legacy
    path = folder / "header.avsout"
    path.write_bytes(_mutated(avsout, mutations))
    try:
        read_avsout(path)
    except InputError as err:
        _assert_names_a_line(err, path)


@pytest.fixture(scope="module")
def packages(tmp_path_factory) -> bytes:
    """Three CTH rezone packages as CTHOUT writes them."""
    path = tmp_path_factory.mktemp("cth") / "packages"
    rng = np.random.default_rng(7)
    write_cth_packages(path, np.array([[2, 3, 4, 1], [2, 3, 4, 2], [5, 6, 7, 5]]), rng.uniform(1, 3, 3),
                       rng.normal(size=(3, 3)) * 1e5, rng.normal(size=(3, 4, 3)))
    return path.read_bytes()


@pytest.mark.parametrize("line, text, message", [
    (7, "", ":1: the package has 1 densities, 2 of xvel, yvel, zvel and 4 points and vertices; expected 1, 3 and 4"),
    (1, "     package   2,   3,   4,   6", ":1: cannot read .*a tetrahedron 1..5"),
    (10, "         point = 1.0, 2.0", ":10: cannot read .*expected x, y, z"),
])
def test_cth_packages_name_the_line_of_what_is_wrong(packages, tmp_path, line, text, message):
    lines = packages.decode().splitlines()
    lines[line - 1] = text
    path = tmp_path / "packages"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(InputError, match=rf"^{re.escape(str(path))}{message}"):
        read_cth_packages(path)


@settings(max_examples=EXAMPLES, deadline=None, database=None)
@given(mutations=st.lists(MUTATIONS, min_size=1, max_size=3))
def test_cth_packages_mutated(packages, tmp_path_factory, mutations):
    path = tmp_path_factory.getbasetemp() / "cth_packages"
    path.write_bytes(_mutated(packages, mutations))
    try:
        read_cth_packages(path)
    except InputError as err:
        _assert_names_a_line(err, path)
