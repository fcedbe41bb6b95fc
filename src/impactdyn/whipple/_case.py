"""Whipple case files: the TOML schema of ``impactdyn whipple run`` (units cm, g, µs, km/s as named).

A case describes a shot (projectile, bumper, rear wall and the stand-off between
them) and the numerics of each stage.  Problem setup only: the functions below
turn a case into the inputs of the shield stage (:func:`shield_problem`), the
debris stage (:func:`debris_case`) and the ballistic-limit check
(:func:`ble_shield`).  See ``examples/whipple/*.toml``.

Coordinates (those of :mod:`impactdyn.shield`): the bumper's front face is the
plane y = 0 and its back face y = t_b; the wall's front face is y = t_b + S
(S = ``wall.spacing_cm``, bumper back to wall front, as in the report's App. A);
x = 0 is the symmetry plane of the half model; the projectile flies along
(0, cos θ, sin θ) and first touches the bumper at the origin.  The wall's x and
z extents are in these coordinates (the report's wall, App. C: x ∈ [0, 8],
z ∈ [−4, 12] cm about the impact point).
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any, Literal, get_type_hints

from pydantic import Field, ValidationError, field_validator, model_validator

from impactdyn import units
from impactdyn._config import (NodeCount, Positive, Range, Section, check_ranges, field_of, load_toml,
                               section_of, validate)
from impactdyn._errors import InputError
from impactdyn.debris import (
    ComputeSection, DebrisCase, FilterSection, IntegratorSection, LegacySection, MomentumTransfer, OutputSection,
    ParticleMaterial, check_bulk_modulus, check_wave_speed)
from impactdyn.debris import WallSection as DebrisWallSection
from impactdyn.materials import (REPORT_MATERIAL, Material, MaterialName, MaterialsTable, get_material,
                                 without_material_echoes)
from impactdyn.shield import (DEFAULT_PLATE_RADIUS_D, FRAGMENT_KEYS, BinningMethod, FragmentOptions, SPHOptions,
                              bin_to_hydrogrid, spacing_too_coarse)
from impactdyn.wall import WallOptions, check_deposition_depth, check_mesh_sizes, resolve_model


class ProjectileSection(Section):
    """The sphere: material name (:data:`impactdyn.materials.MATERIALS`), diameter, speed, obliquity.

    material : the projectile's library material (a name or alias of
        :data:`impactdyn.materials.MATERIALS`); default the report's aluminium.  It sets the shield
        stage's SPH material and, unless ``[debris]`` gives them, the debris particles' constants.
    diameter_cm : the sphere's diameter.  The SPH spacing must put at least 4 particles across it.
    velocity_km_s : the impact speed.  With ``shield.handoff_us`` it bounds how far the debris can
        travel before the hand-off, which must stay short of the wall.
    obliquity_deg : the angle between the flight path and the bumper's normal (0: normal
        incidence); the projectile flies along (0, cos θ, sin θ).
    """

    material: MaterialName = REPORT_MATERIAL
    diameter_cm: Positive
    velocity_km_s: Positive
    obliquity_deg: Annotated[float, Field(ge=0, lt=90)] = 0.0


class BumperSection(Section):
    """The bumper plate; ``radius_cm`` of the modelled half disc (default twice the projectile diameter).

    material : the bumper's library material (:data:`impactdyn.materials.MATERIALS`).
    thickness_cm : the bumper's thickness t_b; its front face is y = 0, its back face y = t_b.
    radius_cm : the radius of the modelled disc (a half disc: the model has the symmetry plane
        x = 0); none: twice the projectile's diameter, wide enough that the hole and the debris
        stay clear of its edge.  It must exceed the projectile's radius.
    """

    material: MaterialName = REPORT_MATERIAL
    thickness_cm: Positive
    radius_cm: Positive | None = None


class WallSection(Section):
    """The rear wall: stand-off S from the bumper's back face, thickness, face grid and the BLE's yield stress.

    material : the wall's library material: the wall stage's material model takes its constants
        from it, and the decks carry it.
    thickness_cm : the wall's thickness t_w (along y).
    spacing_cm : the stand-off S from the bumper's back face to the wall's front face (the
        report's spacing, App. A); the wall's front face is y = t_b + S.  The debris must not
        reach it by the hand-off, and the binning cells must fit in it.
    yield_stress_ksi : the wall's yield stress σ_y in the NASA JSC ballistic-limit equation
        (the verdict the simulation is compared with); the simulated wall's strength comes from
        ``material``.  It enters the equations' yield-stress terms, (σ_y/40)^½ in the ballistic
        regime; 40 ksi is the nominal yield stress of 6061-T6, the report's wall.  Left out: the
        typical tensile yield of the wall's material (its record's ``tensile_yield``; a case's own
        material gives it as ``strength.tensile_yield_MPa``), refused if the material has none.
    x_cm, z_cm : the wall's extent in x and z, cm, in the shield's coordinates (x = 0 is the
        symmetry plane, the projectile touches the bumper at x = z = 0); the report's wall
        (App. C) is x ∈ [0, 8], z ∈ [−4, 12] cm, which oblique debris, flying to +z, needs.
    nodes : the case grid's node counts (x, y, z), as the report's DYNGEN had them (51 × 5 × 101:
        0.16-cm faces and 4 elements through the thickness).  Its face cells are the grid the
        debris deposits its momentum on; the wall solver's graded mesh grows to the size of
        these cells away from the load, and ``wall_solver.mesh = "report"`` runs on this grid.
    clamped_edges : the three outer edges of the wall (all but the symmetry plane) clamped, every
        translation fixed, in the wall stage and the decks; false: DYNGEN's edge codes (the edge
        x = x_max fixes x and y, the edges z = z_min and z_max fix y and z).
    momentum_transfer : what the debris gives the wall: "arrival" (default) its own momentum;
        "cratering" each particle's normal momentum times the β(V_n) of a droplet cratering a thick
        wall (:data:`impactdyn.debris.CRATERING_MOMENTUM`: the crater ejecta's momentum besides
        its own), an upper bound for a cloud (docs/vv/test-shots.md).
    """

    material: MaterialName = REPORT_MATERIAL
    thickness_cm: Positive
    spacing_cm: Positive
    yield_stress_ksi: Positive | None = None
    x_cm: Range = [0.0, 8.0]
    z_cm: Range = [-4.0, 12.0]
    nodes: Annotated[list[NodeCount], Field(min_length=3, max_length=3)] = [51, 5, 101]
    clamped_edges: bool = field_of(DebrisWallSection, "clamped_edges")
    momentum_transfer: MomentumTransfer = field_of(DebrisWallSection, "momentum_transfer")

    @field_validator("spacing_cm", mode="before")  # before the bound > 0: this message says why
    @classmethod
    def _outside_bumper(cls, spacing: Any) -> Any:
        if isinstance(spacing, (int, float)) and not isinstance(spacing, bool) and spacing <= 0:
            raise ValueError(f"{spacing}: the wall's front face would lie inside the bumper (the spacing runs "
                             "from the bumper's back face to the wall's front face and must be > 0)")
        return spacing

    @model_validator(mode="after")
    def _extent(self) -> "WallSection":
        from impactdyn.wallgrid import check_nodes  # sizes: InputError before anything is allocated

        check_nodes("nodes", self.nodes)
        check_ranges([("x_cm", self.x_cm, self.nodes[0]), ("z_cm", self.z_cm, self.nodes[2])], "nodes")
        return self


class _ShieldBase(Section):
    """SPH numerics of the shield stage, the hand-off time and how the debris's fragments are found; the
    numerics are those of :class:`impactdyn.shield.SPHOptions`, the fragments' settings those of
    :class:`impactdyn.shield.FragmentOptions`, with their defaults and bounds (the rest keep their defaults).

    spacing_cm : the SPH particles' pitch (cm; a cubic lattice; 0.0254 cm = 0.01 in).  It must
        put at least 4 particles across the projectile and one layer through the bumper; the
        particle count grows as its inverse cube.  (Not ``wall.spacing_cm``, the stand-off.)
    handoff_us : the time after first contact at which the shield stage stops and the debris
        behind the bumper is binned onto the hand-off grid for the debris stage (the report: 4 µs
        at 7 km/s, 3 µs at 10 km/s).  By then no debris, however fast, may have reached the wall.
    """

    spacing_cm: Positive = 0.0254
    handoff_us: Positive = 4.0

    @model_validator(mode="after")
    def _grady_needs_fragmentation(self) -> "_ShieldBase":
        if self.fragment_options().grady and self.failure_model != "fragmentation":
            raise ValueError(f"failed_fragments = \"grady\" needs failure_model = \"fragmentation\" (got "
                             f"{self.failure_model!r}): the threshold model fails material in compression, "
                             "which breaks nothing")
        return self

    def sph_options(self) -> SPHOptions:
        """The :class:`impactdyn.shield.SPHOptions` of this table."""
        return SPHOptions(**self.model_dump(exclude={"spacing_cm", "handoff_us", *FRAGMENT_KEYS}))

    def fragment_options(self) -> FragmentOptions:
        """The :class:`impactdyn.shield.FragmentOptions` of this table: its fragment keys, and compact
        bodies with the fragmentation failure model."""
        return FragmentOptions(**self.model_dump(include=set(FRAGMENT_KEYS)),
                               compact_bodies=self.failure_model == "fragmentation")


ShieldSection = section_of("ShieldSection",
                           section_of("_ShieldFragments", _ShieldBase, FragmentOptions, FRAGMENT_KEYS, __name__),
                           SPHOptions,
                           ("flow_stress", "failure", "failure_model", "viscosity_switch", "alpha", "beta",
                            "artificial_stress", "h_factor", "cfl"),
                           __name__)


class BinningSection(Section):
    """The hand-off HydroGrid: cubic cells (the report's DC3D cells are 0.03175 cm) and how the SPH
    particles are assigned to them: each with its own SPH kernel (``"kernel"``) or cloud-in-cell
    (``"cic"``), :func:`impactdyn.shield.bin_to_hydrogrid`.

    cell_size_cm : the cubic cells' edge (default the report's DC3D cells, 0.03175 cm).  Every cell
        with enough material becomes five debris particles, so halving it makes eight times as many;
        it must be smaller than ``wall.spacing_cm``.
    method : "kernel" (default): each SPH particle's mass and momentum spread over the cells by its
        own smoothing kernel; "cic": cloud-in-cell, each particle shared (trilinearly) among the 8
        cells whose centres surround it.
    """

    cell_size_cm: float = field_of(bin_to_hydrogrid, "cell_size_cm")
    method: BinningMethod = field_of(bin_to_hydrogrid, "method")


class DebrisMaterialSection(Section):
    """Constants of the debris particles (dc3din record 13–14).

    μ and λ default to the projectile material's G and K − 2G/3 (K = ρ₀c₀²);
    η and ζ to the report's App. C values; the bounds are :class:`impactdyn.debris.ParticleMaterial`'s
    (the bulk modulus λ + ⅔μ, which may take μ from the projectile, is checked by the case).  The
    reference density is the projectile material's.

    mu_Mbar : the particles' shear modulus μ; none: the projectile material's G.
    lambda_Mbar : Lamé's first constant λ; none: K − ⅔μ with the projectile material's bulk
        modulus K = ρ₀c₀².  The bulk modulus λ + ⅔μ must be positive and the wave speed below light.
    eta_Mbar_us : the plastic viscosity η of the flow rule Ėₚ = (2μ/η)(E' − Eₚ): the deviatoric
        strain relaxes at the rate 2μ/η; none: no plastic flow (η = ∞).  0.01: the report's
        (App. C).
    zeta_Mbar_us : the artificial bulk viscosity ζ ≥ 0, which damps the particles' volumetric
        ringing (1.0: the report's, App. C).
    """

    mu_Mbar: float | None = field_of(ParticleMaterial, "mu", None)
    lambda_Mbar: float | None = field_of(ParticleMaterial, "lam", None)
    eta_Mbar_us: float | None = field_of(ParticleMaterial, "eta", 0.01)
    zeta_Mbar_us: float = field_of(ParticleMaterial, "zeta", 1.0)


class _WallSolverBase(Section):
    """The wall stage's solver: the settings of :class:`impactdyn.wall.WallOptions` (its defaults and
    bounds are the only ones) but the supports, which follow ``wall.clamped_edges`` (clamped, or
    DYNGEN's edge codes) as the decks do."""

    @model_validator(mode="after")
    def _valid(self) -> "_WallSolverBase":
        try:
            self.options(clamped_edges=True)
        except InputError as err:
            raise ValueError(str(err)) from None
        return self

    def options(self, clamped_edges: bool) -> WallOptions:
        """The solver options, with the supports of the wall's edges."""
        return WallOptions(**self.model_dump(), supports="clamped" if clamped_edges else "dyngen")


WallSolverSection = section_of("WallSolverSection", _WallSolverBase, WallOptions,
                               [name for name in get_type_hints(WallOptions) if name != "supports"], __name__)


#: A test shot's outcome in the verdicts' words: the database's P counts a detached spall, as JSC test practice
#: does, as a failed rear wall, so a failed wall reads as either.
TEST_OUTCOMES = {True: "perforation or detached spall", False: "no perforation"}


class DatabaseShotSection(Section):
    """The test database's shot that the case reproduces (``whipple shot`` writes it): where the shot is and
    what the test gave, for the report to set beside the verdicts.  No stage reads it.

    database : the test database file's name.
    line : the shot's line in that file.
    source : the publication that gives the shot.
    shot_id : the shot's identifier in that publication's table of tests, as the database lists it.
    perforated : the test's outcome: true where the rear wall was perforated or spalled (P).
    """

    database: str
    line: int
    source: str
    shot_id: str
    perforated: bool

    @property
    def name(self) -> str:
        """The shot as a reader finds it: source, ID and file line."""
        return f"{self.source} {self.shot_id} (line {self.line} of {self.database})"

    @property
    def outcome(self) -> str:
        return TEST_OUTCOMES[self.perforated]


class WhippleCase(Section):
    """A complete Whipple case (every table of the TOML file).

    title : a name for the case, shown at the top of the report and written as the decks' title.
    test_shot : the test database's shot the case reproduces (:class:`DatabaseShotSection`); none: the case is no
        test shot.
    materials : the case's own alloys, ``[materials.NAME]`` tables (:class:`impactdyn.materials.MaterialTable`),
        which ``[projectile]``, ``[bumper]`` and ``[wall]`` then name like the library's; none: the
        library's alone.
    """

    title: str = ""
    test_shot: DatabaseShotSection | None = None
    materials: MaterialsTable | None = None  # before the tables that name them: validated (registered) first
    projectile: ProjectileSection
    bumper: BumperSection
    wall: WallSection
    shield: ShieldSection = ShieldSection()
    binning: BinningSection = BinningSection()
    debris: DebrisMaterialSection = DebrisMaterialSection()
    filter: FilterSection = FilterSection()
    integrator: IntegratorSection = IntegratorSection()
    compute: ComputeSection = ComputeSection()
    output: OutputSection = OutputSection()
    legacy: LegacySection = LegacySection()
    wall_solver: WallSolverSection = WallSolverSection()

    @model_validator(mode="wrap")
    @classmethod
    def _one_error_per_bad_material(cls, data, handler):
        try:
            return handler(data)
        except ValidationError as err:
            raise without_material_echoes(err) from None

    @model_validator(mode="after")
    def _fits(self) -> "WhippleCase":
        p, b, w, s = self.projectile, self.bumper, self.wall, self.shield
        if self.fragment_options.grady:
            lacking = [f"{key}.material = {m.material!r}" for key, m in (("projectile", p), ("bumper", b))
                       if get_material(m.material).fracture_toughness is None]
            if lacking:
                raise ValueError(f"shield.failed_fragments = \"grady\": no fracture toughness for "
                                 f"{', '.join(lacking)} (no fracture_toughness in its material record)")
        if s.failure_model == "fragmentation":
            for key, m in (("projectile", p), ("bumper", b)):
                try:
                    get_material(m.material).require("weibull_flaws", f"{key}.material with shield.failure_model "
                                                                      "= \"fragmentation\"")
                except InputError as err:
                    raise ValueError(str(err)) from None
        if w.yield_stress_ksi is None and get_material(w.material).tensile_yield is None:
            raise ValueError(f"wall.yield_stress_ksi: not given, and the wall's material {w.material!r} has no "
                             "tensile yield stress to take it from (strength.tensile_yield_MPa of a case's "
                             "material); give one of them")
        coarse = spacing_too_coarse(s.spacing_cm, p.diameter_cm, b.thickness_cm, plate="bumper")
        if coarse:
            raise ValueError(f"shield.spacing_cm = {s.spacing_cm} is too coarse {coarse}")
        if b.radius_cm is not None and b.radius_cm <= p.diameter_cm / 2:
            raise ValueError(f"bumper.radius_cm = {b.radius_cm} must exceed the projectile radius")
        reach = units.km_s_to_cm_us(p.velocity_km_s) * s.handoff_us  # cm: no debris outruns the projectile
        if reach >= w.spacing_cm:
            raise ValueError(
                f"wall.spacing_cm = {w.spacing_cm} cannot hold the hand-off grid: by shield.handoff_us = "
                f"{s.handoff_us} µs debris at up to {p.velocity_km_s} km/s may be {reach:.4g} cm behind the "
                "bumper, at or past the wall; increase the spacing or hand off earlier")
        if self.binning.cell_size_cm >= w.spacing_cm:
            raise ValueError(f"binning.cell_size_cm = {self.binning.cell_size_cm} does not fit in the "
                             f"{w.spacing_cm} cm between bumper and wall")
        y0 = self.wall_front_y  # the debris case's wall.y_cm
        check_ranges([("the wall's y extent (bumper.thickness_cm + wall.spacing_cm, + wall.thickness_cm)",
                       [y0, y0 + w.thickness_cm], w.nodes[1])], "wall.nodes")
        debris = debris_material_constants(self)
        names = [f"debris.{key}" if getattr(self.debris, key) is not None else
                 f"debris.{key} (default: from projectile.material = {p.material!r})"
                 for key in ("lambda_Mbar", "mu_Mbar")]
        check_bulk_modulus(debris["lambda_Mbar"], debris["mu_Mbar"], names)
        check_wave_speed(debris["lambda_Mbar"], debris["mu_Mbar"], debris["rho_ref_g_cm3"],
                         (*names, f"the density of projectile.material = {p.material!r}"))
        try:
            resolve_model(w.material, self.wall_options)
        except InputError as err:
            raise ValueError(f"wall.material = {w.material!r} with wall_solver.material_model = "
                             f"{self.wall_solver.material_model!r}: {err}") from None
        solver = self.wall_solver
        try:
            check_mesh_sizes(min(w.x_cm[1] - w.x_cm[0], w.z_cm[1] - w.z_cm[0]), solver.element_size_cm,
                             solver.max_element_size_cm)
            if solver.deposition_depth_cm is not None:
                check_deposition_depth(solver.deposition_depth_cm, w.thickness_cm)
        except InputError as err:
            raise ValueError(f"wall_solver.{err}") from None
        import math

        from impactdyn._limits import SPH_PARTICLE_BYTES, check_fits  # SPH particles, before allocating them

        dx, R = s.spacing_cm, DEFAULT_PLATE_RADIUS_D * p.diameter_cm if b.radius_cm is None else b.radius_cm
        across, radius, layers = p.diameter_cm / dx, R / dx, max(1.0, b.thickness_cm / dx - 0.5)  # in spacings
        n = across * across * across * math.pi / 12 + radius * radius * math.pi / 2 * layers  # half sphere, disc
        check_fits(f"shield.spacing_cm = {dx:g} for the {p.diameter_cm:g} cm projectile and the {R:g} cm "
                   f"radius, {b.thickness_cm:g} cm bumper", n, SPH_PARTICLE_BYTES, "SPH particles")
        return self

    @property
    def wall_yield_ksi(self) -> float:
        """σ_y of the JSC equations, ksi: ``wall.yield_stress_ksi``, or the wall material's tensile yield."""
        if self.wall.yield_stress_ksi is not None:
            return self.wall.yield_stress_ksi
        return get_material(self.wall.material).tensile_yield / units.MBAR_PER_KSI

    @property
    def wall_front_y(self) -> float:
        """y of the wall's front face, cm."""
        return self.bumper.thickness_cm + self.wall.spacing_cm

    @property
    def fragment_options(self) -> FragmentOptions:
        """How the shield stage's debris becomes fragments (:class:`impactdyn.shield.FragmentOptions`, from
        ``[shield]``): the one place the stages, the report and the limit take them from."""
        return self.shield.fragment_options()

    @property
    def wall_options(self):
        """The wall stage's :class:`impactdyn.wall.WallOptions`: the ``[wall_solver]`` table with the
        wall's supports (``wall.clamped_edges``); the one place the stages and the decks take them from."""
        return self.wall_solver.options(self.wall.clamped_edges)


def load_whipple_case(path: str | Path) -> WhippleCase:
    """Load and validate a Whipple case file."""
    return validate(WhippleCase, load_toml(path), source=str(path))


def shield_problem(case: WhippleCase):
    """The SPH sphere-on-plate problem and options of the shield stage."""
    from impactdyn.shield import sphere_on_plate

    p, b, s = case.projectile, case.bumper, case.shield
    problem = sphere_on_plate(p.material, b.material, diameter_cm=p.diameter_cm, velocity_km_s=p.velocity_km_s,
                              obliquity_deg=p.obliquity_deg, plate_thickness_cm=b.thickness_cm,
                              spacing_cm=s.spacing_cm, plate_radius_cm=b.radius_cm)
    return problem, s.sph_options()


def projectile_mass(case: WhippleCase) -> float:
    """The projectile's mass ρ₀ π d³/6, g (the full sphere)."""
    import math

    return get_material(case.projectile.material).rho0 * math.pi * case.projectile.diameter_cm ** 3 / 6.0


def binning_region(case: WhippleCase, particles) -> tuple:
    """The hand-off grid's box: behind the bumper's back face (y ≥ t_b), from the symmetry plane x = 0,
    over the particles there, corners rounded outward to whole cells."""
    import math

    import numpy as np

    cell, y0 = case.binning.cell_size_cm, case.bumper.thickness_cm
    x = particles.position[particles.position[:, 1] >= y0]
    if len(x) == 0:
        x = np.array([[cell, y0 + cell, 0.0]])
    return ((0.0, cell * math.ceil(x[:, 0].max() / cell + 1e-9)),
            (y0, y0 + cell * math.ceil((x[:, 1].max() - y0) / cell + 1e-9)),
            (cell * math.floor(x[:, 2].min() / cell), cell * math.ceil(x[:, 2].max() / cell + 1e-9)))


def debris_material_constants(case: WhippleCase) -> dict:
    """μ, λ, ρ_ref, η, ζ of the debris particles (Mbar, g/cm³, Mbar·µs)."""
    m: Material = get_material(case.projectile.material)
    bulk = m.rho0 * m.c0**2
    mu = case.debris.mu_Mbar if case.debris.mu_Mbar is not None else m.shear_modulus
    lam = case.debris.lambda_Mbar if case.debris.lambda_Mbar is not None else bulk - mu / 1.5  # 2μ may overflow
    return dict(mu_Mbar=mu, lambda_Mbar=lam, rho_ref_g_cm3=m.rho0, eta_Mbar_us=case.debris.eta_Mbar_us,
                zeta_Mbar_us=case.debris.zeta_Mbar_us)


def debris_case(case: WhippleCase, grid_file: str) -> DebrisCase:
    """The debris case the Whipple case implies, reading the hand-off grid from ``grid_file``.

    Written as ``debris/config.resolved.toml``, it reruns the debris stage alone
    with ``impactdyn debris run``.
    """
    w = case.wall
    y0 = case.wall_front_y
    shared = {name: getattr(case, name).model_dump() for name in ("filter", "integrator", "compute", "output",
                                                                  "legacy")}
    own = {"materials": case.model_dump(mode="json")["materials"]} if case.materials else {}
    return validate(DebrisCase, shared | own | {
        "title": case.title, "grid": {"file": grid_file}, "material": debris_material_constants(case),
        "wall": {"x_cm": list(w.x_cm), "y_cm": [y0, y0 + w.thickness_cm], "z_cm": list(w.z_cm),
                 "nodes": list(w.nodes), "clamped_edges": w.clamped_edges, "material": w.material,
                 "momentum_transfer": w.momentum_transfer}}, source="debris case of the Whipple case")


def ble_shield(case: WhippleCase):
    """The NASA JSC Whipple shield of the case (:class:`impactdyn.ble.WhippleShield`)."""
    from impactdyn.ble import WhippleShield

    return WhippleShield(bumper_thickness_cm=case.bumper.thickness_cm, wall_thickness_cm=case.wall.thickness_cm,
                         spacing_cm=case.wall.spacing_cm, wall_yield_ksi=case.wall_yield_ksi)

