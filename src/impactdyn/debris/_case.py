"""Debris case files: the TOML schema of ``impactdyn debris run`` (units cm, g, µs, Mbar).

A case names its hydrocode state (a HydroGrid file in any registered format, or
the analytic shell cloud of :mod:`._analytic`), the debris material, the filters,
the wall, the integrator, where the chunks run and what to write.  Problem setup
only: :func:`build` turns a case into the arguments of
:func:`impactdyn.debris.run_debris`.  See ``examples/debris/*.toml``.

A table that feeds an option of :func:`~impactdyn.debris.run_debris` takes its
defaults and bounds from it: ``[integrator]`` and ``[compute]`` are
:class:`IntegratorOptions` and :class:`ComputeOptions`; ``[filter]`` is a
:class:`SeedFilter` with the :class:`ArrivalWindow`'s times; the ``[legacy]`` flags
and the shell cloud's defaults are declared with :func:`~impactdyn._config.field_of`
from the options they set (:data:`LEGACY_FLAGS`).  The Whipple case reuses these
tables and validators.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import numpy as np
from pydantic import Field, create_model, field_validator, model_validator

from impactdyn import units
from impactdyn._config import NodeCount, Range, Section, check_ranges, field_of, load_toml, rule, validate
from impactdyn._errors import InputError
from impactdyn.debris._analytic import ShellCloud, check_shell, grid_box, shell_cloud_grid
from impactdyn.debris._integrators import IntegratorOptions
from impactdyn.debris._particle import LIGHT_SPEED, ParticleMaterial, check_bulk_modulus, check_wave_speed
from impactdyn.debris._deposit import MomentumTransfer
from impactdyn.debris._propagate import ArrivalWindow, ComputeOptions, DepositionOptions, check_window
from impactdyn.debris._seed import SeedFilter, SeedOptions, check_particle_count, seed_cells
from impactdyn.io import formats, read_grid, write_lsdyna_deck
from impactdyn.materials import REPORT_MATERIAL, MaterialName, MaterialsTable

# TOML arrays are lists; strict validation does not turn them into tuples.
Vector = Annotated[list[float], Field(min_length=3, max_length=3)]

LIGHT_SPEED_KM_S = units.cm_us_to_km_s(LIGHT_SPEED)
"""No debris is faster; below it the cloud's velocities, momenta and energies stay finite numbers."""

Speed = Annotated[float, Field(ge=-LIGHT_SPEED_KM_S, le=LIGHT_SPEED_KM_S)]
"""A velocity component, km/s."""


class ShellSection(Section):
    """The analytic debris cloud (:class:`impactdyn.debris.ShellCloud`): a spherical shell, cut to a
    cap about its flight direction, moving with the velocity field v(x) = v_c + v_e (x − c)/R.

    centre_cm : the shell's centre c at the hand-off, (x, y, z).
    velocity_km_s : the centre's velocity v_c, (x, y, z); not zero: its direction is the cap's axis.
    expansion_velocity_km_s : v_e, the outward speed of material at the outer radius R relative to
        the centre.
    radius_cm : the shell's outer radius R.
    thickness_cm : the shell's thickness δ ≤ R (δ = R: a full ball).
    cap_half_angle_deg : the cap's half-angle α about the flight direction; 180: the whole shell.
    density_g_cm3 : the density ρ of the shell's material (2.703: aluminium).
    void_fraction : the void fraction φ of the shell's material (fragments and voids between them);
        a full cell holds the mass (1 − φ) ρ V.
    sound_speed_km_s : the value written into the grid's sound-speed field (the particles'
        stiffness comes from ``[material]``).
    time_us : the grid's (absolute) time, the hand-off; arrival times are counted from it.
    cell_size_cm : the cubic cells' edge (default the report's DC3D cells, 0.03175 cm); the grid
        covers the half (x ≥ 0) bounding box of the sphere.
    subsamples : points per cell edge (subsamples³ per cell) that measure the fraction of each
        cell inside the shell and its mean velocity there.
    """

    centre_cm: Vector
    velocity_km_s: Annotated[list[Speed], Field(min_length=3, max_length=3)]
    expansion_velocity_km_s: Annotated[float, Field(le=LIGHT_SPEED_KM_S)] = field_of(ShellCloud,
                                                                                      "expansion_velocity")
    radius_cm: float = field_of(ShellCloud, "radius")
    thickness_cm: float = field_of(ShellCloud, "thickness")
    cap_half_angle_deg: float = field_of(ShellCloud, "cap_half_angle_deg")
    density_g_cm3: float = field_of(ShellCloud, "density")
    void_fraction: float = field_of(ShellCloud, "void_fraction")
    sound_speed_km_s: float = field_of(ShellCloud, "sound_speed", units.cm_us_to_km_s(
        ShellCloud.model_fields["sound_speed"].default))
    time_us: float = field_of(ShellCloud, "time")
    cell_size_cm: float = field_of(shell_cloud_grid, "cell_size")
    subsamples: int = field_of(shell_cloud_grid, "subsamples")

    _shell = rule(check_shell, "radius_cm", "thickness_cm", "velocity_km_s")

    @model_validator(mode="after")
    def _cells(self) -> "ShellSection":
        grid_box(self.centre_cm, self.radius_cm, self.cell_size_cm, ("centre_cm", "radius_cm", "cell_size_cm"))
        return self


class GridSection(Section):
    """Where the hand-off state comes from: ``file`` (relative to the case file) or ``shell``.

    file : a HydroGrid file (the hand-off state of a hydrocode, e.g. a Whipple run's
        ``binning/handoff_grid.h5`` or a CTH ``avsout`` dump), relative to the case file.
    format : the reader's name (:func:`impactdyn.io.formats`: "hdf5", "avsout",
        "vtk-rectilinear"); none: chosen from the file's name.
    """

    file: str | None = None
    format: str | None = None
    shell: ShellSection | None = None

    @field_validator("file")
    @classmethod
    def _a_path(cls, file: str | None) -> str | None:
        if file is not None and "\x00" in file:
            raise ValueError(f"{file!r}: a file name cannot hold a NUL character")
        return file

    @field_validator("format")
    @classmethod
    def _readable(cls, name: str | None) -> str | None:
        readers = sorted(n for n, f in formats().items() if f.reader is not None)
        if name is not None and name not in readers:
            raise ValueError(f"{name!r}: no grid reader of that name; known: {', '.join(readers)}")
        return name

    @model_validator(mode="after")
    def _one_source(self) -> "GridSection":
        if (self.file is None) == (self.shell is None):
            raise ValueError("give exactly one of grid.file and grid.shell")
        return self


class MaterialSection(Section):
    """Debris material (dc3din record 13–14), :class:`ParticleMaterial`'s defaults and bounds;
    omit eta for no plastic flow.

    mu_Mbar : the shear modulus μ (Lamé's second constant) of the particles' elastic energy.
    lambda_Mbar : Lamé's first constant λ; the bulk modulus λ + ⅔μ must be positive, and the
        wave speed below that of light.
    rho_ref_g_cm3 : the reference density ρ_ref: a particle of mass m and void fraction φ has the
        stress-free volume V₀ = m/((1 − φ) ρ_ref), and the seed filters compare ρ/ρ_ref.
    eta_Mbar_us : the plastic viscosity η of the flow rule Ėₚ = (2μ/η)(E' − Eₚ): the deviatoric
        strain relaxes at the rate 2μ/η; omitted: no plastic flow (η = ∞).
    zeta_Mbar_us : the artificial bulk viscosity ζ ≥ 0, which damps the particles' volumetric
        ringing; 0: none.
    """

    mu_Mbar: float = field_of(ParticleMaterial, "mu")
    lambda_Mbar: float = field_of(ParticleMaterial, "lam")
    rho_ref_g_cm3: float = field_of(ParticleMaterial, "rho_ref")
    eta_Mbar_us: float | None = field_of(ParticleMaterial, "eta", None)
    zeta_Mbar_us: float = field_of(ParticleMaterial, "zeta")

    _bulk = rule(check_bulk_modulus, "lambda_Mbar", "mu_Mbar")
    _causal = rule(check_wave_speed, "lambda_Mbar", "mu_Mbar", "rho_ref_g_cm3")


class FilterSection(SeedFilter):
    """Which cells become particles (:class:`SeedFilter`) and which particles are carried
    (:class:`ArrivalWindow`); dc3din record 8.  The ratios are dimensionless; the defaults are
    the listing's.

    dencut : the smallest bulk density ratio (1 − φ) ρ/ρ_ref of a cell that becomes particles
        (dc3din record 8's dencut, 0.01 in the report's input).  It drops the thin spray and
        the nearly empty cells at the cloud's edge, whose particles carry little momentum but
        cost as much to integrate as any.  The listing also applies a fixed 0.01 to the same
        ratio; here ``dencut`` alone does.
    min_density_ratio, max_density_ratio : the range of ρ/ρ_ref (the material's density, voids
        aside) of a cell that becomes particles (the listing's fixed 0.01 and 1000).
    max_void_fraction : the largest void fraction φ of such a cell (the listing's fixed 0.999).
    t_min_us, t_cut_us : the arrival window, µs after the hand-off: only particles whose centre
        reaches the wall's plane in [t_min_us, t_cut_us] are integrated and deposit momentum
        (the report's input: 0 and 25 µs); t_cut_us must exceed t_min_us.
    """

    t_min_us: float = field_of(ArrivalWindow, "t_min")
    t_cut_us: float = field_of(ArrivalWindow, "t_cut")

    _window = rule(check_window, "t_min_us", "t_cut_us")


class RemapSection(Section):
    """A second face grid to remap the deposition onto (DCPOST, dc3din's new wall grid).

    x_cm, z_cm : the [first, last] coordinates of the second grid's edges in x and in z, cm, in
        the wall's coordinates.
    nodes : its node counts (x, z); the deposited impulse is shared among its face cells by
        overlap area (conservative), written to ``areal_density_remap.csv``.
    """

    x_cm: Range
    z_cm: Range
    nodes: Annotated[list[NodeCount], Field(min_length=2, max_length=2)]


class WallSection(Section):
    """The rear wall: its front face is the plane y = y_cm[0]; nodes = (x, y, z) node counts (DYNGEN);
    ``material`` (a library name) is the one its decks carry (:func:`impactdyn.materials.mat13_card`).

    material : the wall's library material, written into its decks.
    x_cm, y_cm, z_cm : the wall's extent, cm; y_cm[0] is its front face, the plane the debris
        arrives at, and must lie beyond the cloud.
    nodes : node counts (x, y, z) of the wall grid, as DYNGEN's: its front-face cells are the grid
        the momentum is deposited on, the y nodes the element layers of the decks.
    clamped_edges : the decks fix every translation of the wall's three outer edges (all but the
        symmetry plane x = x_cm[0]); false: DYNGEN's edge codes (the edge x = x_max fixes x and y,
        the edges z = z_min and z_max fix y and z).
    momentum_transfer : what an arriving particle gives the wall: "arrival" (default) its own
        momentum; "cratering" its normal component times the β(V_n) of a droplet cratering a thick
        wall (:data:`impactdyn.debris.CRATERING_MOMENTUM`), an upper bound for a cloud.
    """

    material: MaterialName = REPORT_MATERIAL
    x_cm: Range
    y_cm: Range
    z_cm: Range
    nodes: Annotated[list[NodeCount], Field(min_length=3, max_length=3)]
    clamped_edges: bool = True
    momentum_transfer: MomentumTransfer = field_of(DepositionOptions, "momentum_transfer")
    remap: RemapSection | None = None

    @model_validator(mode="after")
    def _ranges(self) -> "WallSection":
        from impactdyn.wallgrid import check_nodes  # sizes: InputError before anything is allocated

        check_nodes("wall.nodes", self.nodes)
        check_ranges(list(zip(("wall.x_cm", "wall.y_cm", "wall.z_cm"), (self.x_cm, self.y_cm, self.z_cm),
                              self.nodes)), "wall.nodes")
        if self.remap is not None:
            check_ranges(list(zip(("wall.remap.x_cm", "wall.remap.z_cm"), (self.remap.x_cm, self.remap.z_cm),
                                  self.remap.nodes)), "wall.remap.nodes")
            check_nodes("wall.remap.nodes (x, 2 through the thickness, z)", [self.remap.nodes[0], 2,
                                                                           self.remap.nodes[1]])
        return self


IntegratorSection = IntegratorOptions
"""The ``[integrator]`` table is :class:`IntegratorOptions` (its defaults and bounds)."""

ComputeSection = ComputeOptions
"""The ``[compute]`` table is :class:`ComputeOptions`."""


class OutputSection(Section):
    """What the debris stage writes besides ``summary.json``, ``config.resolved.toml`` and the areal
    density tables (:mod:`._outputs`).

    hdf5 : ``debris.h5`` (every array: particles, arrival states, deposition, wall) and
        ``handoff_grid.h5`` (the grid the particles came from).  A Whipple run's wall and decks
        stages read ``debris/debris.h5``, so keep it there.
    vtk : ParaView files: the particles as tetrahedra at the hand-off and at arrival
        (``particles_*.vtu``, up to ``max_vtk_particles``) and the wall's front face with its
        impulse (``wall_deposition.vtu``); in a Whipple run also the shield's particles and the
        wall stage's time series.
    lsdyna_deck : ``wall.k``, an LS-DYNA keyword deck of the wall with the deposited momentum as
        time-resolved loads (a lean Whipple run writes no decks; ``--keep all`` does).
    dyna3d_deck : ``wall_dyna3d.inp``, the legacy DYNA3D deck as DYNGEN wrote it, with DCPOST's
        impulse per element (summed, at t = 0).
    plots : the PNG figures (DCMPLT's contour map of the areal density, the cloud at hand-off and
        at arrival; in a Whipple run also the wall's front, rear and history).
    max_vtk_particles : a particle VTU file is written only if it holds at most this many
        particles (the hand-off file counts the seeded ones, the arrival file the carried ones).
    """

    hdf5: bool = True
    vtk: bool = True
    lsdyna_deck: bool = True
    dyna3d_deck: bool = True
    plots: bool = True
    pulse_width_us: float = field_of(write_lsdyna_deck, "pulse_width")
    """Width of the triangular force pulse that carries each deposited impulse in the LS-DYNA deck."""
    end_time_us: float | None = field_of(write_lsdyna_deck, "end_time", None)
    """LS-DYNA termination time; default: the last arrival plus 10 µs."""
    max_vtk_particles: Annotated[int, Field(ge=1)] = 2_000_000


LEGACY_FLAGS: dict[str, tuple[type, str]] = {
    "nddata_swap": (SeedOptions, "legacy_nddata_swap"),                  # NDDATA swaps the velocities of n7, n8
    "fdot_scaling": (SeedOptions, "legacy_fdot_scaling"),                # IVCALC's Ḟ(0) = L (ρ_ref/ρ)/3
    "inertia_transform": (SeedOptions, "legacy_inertia_transform"),      # JCALC's J = g⁻ᵀ J_ref g⁻¹
    "eta_per_volume": (ParticleMaterial, "legacy_eta_per_volume"),       # Ėₚ = V₀(2μ/η)(E' − Eₚ)
    "abs_arrival": (ArrivalWindow, "legacy_abs_arrival"),                # arrival time |(y_wall − c_y)/v_y|
    "vertex_scaling": (DepositionOptions, "legacy_vertex_scaling"),      # points scaled by (ρ/ρ_ref)^{1/3}
    "momentum_enhancement": (DepositionOptions, "legacy_momentum_enhancement"),  # p × √((m_e + m)/m)
}
"""The ``[legacy]`` flags: each key sets one field of one option of :func:`~impactdyn.debris.run_debris`,
whose default it takes (the listing's deviations are off unless asked for)."""

LegacySection = create_model(
    "LegacySection", __base__=Section, __module__=__name__,
    __doc__="""The listing's behaviour where it departs from the model (docs/theory/debris.md, the listing's
    errata), one flag each (:data:`LEGACY_FLAGS`).  Every flag is off by default (the model); each
    switches one erratum of the 1994 DC3D listing back on, to reproduce the report's numbers or to
    measure what the erratum changes.

    nddata_swap : NDDATA gives nodes n7 and n8 of each cell each other's velocity (their coordinates
        are right), so the tetrahedra that hold them start with a wrong velocity gradient; off: each
        node its own velocity.
    fdot_scaling : IVCALC starts a particle with the deformation rate Ḟ(0) = L (ρ_ref/ρ)/3 instead
        of L, the velocity gradient fitted to its vertices' velocities; off: Ḟ(0) = L, so the
        particle starts with the velocity field of the hand-off grid.
    inertia_transform : JCALC maps the reference tetrahedron's inertia tensor with the inverse map,
        J = g⁻ᵀ J_ref g⁻¹; off: g J_ref gᵀ, the particle's own second moment of mass.
    eta_per_volume : the listing's flow rule is Ėₚ = V₀(2μ/η)(E' − Eₚ), its η per unit volume
        (Mbar·cm³·µs), so a particle's plastic rate grows with its size; off: Ėₚ = (2μ/η)(E' − Eₚ),
        η in Mbar·µs.  On, the case's η is read as the listing's.
    abs_arrival : DCELEM's arrival time |(y_wall − c_y)/v_y| also counts particles flying away from
        the wall (or already past it), which then deposit their momentum as if they arrived; off: only
        particles in front of the wall and approaching it (v_y > 0) arrive.
    vertex_scaling : DYNOUT places a particle's deposition points at its vertices scaled by
        (ρ/ρ_ref)^⅓ about the centre; off: the deformed vertices c + F(x⁰ − c⁰).
    momentum_enhancement : DYNOUT's factor √((m_e + m)/m) on a particle's deposited momentum, m_e the
        mass of one wall element at the debris' reference density.  The listing computes it and
        then sets it to 1, so the report's runs did not apply it; on, it is applied, and the
        deposited momentum exceeds the debris'.
    """,
    **{key: (bool, field_of(option, name)) for key, (option, name) in LEGACY_FLAGS.items()})


def _legacy(flags, option: type) -> dict:
    """The keywords of ``option`` that the ``[legacy]`` ``flags`` set."""
    return {name: getattr(flags, key) for key, (target, name) in LEGACY_FLAGS.items() if target is option}


class DebrisCase(Section):
    """A complete debris case (every table of the TOML file).

    title : a name for the case, written as the decks' title.
    materials : the case's own alloys, ``[materials.NAME]`` tables (:class:`impactdyn.materials.MaterialTable`),
        which ``[wall]`` may then name like the library's (a Whipple run's debris case carries its case's).
    """

    title: str = ""
    materials: MaterialsTable | None = None  # before the wall that may name one: validated (registered) first
    grid: GridSection
    material: MaterialSection
    filter: FilterSection = FilterSection()
    wall: WallSection
    integrator: IntegratorOptions = IntegratorOptions()
    compute: ComputeOptions = ComputeOptions()
    output: OutputSection = OutputSection()
    legacy: LegacySection = LegacySection()


def load_debris_case(path: str | Path) -> DebrisCase:
    """Load and validate a case; a relative ``grid.file`` is taken relative to the case file."""
    path = Path(path)
    case = validate(DebrisCase, load_toml(path), source=str(path))
    file = case.grid.file
    if file is None or Path(file).is_absolute():
        return case
    grid = case.grid.model_copy(update={"file": str((path.parent / file).resolve())})
    return case.model_copy(update={"grid": grid})


def hand_off_grid(case: DebrisCase, source: str = "<case>"):
    """The HydroGrid a case names: its analytic shell cloud, or its file read through the format registry.

    Checked against the case before any particle is seeded: the particles of the cells that pass
    the seed filters must fit in this machine's memory and lie in front of the wall.
    """
    g = case.grid
    if g.shell is not None:
        s = g.shell
        kms = units.CM_US_PER_KM_S
        try:
            grid = shell_cloud_grid(ShellCloud(
                centre=tuple(s.centre_cm), velocity=tuple(v * kms for v in s.velocity_km_s),
                expansion_velocity=s.expansion_velocity_km_s * kms, radius=s.radius_cm, thickness=s.thickness_cm,
                cap_half_angle_deg=s.cap_half_angle_deg, density=s.density_g_cm3, void_fraction=s.void_fraction,
                sound_speed=s.sound_speed_km_s * kms, time=s.time_us), s.cell_size_cm, s.subsamples)
        except InputError as err:  # values the table takes one by one that do not make a grid together
            raise InputError(f"{source}: grid.shell: {err}") from None
        size = f"grid.shell.cell_size_cm = {s.cell_size_cm:g} for the {s.radius_cm:g} cm shell"
        cloud = f"grid.shell (centre_cm = {s.centre_cm}, radius_cm = {s.radius_cm:g})"
    else:
        if not Path(g.file).is_file():
            raise InputError(f"{source}: grid.file: {g.file}: no such file")
        try:
            grid = read_grid(g.file, g.format)
        except InputError as err:
            raise InputError(f"{source}: grid.file: {err}") from None
        size = cloud = f"grid.file = {g.file}"
    check_seeding(case, grid, f"{source}: {size}", f"{source}: wall.y_cm[0]", cloud)
    return grid


def check_seeding(case: DebrisCase, grid, size: str, front: str, cloud: str) -> None:
    """The particles of ``grid``'s cells that pass the case's seed filters fit in memory and lie in front of
    the wall (:func:`seed_particles` and :func:`seed_and_select` refuse them too, but name no key).

    The :class:`InputError` begins with ``size`` (what set the grid's size) or ``front`` (what set
    the wall's front face) and names ``cloud`` (what placed the debris).
    """
    keep = seed_cells(grid, case.material.rho_ref_g_cm3, _seed_filter(case))
    check_particle_count(f"{size}, seed filters of [filter]: the hand-off grid", keep)
    rows = np.nonzero(keep.any(axis=(0, 2)))[0]
    y = case.wall.y_cm[0]
    if len(rows) and grid.y[rows[-1] + 1] > y:
        raise InputError(f"{front} = {y:g}: the wall's front face lies behind or inside the debris of {cloud}, "
                         f"which reaches y = {grid.y[rows[-1] + 1]:g} cm; the wall must lie beyond the cloud in +y")


def _seed_filter(case: DebrisCase) -> SeedFilter:
    return SeedFilter(**case.filter.model_dump(include=set(SeedFilter.model_fields)))


def build(case: DebrisCase, source: str = "<case>", grid=None) -> dict:
    """The hand-off grid, wall and options of a case: keyword arguments of ``run_debris``.

    ``grid``: a HydroGrid already in hand, used instead of reading ``case.grid``.
    """
    from impactdyn.wallgrid import WallGrid

    grid = hand_off_grid(case, source) if grid is None else grid
    w, m, f, lg = case.wall, case.material, case.filter, case.legacy
    wall = WallGrid.uniform(w.x_cm, w.y_cm, w.z_cm, w.nodes)
    material = ParticleMaterial(mu=m.mu_Mbar, lam=m.lambda_Mbar, rho_ref=m.rho_ref_g_cm3,
                                eta=float("inf") if m.eta_Mbar_us is None else m.eta_Mbar_us, zeta=m.zeta_Mbar_us,
                                **_legacy(lg, ParticleMaterial))
    return dict(
        grid=grid, wall=wall, material=material,
        seed_filter=_seed_filter(case),
        seed_options=SeedOptions(**_legacy(lg, SeedOptions)),
        window=ArrivalWindow(t_min=f.t_min_us, t_cut=f.t_cut_us, **_legacy(lg, ArrivalWindow)),
        integrator=case.integrator, compute=case.compute,
        deposition=DepositionOptions(momentum_transfer=w.momentum_transfer, **_legacy(lg, DepositionOptions)),
    )


def remap_grid(case: DebrisCase):
    """The remap face grid as a one-element-thick WallGrid, or None."""
    from impactdyn.wallgrid import WallGrid

    r = case.wall.remap
    if r is None:
        return None
    return WallGrid.uniform(r.x_cm, case.wall.y_cm, r.z_cm, (r.nodes[0], 2, r.nodes[1]))
