"""Sizes beyond the machine's memory: refused before anything is allocated, naming the record or key."""

from __future__ import annotations

import math

import pytest

from impactdyn import _limits
from impactdyn._errors import InputError
from impactdyn._limits import check_fits, physical_memory
from impactdyn.hydrogrid import CELL_BYTES, check_cells
from impactdyn.io import read_dc3din
from impactdyn.io._legacy_avs import AvsLayout
from impactdyn.wallgrid import NODE_BYTES, WallGrid, check_nodes

HUGE = 99999999999  # the grid record


def _dc3din(tmp_path, example, **lines: str):
    """The Appendix C file with whole lines replaced (``l5=...``: 1-based line 5)."""
    text = example.read_text().splitlines()
    for key, value in lines.items():
        text[int(key[1:]) - 1] = value
    p = tmp_path / "dc3din"
    p.write_text("\n".join(text) + "\n")
    return p


def test_physical_memory_is_known_here():
    assert 2**26 < physical_memory() < 2**60


def test_check_fits_returns_the_count_or_names_the_key(monkeypatch):
    monkeypatch.setattr(_limits, "physical_memory", lambda: 1000)
    assert check_fits("k", 100, 10) == 100
    assert check_fits("k", 99.0, 10) == 99
    with pytest.raises(InputError, match=r"^k: 101 things need at least 1010 B, more than this machine's 1000 B"):
        check_fits("k", 101, 10, "things")
    for count in (math.inf, 10**400, 1e308):
        with pytest.raises(InputError, match=r"^k: gives more things than any machine's memory holds"):
            check_fits("k", count, 10, "things")
    for count in (math.nan, -1, "3", True, None):
        with pytest.raises(InputError, match="not a count"):
            check_fits("k", count, 10, "things")


def test_grid_and_wall_helpers_use_their_item_sizes(monkeypatch):
    monkeypatch.setattr(_limits, "physical_memory", lambda: 1200 * CELL_BYTES * NODE_BYTES)
    assert check_cells("c", (10, 10, 10.2)) == 1100  # a length over a cell size rounds up
    assert check_cells("c", (1200 * NODE_BYTES, 1, 1)) == 1200 * NODE_BYTES
    with pytest.raises(InputError, match=r"^c: 1\.152e\+05 grid cells need"):
        check_cells("c", (1200 * NODE_BYTES + 0.5, 1, 1))
    assert check_nodes("n", (10, 10, 10)) == 1000
    assert check_nodes("n", (1200, CELL_BYTES, 1)) == 1200 * CELL_BYTES
    with pytest.raises(InputError, match=r"^n = \[1201, 80, 1\]: 9\.608e\+04 wall nodes need"):
        check_nodes("n", (1201, CELL_BYTES, 1))
    with pytest.raises(InputError, match=r"^n = \[2, 2, 10+\]: gives more wall nodes than any"):
        check_nodes("n", (2, 2, 10**400))


def test_wall_grid_uniform_refuses_before_allocating():
    with pytest.raises(InputError, match=r"WallGrid.uniform: nodes = \[99999999999, 5, 101\]: 5.05e\+13 wall nodes"):
        WallGrid.uniform((0, 1), (0, 1), (0, 1), (HUGE, 5, 101))


def test_avsout_layout_refuses_a_block_beyond_memory():
    with pytest.raises(InputError, match=r"avsout layout: 2..99999999999 x 2..99999999999 x 2..3: .* grid cells"):
        AvsLayout(2, HUGE, 2, HUGE, 2, 3, 0.0, 0.1, 0.0, 0.1, 0.0, 0.1)


def test_dc3din_wall_record_beyond_memory_names_file_and_line(tmp_path, example_dc3din):
    """The issue's case: 99999999999 wall nodes ended in a 745-GiB MemoryError."""
    p = _dc3din(tmp_path, example_dc3din, l4="         2         2",
                l20=f" {HUGE}         5       101        51         5       101")
    with pytest.raises(InputError, match=rf"^{p}:20: idmax jdmax kdmax = \[{HUGE}, 5, 101\]: .* wall nodes"):
        read_dc3din(p)


@pytest.mark.parametrize("run, message", [
    ("         2         1", r":20: idmaxn, 2, kdmaxn \(the remap face\)"),
    ("         2         3", r":20: idmaxn jdmaxn kdmaxn"),
])
def test_dc3din_new_wall_grid_checked_where_used(tmp_path, example_dc3din, run, message):
    p = _dc3din(tmp_path, example_dc3din, l4=run,
                l20=f"        51         5       101 {HUGE}         5       101")
    with pytest.raises(InputError, match=message):
        read_dc3din(p)
    read_dc3din(_dc3din(tmp_path, example_dc3din, l4="         2         2",  # 2/2 does not use it
                        l20=f"        51         5       101 {HUGE}         5       101"))


def test_dc3din_cell_block_beyond_memory_names_its_records(tmp_path, example_dc3din):
    p = _dc3din(tmp_path, example_dc3din, l6=f"         2 {HUGE}")
    with pytest.raises(InputError, match=rf"^{p}:6-10: records i1 i2, j1 j2, k1 k2 \(the avsout cells\): "):
        read_dc3din(p)
    # the wall-deck-only run types do not read avsout: the block is not theirs to refuse
    assert read_dc3din(_dc3din(tmp_path, example_dc3din, l4="         2         2", l6=f"         2 {HUGE}")
                       ).i2 == HUGE
