"""Debris case files: the TOML schema of ``impactdyn debris run`` (units cm, g, µs, Mbar).

A case names its hydrocode state (a HydroGrid file in any registered format, or
the analytic shell cloud of :mod:`._analytic`), the debris material, the filters,
the wall, the integrator, where the chunks run and what to write.  Problem setup
only: :func:`build` turns a case into the arguments of
:func:`impactdyn.debris.run_debris`.  See ``examples/debris/*.toml``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Literal

from pydantic import Field, model_validator

from impactdyn import units
from impactdyn._config import NonNegative, Positive, Section, load_toml, validate
from impactdyn._errors import InputError

# TOML arrays are lists; strict validation does not turn them into tuples.
Vector = Annotated[list[float], Field(min_length=3, max_length=3)]
Range = Annotated[list[float], Field(min_length=2, max_length=2)]
NodeCount = Annotated[int, Field(ge=2)]


class ShellSection(Section):
    """The analytic debris cloud (:class:`impactdyn.debris.ShellCloud`)."""

    centre_cm: Vector
    velocity_km_s: Vector
    expansion_velocity_km_s: NonNegative
    radius_cm: Positive
    thickness_cm: Positive
    cap_half_angle_deg: Annotated[float, Field(gt=0, le=180)] = 180.0
    density_g_cm3: Positive = 2.703
    void_fraction: Annotated[float, Field(ge=0, lt=1)] = 0.5
    sound_speed_km_s: NonNegative = 5.24
    time_us: float = 0.0
    cell_size_cm: Positive = 0.03175
    subsamples: Annotated[int, Field(ge=1, le=8)] = 3

    @model_validator(mode="after")
    def _thin(self) -> "ShellSection":
        if self.thickness_cm > self.radius_cm:
            raise ValueError(f"thickness_cm = {self.thickness_cm} exceeds radius_cm = {self.radius_cm}")
        from impactdyn.hydrogrid import check_cells  # the grid of debris._analytic, before it is built

        x0, R, h = self.centre_cm[0], self.radius_cm, self.cell_size_cm
        check_cells(f"cell_size_cm = {h:g} for the {R:g} cm shell",
                    [max(1.0, (x0 + R - max(0.0, x0 - R)) / h), 2 * R / h, 2 * R / h])
        return self


class GridSection(Section):
    """Where the hand-off state comes from: ``file`` (relative to the case file) or ``shell``."""

    file: str | None = None
    format: str | None = None
    shell: ShellSection | None = None

    @model_validator(mode="after")
    def _one_source(self) -> "GridSection":
        if (self.file is None) == (self.shell is None):
            raise ValueError("give exactly one of grid.file and grid.shell")
        return self


class MaterialSection(Section):
    """Debris material (dc3din record 13–14); omit eta for no plastic flow."""

    mu_Mbar: Positive
    lambda_Mbar: float
    rho_ref_g_cm3: Positive
    eta_Mbar_us: Positive | None = None
    zeta_Mbar_us: NonNegative = 0.0

    @model_validator(mode="after")
    def _bulk(self) -> "MaterialSection":
        if self.lambda_Mbar + 2.0 * self.mu_Mbar / 3.0 <= 0:
            raise ValueError("lambda_Mbar + 2/3 mu_Mbar must be > 0 (bulk modulus)")
        return self


class FilterSection(Section):
    """Which cells become particles and which particles are carried (dc3din record 8)."""

    dencut: NonNegative = 0.01
    min_density_ratio: NonNegative = 0.01
    max_density_ratio: Positive = 1000.0
    max_void_fraction: Annotated[float, Field(ge=0, le=1)] = 0.999
    t_min_us: NonNegative = 0.0
    t_cut_us: Positive = 25.0

    @model_validator(mode="after")
    def _window(self) -> "FilterSection":
        if self.t_cut_us <= self.t_min_us:
            raise ValueError(f"t_cut_us = {self.t_cut_us} must exceed t_min_us = {self.t_min_us}")
        return self


class RemapSection(Section):
    """A second face grid to remap the deposition onto (DCPOST, dc3din's new wall grid)."""

    x_cm: Range
    z_cm: Range
    nodes: Annotated[list[NodeCount], Field(min_length=2, max_length=2)]


class WallSection(Section):
    """The rear wall: its front face is the plane y = y_cm[0]; nodes = (x, y, z) node counts (DYNGEN)."""

    x_cm: Range
    y_cm: Range
    z_cm: Range
    nodes: Annotated[list[NodeCount], Field(min_length=3, max_length=3)]
    clamped_edges: bool = True
    remap: RemapSection | None = None

    @model_validator(mode="after")
    def _ranges(self) -> "WallSection":
        ranges = [("x_cm", self.x_cm), ("y_cm", self.y_cm), ("z_cm", self.z_cm)]
        if self.remap is not None:
            ranges += [("remap.x_cm", self.remap.x_cm), ("remap.z_cm", self.remap.z_cm)]
        for name, (lo, hi) in ranges:
            if not hi > lo:
                raise ValueError(f"wall.{name} = [{lo}, {hi}]: the upper bound must exceed the lower")
        from impactdyn.wallgrid import check_nodes  # sizes: InputError before anything is allocated

        check_nodes("wall.nodes", self.nodes)
        if self.remap is not None:
            check_nodes("wall.remap.nodes (x, 2 through the thickness, z)", [self.remap.nodes[0], 2,
                                                                           self.remap.nodes[1]])
        return self


class IntegratorSection(Section):
    method: str = "splitting4"
    eps: Annotated[float, Field(gt=0, lt=1)] = 1e-6
    steps_per_period: Annotated[float, Field(gt=3.2)] | None = None
    """Splitting steps per period of the fastest vibration; default: the method's own."""
    max_steps: Annotated[int, Field(ge=1)] = 10_000_000
    ymxref: Positive = 1e-6

    @model_validator(mode="after")
    def _known(self) -> "IntegratorSection":
        from impactdyn.debris._integrators import INTEGRATORS

        if self.method not in INTEGRATORS:
            raise ValueError(f"method = {self.method!r}: choose one of {sorted(INTEGRATORS)}")
        return self

    @model_validator(mode="before")
    @classmethod
    def _method_step(cls, data):
        """Fill in the method's own steps_per_period, so config.resolved.toml records the step used."""
        from impactdyn.debris._integrators import DEFAULT_STEPS_PER_PERIOD

        if isinstance(data, dict) and data.get("steps_per_period") is None:
            method = data.get("method", cls.model_fields["method"].default)
            if method in DEFAULT_STEPS_PER_PERIOD:
                return {**data, "steps_per_period": DEFAULT_STEPS_PER_PERIOD[method]}
        return data


class ComputeSection(Section):
    """Where the particle chunks run; ``address`` of a Dask scheduler (omit for a LocalCluster)."""

    scheduler: Literal["local", "dask"] = "local"
    address: str | None = None
    chunk_size: Annotated[int, Field(ge=1)] = 65536
    workers: Annotated[int, Field(ge=1)] | None = None


class OutputSection(Section):
    hdf5: bool = True
    vtk: bool = True
    lsdyna_deck: bool = True
    dyna3d_deck: bool = True
    plots: bool = True
    pulse_width_us: Positive = 0.05
    """Width of the triangular force pulse that carries each deposited impulse in the LS-DYNA deck."""
    end_time_us: Positive | None = None
    """LS-DYNA termination time; default: the last arrival plus 10 µs."""
    max_vtk_particles: Annotated[int, Field(ge=1)] = 2_000_000


class LegacySection(Section):
    """The listing's behaviour where it departs from the model (DESIGN §5), one flag each."""

    nddata_swap: bool = False
    fdot_scaling: bool = False
    inertia_transform: bool = False
    eta_per_volume: bool = False
    abs_arrival: bool = False
    vertex_scaling: bool = False
    momentum_enhancement: bool = False


class DebrisCase(Section):
    """A complete debris case (every table of the TOML file)."""

    title: str = ""
    grid: GridSection
    material: MaterialSection
    filter: FilterSection = FilterSection()
    wall: WallSection
    integrator: IntegratorSection = IntegratorSection()
    compute: ComputeSection = ComputeSection()
    output: OutputSection = OutputSection()
    legacy: LegacySection = LegacySection()


def load_debris_case(path: str | Path) -> DebrisCase:
    """Load and validate a case; a relative ``grid.file`` is taken relative to the case file."""
    path = Path(path)
    data = load_toml(path)
    grid = data.get("grid")
    if isinstance(grid, dict) and isinstance(grid.get("file"), str) and not Path(grid["file"]).is_absolute():
        grid["file"] = str((path.parent / grid["file"]).resolve())
    return validate(DebrisCase, data, source=str(path))


def hand_off_grid(case: DebrisCase, source: str = "<case>"):
    """The HydroGrid a case names: its analytic shell cloud, or its file read through the format registry."""
    from impactdyn.debris._analytic import ShellCloud, shell_cloud_grid

    g = case.grid
    if g.shell is not None:
        s = g.shell
        kms = units.CM_US_PER_KM_S
        return shell_cloud_grid(ShellCloud(
            centre=tuple(s.centre_cm), velocity=tuple(v * kms for v in s.velocity_km_s),
            expansion_velocity=s.expansion_velocity_km_s * kms, radius=s.radius_cm, thickness=s.thickness_cm,
            cap_half_angle_deg=s.cap_half_angle_deg, density=s.density_g_cm3, void_fraction=s.void_fraction,
            sound_speed=s.sound_speed_km_s * kms, time=s.time_us), s.cell_size_cm, s.subsamples)
    from impactdyn.io import read_grid

    if not Path(g.file).is_file():
        raise InputError(f"{source}: grid.file: {g.file}: no such file")
    return read_grid(g.file, g.format)


def build(case: DebrisCase, source: str = "<case>", grid=None) -> dict:
    """The hand-off grid, wall and options of a case: keyword arguments of ``run_debris``.

    ``grid``: a HydroGrid already in hand, used instead of reading ``case.grid``.
    """
    from impactdyn.debris._particle import ParticleMaterial
    from impactdyn.debris._propagate import (
        ArrivalWindow, ComputeOptions, DepositionOptions, IntegratorOptions)
    from impactdyn.debris._seed import SeedFilter, SeedOptions
    from impactdyn.wallgrid import WallGrid

    grid = hand_off_grid(case, source) if grid is None else grid
    w, m, f, lg = case.wall, case.material, case.filter, case.legacy
    wall = WallGrid.uniform(w.x_cm, w.y_cm, w.z_cm, w.nodes)
    material = ParticleMaterial(mu=m.mu_Mbar, lam=m.lambda_Mbar, rho_ref=m.rho_ref_g_cm3,
                        eta=float("inf") if m.eta_Mbar_us is None else m.eta_Mbar_us, zeta=m.zeta_Mbar_us,
                        legacy_eta_per_volume=lg.eta_per_volume)
    i, c = case.integrator, case.compute
    return dict(
        grid=grid, wall=wall, material=material,
        seed_filter=SeedFilter(dencut=f.dencut, min_density_ratio=f.min_density_ratio,
                               max_density_ratio=f.max_density_ratio, max_void_fraction=f.max_void_fraction),
        seed_options=SeedOptions(legacy_nddata_swap=lg.nddata_swap, legacy_fdot_scaling=lg.fdot_scaling,
                                 legacy_inertia_transform=lg.inertia_transform),
        window=ArrivalWindow(t_min=f.t_min_us, t_cut=f.t_cut_us, legacy_abs_arrival=lg.abs_arrival),
        integrator=IntegratorOptions(method=i.method, eps=i.eps, steps_per_period=i.steps_per_period,
                                     max_steps=i.max_steps, ymxref=i.ymxref),
        compute=ComputeOptions(scheduler=c.scheduler, address=c.address, chunk_size=c.chunk_size,
                               workers=c.workers),
        deposition=DepositionOptions(legacy_vertex_scaling=lg.vertex_scaling,
                                     legacy_momentum_enhancement=lg.momentum_enhancement),
    )


def remap_grid(case: DebrisCase):
    """The remap face grid as a one-element-thick WallGrid, or None."""
    from impactdyn.wallgrid import WallGrid

    r = case.wall.remap
    if r is None:
        return None
    return WallGrid.uniform(r.x_cm, case.wall.y_cm, r.z_cm, (r.nodes[0], 2, r.nodes[1]))
