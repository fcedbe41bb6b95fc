"""The wall decks of a debris run: LS-DYNA (time-resolved loads) and the legacy DYNA3D deck (DCPOST's cards)."""

from __future__ import annotations

import numpy as np

from impactdyn._runfolder import FolderWriter
from impactdyn.debris._deposit import element_records
from impactdyn.materials import AL_6061_T6_MAT13, Mat13Card
from impactdyn.wallgrid import WallDeposition, WallGrid

END_TIME_MARGIN_US = 10.0
"""Default LS-DYNA termination time: this long after the last arrival (``output.end_time_us``)."""


def write_decks(folder: FolderWriter, wall: WallGrid, deposition: WallDeposition, impulse: np.ndarray, case,
                dcpost_factor: float = 1.0, material: Mat13Card = AL_6061_T6_MAT13) -> list[str]:
    """The wall decks ``case.output`` asks for: LS-DYNA (time-resolved loads) and DYNA3D (DCPOST's cards)."""
    o, written = case.output, []
    if o.lsdyna_deck:
        from impactdyn.io import write_lsdyna_deck

        end = o.end_time_us or (float(deposition.time.max()) + END_TIME_MARGIN_US if deposition.time.size
                               else END_TIME_MARGIN_US)
        write_lsdyna_deck(folder.file("wall.k"), wall, material, deposition, pulse_width=o.pulse_width_us,
                          end_time=end, clamped_edges=case.wall.clamped_edges,
                          title=case.title or "impactdyn rear wall under debris-cloud deposition")
        written.append("wall.k")
    if o.dyna3d_deck:
        from impactdyn.io import write_dyna3d_deck

        write_dyna3d_deck(folder.file("wall_dyna3d.inp"), wall, material, element_records(impulse, dcpost_factor),
                          clamped_edges=case.wall.clamped_edges)
        written.append("wall_dyna3d.inp")
    return written
