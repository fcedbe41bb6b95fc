"""The wall decks of a run: LS-DYNA (time-resolved loads) and the legacy DYNA3D deck (DCPOST's cards)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from impactdyn._config import field_of
from impactdyn._runfolder import FolderWriter
from impactdyn.debris._deposit import element_records
from impactdyn.io import write_lsdyna_deck
from impactdyn.materials import AL_6061_T6_MAT13, Mat13Card, Material, mat13_card
from impactdyn.wallgrid import WallDeposition, WallGrid

END_TIME_MARGIN_US = 10.0
"""Default LS-DYNA termination time: this long after the last arrival (``output.end_time_us``)."""


@dataclass(frozen=True)
class DeckOptions:
    """What the decks need to know beyond the wall and its load.

    lsdyna, dyna3d : which decks to write; end_time_us : LS-DYNA's termination time (None:
    the last arrival plus :data:`END_TIME_MARGIN_US`); pulse_width_us : the force pulse of each
    deposited impulse; clamped_edges : the edge supports; material : the wall's type-13 card
    (both decks), or for the LS-DYNA deck a Johnson–Cook library material (then the DYNA3D
    deck carries its type-13 card, :func:`impactdyn.materials.mat13_card`); hourglass (IHQ, QH)
    and bulk_viscosity (Q1, Q2) : the LS-DYNA deck's controls (None: LS-DYNA's defaults);
    dcpost_factor : DCPOST's scale on the DYNA3D deck's cards; title : the decks' title;
    failure_strain_floor, erode_failed : the Johnson–Cook card's EFMIN and erosion
    (:func:`impactdyn.io.write_lsdyna_deck`).
    """

    lsdyna: bool = True
    dyna3d: bool = True
    end_time_us: float | None = None
    pulse_width_us: float = field_of(write_lsdyna_deck, "pulse_width").default
    clamped_edges: bool = True
    material: Mat13Card | Material = AL_6061_T6_MAT13
    hourglass: tuple[int, float] | None = None
    bulk_viscosity: tuple[float, float] | None = None
    dcpost_factor: float = 1.0
    title: str = ""
    failure_strain_floor: float | None = None
    erode_failed: bool = True

    @classmethod
    def of(cls, case, dcpost_factor: float = 1.0) -> "DeckOptions":
        """The options a debris or Whipple case sets (its ``output`` table, its wall's edges and
        material, its title)."""
        o, w = case.output, case.wall
        return cls(lsdyna=o.lsdyna_deck, dyna3d=o.dyna3d_deck, end_time_us=o.end_time_us,
                   pulse_width_us=o.pulse_width_us, clamped_edges=w.clamped_edges, material=mat13_card(w.material),
                   dcpost_factor=dcpost_factor, title=case.title)


def write_decks(folder: FolderWriter, wall: WallGrid, deposition: WallDeposition, impulse: np.ndarray,
                options: DeckOptions = DeckOptions(), deposition_grid: WallGrid | None = None) -> list[str]:
    """The wall decks ``options`` ask for: LS-DYNA (time-resolved loads) and DYNA3D (DCPOST's cards).

    ``wall`` the mesh the decks carry; ``deposition`` the records on ``deposition_grid``'s face cells
    (None: ``wall``'s); ``impulse`` (nx, nz, 3) the total per face element of ``wall``."""
    o, written = options, []
    if o.lsdyna:
        end = o.end_time_us or (float(deposition.time.max()) + END_TIME_MARGIN_US if deposition.time.size
                                else END_TIME_MARGIN_US)
        write_lsdyna_deck(folder.file("wall.k"), wall, o.material, deposition, pulse_width=o.pulse_width_us,
                          end_time=end, clamped_edges=o.clamped_edges,
                          title=o.title or "impactdyn rear wall under debris-cloud deposition",
                          hourglass=o.hourglass, bulk_viscosity=o.bulk_viscosity,
                          failure_strain_floor=o.failure_strain_floor, erode_failed=o.erode_failed,
                          deposition_grid=deposition_grid)
        written.append("wall.k")
    if o.dyna3d:
        from impactdyn.io import write_dyna3d_deck

        card = o.material if isinstance(o.material, Mat13Card) else mat13_card(o.material)
        write_dyna3d_deck(folder.file("wall_dyna3d.inp"), wall, card,
                          element_records(impulse, o.dcpost_factor), clamped_edges=o.clamped_edges)
        written.append("wall_dyna3d.inp")
    return written
