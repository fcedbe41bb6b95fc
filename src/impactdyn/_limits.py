"""Sizes a case may ask for: refuse, before anything is allocated, what the machine cannot hold.

A case can ask for more items than any computer holds (``time.end_s = 1e308`` output
steps, a dc3din wall of 99999999999 nodes, an SPH spacing of a nanometre).  Each such
count goes through :func:`check_fits` with the bytes one item costs *at least*; if the
product exceeds the machine's physical memory, the case is refused with an
:class:`~impactdyn._errors.InputError` naming the key or record, instead of a
``MemoryError`` or ``OverflowError`` traceback (or hours of swapping) later.

The per-item figures are lower estimates (arrays a run with the default outputs
allocates in any case), so a refused case could not have run here; one that passes
may still be too big for the memory that is free at the time.

======================  =========  ====================================================
item                    bytes      counted by, for
======================  =========  ====================================================
beam output step        8 (2n+9)   ``beam/_case.py``: ``time.*`` (time, 2n+7 states, force)
grid cell               80         :func:`impactdyn.hydrogrid.check_cells`: dc3din records
                                   i1..k2, the avsout layout, the debris ``grid.shell``
wall node               96         :func:`impactdyn.wallgrid.check_nodes`: ``wall.nodes``
                                   (debris, Whipple), ``wall.remap.nodes``, dc3din record
                                   idmax…kdmaxn, :meth:`WallGrid.uniform`
debris particle         584        :func:`impactdyn.debris.seed_particles`: 5 per cell passing
                                   the seed filters (``debris._seed.PARTICLE_BYTES``); a case's
                                   ``grid.shell.cell_size_cm`` or ``grid.file`` (``debris.build``),
                                   dc3din records i1..k2 (``debris legacy``), before seeding
SPH particle            1024       :data:`SPH_PARTICLE_BYTES`: the Whipple case's
                                   ``shield.spacing_cm`` against projectile and bumper
sweep / campaign case   1024       :data:`CASE_BYTES`: the N of ``--vary``, ``--velocity``,
                                   ``--diameter`` (``_config.parse_range``)
======================  =========  ====================================================
"""

from __future__ import annotations

import math
import numbers
import os
import sys

from impactdyn._errors import InputError

#: One SPH particle of the shield stage: its state, rates and predictor copies (~60
#: float64), the three 3×3 work tensors, the pair-sum rows, and a neighbour list of 96
#: int32 + int8 entries (``shield._integrate._Solver``, ``shield._neighbours``).
SPH_PARTICLE_BYTES = 1024

#: One case of a beam sweep or a Whipple campaign (a validated pydantic model and its
#: row of results; each also runs a whole simulation).
CASE_BYTES = 1024


def physical_memory() -> int:
    """Bytes of physical memory of this machine (``os.sysconf``); ``sys.maxsize`` if it cannot say."""
    try:
        pages, page_size = os.sysconf("SC_PHYS_PAGES"), os.sysconf("SC_PAGE_SIZE")
    except (AttributeError, ValueError, OSError):  # no sysconf (Windows) or the names are unknown
        return sys.maxsize
    if pages <= 0 or page_size <= 0:
        return sys.maxsize
    return pages * page_size


def check_fits(what: str, count: float, item_bytes: int, items: str = "items") -> int:
    """``count`` as an int if ``count`` ``items`` of ``item_bytes`` each fit in physical memory.

    ``what`` names the key or record that set the count (``"case.toml: time.output_step_s"``);
    it begins the :class:`InputError` message.  ``count`` may be a float (a ratio of
    two lengths or times): a non-finite or negative count is refused as well.
    """
    if isinstance(count, bool) or not isinstance(count, numbers.Real):
        raise InputError(f"{what}: gives {count!r} {items}, not a count")
    try:
        n = float(count)
    except OverflowError:  # an int beyond the float range
        n = math.inf
    if math.isnan(n) or n < 0:
        raise InputError(f"{what}: gives {count!r} {items}, not a count")
    total, memory = n * item_bytes, physical_memory()
    if math.isinf(total):
        raise InputError(f"{what}: gives more {items} than any machine's memory holds")
    if total > memory:
        raise InputError(f"{what}: {n:.4g} {items} need at least {_bytes(total)}, more than this machine's "
                         f"{_bytes(memory)} of memory")
    return int(count)


def _bytes(n: float) -> str:
    for unit in ("B", "KiB", "MiB", "GiB", "TiB", "PiB"):
        if n < 1024:
            break
        n /= 1024
    return f"{n:.4g} {unit}"
