"""Options of the wall solver (a config section: the one home of their defaults and bounds, which a
case's ``[wall_solver]`` table takes over), and the solver's breakdown error."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field

from impactdyn._config import NonNegative, Positive, Section
from impactdyn._errors import SimulationError
from impactdyn.wall._grading import GRADING_RATIO, MAX_GRADING_RATIO
from impactdyn.wall._failure_law import FAILURE_LAWS
from impactdyn.wall._johnson_cook import FRACTURE_STRAIN_FLOORS
from impactdyn.wall._load import SPREADS
from impactdyn.wall._mesh import MESH_KINDS, SUPPORTS
from impactdyn.wall._models import MODELS

HOURGLASS_FORMS = ("viscous", "stiffness", "assumed_strain")
#: LS-DYNA's hourglass type (IHQ) of each form: Flanagan–Belytschko viscous 2 and stiffness 4,
#: Belytschko–Bindeman assumed strain 6 (whose QH is 1: the form has no coefficient; LS-DYNA's
#: type 6 keeps the elastic moduli, this solver's follows the material's tangent, :mod:`._hourglass`).
LSDYNA_HOURGLASS_TYPE = {"viscous": 2, "stiffness": 4, "assumed_strain": 6}


class WallSolverError(SimulationError):
    """The wall solver broke down: a non-finite state, an element of non-positive volume that
    had not failed, or a collapsing time step.  The message names the element and the time.
    The CLI reports it as "simulation failed" with exit code 1 (:mod:`impactdyn._errors`).
    """


#: A number in (0, 1].
Fraction = Annotated[float, Field(gt=0, le=1)]


class WallOptions(Section):
    """Numerical and physical options of :func:`impactdyn.wall.run_wall` (units µs, km/s).

    mesh : "graded" (default; :mod:`._grading`): near-cubic elements of the core size in the region
        the debris load is densest, growing by at most ``grading_ratio`` per element to the case
        grid's cell, with every record's impulse re-binned onto the mesh exactly; or "report": the
        case's grid as the report's DYNA3D model had it (51 × 5 × 101 nodes for Table 2), for
        comparison with the 1994 results.
    element_size_cm : the core element's edge; None (default): the rule of
        :func:`impactdyn.wall.core_element_size` (8 layers through the thickness at least, and 4
        elements across the crater of a 0.06-cm fragment at 6 km/s).
    grading_ratio : the largest ratio of neighbouring element sizes of the graded mesh (1.2).
    max_element_size_cm : the largest in-plane element of the graded mesh; None: the case grid's.
    refinement_thickness, refinement_plane : every element of the mesh (either kind) cut into
        that many layers and pieces along each in-plane axis (:mod:`._mesh`): the convergence
        study's "2×" is 2 and 2.
    material_model : a registered model name (:data:`impactdyn.wall.MODELS`): "johnson_cook"
        (default: Johnson–Cook strength, Mie–Grüneisen EOS, JC damage, spall and erosion) or
        "mat13" (the report's DYNA3D type 13).  Why the default: chosen by a rule fixed before
        the runs, on a second set of 12 test shots disjoint from the first (validation set 2,
        validation/select_validation_shots.py): right on 7 of 12 with 5 perforations called
        safe, against 6 of 12 and all 6 perforations called safe with the type-13 card, whose
        only failure criterion (an effective plastic strain of 1.5) no element reached on
        either set (docs/vv/test-shots.md, "The simulated verdict on the validation sets").
    supports : "dyngen" (DYNGEN's edge codes), "clamped", "free" or "uniaxial" (:mod:`._mesh`).
    hourglass : "assumed_strain" (default; Belytschko–Bindeman: the element's own bending and
        twisting stiffness, loaded at the material's tangent, unloaded elastically, bounded by
        the flow stress in yielding elements, :mod:`._hourglass`) or the Flanagan–Belytschko forms
        "stiffness" and "viscous".  Why the default (docs/vv/cross-code.md, "The wall solver against CalculiX"):
        on the clamped-plate check it is mesh-converged (0.244 / 0.249 / 0.251 cm at h 0.1 /
        0.05 / 0.025) and within 5 % of CalculiX (+0.2 % at h 0.1), where the stiffness form
        with QH 0.1 gave 0.117 / 0.226 / 0.241 (−52 % against CalculiX): its κ ∝ ΣB²/V grows
        with the largest face and over-stiffens the bending of elements flat in the thickness.
        On the ``table2_7a`` wall both forms give the same bulge within 1 % (0.353 / 0.349 cm);
        on the 0.16-cm wall of test shot A1603 (elements 4:1 flat) the hourglass work is 6 % of
        the internal energy against the stiffness form's 29 %.  What it costs: it keeps 21
        stresses per element and is ~30 % slower per step; its hourglass work — the element's
        own bending energy, not a spurious mode's: in bending with n elements through the
        thickness 1/(n² − 1) of the stress work, 6.7 % at the report's n = 4 (tested) — is 5.8 %
        of the internal energy on 7a with the type-13 card (stiffness 2.1 %), 13 % with
        Johnson–Cook (whose erosion leaves ligaments of 1–3 elements bending) and 17 % on the
        synthetic 7-km/s-like load of benchmarks/bench_wall.py at 40 µs (stiffness 11 %).  The
        viscous form took 55–75 % there.
    hourglass_coefficient : QH of the Flanagan–Belytschko forms (LS-DYNA's default 0.1); the
        assumed-strain form has no coefficient.
    q1, q2 : quadratic and linear bulk-viscosity coefficients (LS-DYNA's 1.5, 0.06).
    courant : safety factor on the smallest element step (0.9).
    end_time_us : end of the run; None: run until the kinetic energy of the wall (nodes of
        intact material connected to the supports, :mod:`._verdict`) has fallen below
        ``decay_fraction`` of its peak after the last arrival, or ``max_time_us``.  The solver has
        no structural damping, so a supported wall rings elastically and its kinetic energy
        seldom decays that far: every Table 2 and validation run (40 runs) ends at the ceiling
        with 4–54 % of the load's work still kinetic; ``measures["ended_by"]`` says
        which end a run met (docs/vv/convergence.md, "The wall: Table 2 at the default mesh and at twice its resolution").
    decay_fraction : the fraction of the peak kinetic energy that ends a run (0.05).
    perforation_hold_us : a run without ``end_time_us`` ends (``ended_by`` "perforated") this long
        after a through-thickness path of failed or eroded elements has formed and the last
        record so far has arrived, whichever is later; None: never on that account.  Failure is
        for good, so the verdict is "perforation" from the path's first appearance
        (``perforated_at_us``, to a history sample); the hold only lets the hole and the failed mass
        that the report shows grow on for a stated time, and they are those of the end of the run,
        not of a wall at rest.  Records arriving after that end (a late compact fragment) are not
        applied; the measures count them (``unapplied_records``, ``impulse_unapplied``).
    max_time_us : ceiling of the run's end time (absolute time, µs).
    output_interval_us : time between output frames (ParaView series); None: the first and last frames
        only.  2 µs: 51 frames of a 100-µs run; each frame of the graded 7a wall is 5 MB (71,280
        elements), so the series stays near the report mesh's 1-µs series (146 MB against 260 MB;
        at 1 µs, 513 MB).
    history_interval_us : time between history samples (energies, bulge).
    spread : how a record's impulse is shared among the front-face nodes (:mod:`._load`):
        "area" by default — DYNA3D's equal quarters on the corners at in-plane refinement 1,
        the tributary areas of the sub-faces when refined ("corners" keeps the quarters on
        the parent's corners, which on a refined mesh leaves the nodes between them unloaded
        and crushed the loaded ones: failed mass 0 → 0.41 g at 2× refinement on a synthetic
        7-km/s-like load).
    deposition_depth_cm : the depth δ (cm) below the front face over which each record's
        impulse is spread as a uniform body force (:mod:`._load`).  None (default): half the
        first element layer of the case's grid, which at refinement 1 is DYNA3D's nodal load
        on the front face exactly and on a refined mesh the same load over the same depth;
        0: the front-face nodes alone at every refinement (the load's energy then grows with
        the refinement through the thickness).  Must not exceed the wall's thickness.
    settle : after the run, let the wall swing back once and bring it to rest by kinetic damping,
        and report its permanent rear bulge (:meth:`impactdyn.wall.WallSolver.settle`); off by
        default: it takes 15–50 times the run's steps (Table 2, 14,300–44,800 against 840–960:
        7a's wall stage about 8 times longer; on a wall of twice the span and four times the
        elements roughly 16 times that).
        Without it no run measures a permanent set: a supported wall still rings when the run
        ends (docs/vv/convergence.md, "The wall: Table 2 at the default mesh and at twice its resolution").
    settle_tolerance : the settling stops at rest with the out-of-balance force on the wall's free
        nodes below this fraction of the element forces that balance there (Euclidean norms;
        1e-3: the 7a bulge to 0.01 %, benchmarks/BENCHMARKS.md, "Settling").
    max_settle_steps : the most steps the settling may take; if reached, ``settled`` is false.
    spall_law : the Johnson–Cook wall's failure law, a registered name (:data:`impactdyn.wall.FAILURE_LAWS`,
        :mod:`impactdyn.wall.failure_laws`, docs/wall.md): "tuler_butcher" (default: Tuler–Butcher
        cumulative damage of the mean tension over a threshold, a failure with a time scale) or "cutoff"
        (the instantaneous pressure cut-off p < −p_spall).
    fracture_strain_floor : the Johnson–Cook wall's floor on the fracture strain: "library" (default:
        the alloy's ε_f,min (:attr:`impactdyn.materials.JohnsonCookDamage.efmin`), where its fit falls
        to zero beyond its data) or "unbounded" (the fit as published, an extrapolation: any plastic
        increment beyond its zero fails the element).
    escape_velocity_km_s : the speed above which rear-face material attached to failed
        material is leaving the wall (verdict, :mod:`._verdict`).
    erosion_step_fraction : a failed element is eroded (it leaves the force computation, its mass and
        momentum stay on its nodes) when its step falls below this fraction of the mesh's initial
        step: LS-DYNA's DTMIN with ERODE = 1, for failed elements only (an intact element's step below
        ``min_step_fraction`` is a breakdown).  Failed material is rubble (compressive pressure
        only), and a step that has collapsed holds every step of the run down with it.  0.25:
        a failed brick flattened at constant volume (stretch λ along one axis, 1/λ along another)
        keeps its sound speed while its length V/A_max falls as 1/λ, so its step falls to 0.25 at
        λ = 4, a geometric (equivalent logarithmic) strain of (2/√3) ln 4 = 1.6 — the value at which
        Ansys's explicit solvers erode distorted elements by default (1.5; "typical values range from
        0.5 to 2.0", Ansys Explicit Dynamics Analysis Guide, erosion controls).  0.1 (λ = 10, strain
        2.7) let the holed walls of two test shots (0.635-cm spheres at 5.3 km/s on a 0.102-cm wall)
        run at a mean step near a tenth of the initial one (benchmarks/BENCHMARKS.md, "Wall stage: a
        holed wall stops early").
    min_step_fraction : a step of an element that has not failed below this fraction of
        the initial step is a breakdown (:class:`WallSolverError`).
    """

    mesh: Literal[MESH_KINDS] = "graded"
    element_size_cm: Positive | None = None
    grading_ratio: Annotated[float, Field(gt=1, le=MAX_GRADING_RATIO)] = GRADING_RATIO
    max_element_size_cm: Positive | None = None
    refinement_thickness: Annotated[int, Field(ge=1)] = 1
    refinement_plane: Annotated[int, Field(ge=1)] = 1
    material_model: MODELS.name_type() = "johnson_cook"
    supports: Literal[SUPPORTS] = "dyngen"
    hourglass: Literal[HOURGLASS_FORMS] = "assumed_strain"
    hourglass_coefficient: NonNegative = 0.1
    q1: NonNegative = 1.5
    q2: NonNegative = 0.06
    courant: Fraction = 0.9
    end_time_us: Positive | None = None
    decay_fraction: Fraction = 0.05
    perforation_hold_us: NonNegative | None = 5.0
    max_time_us: Positive = 100.0
    output_interval_us: Positive | None = 2.0
    history_interval_us: Positive = 0.2
    spread: Literal[SPREADS] = "area"
    deposition_depth_cm: NonNegative | None = None
    settle: bool = False
    settle_tolerance: Fraction = 1.0e-3
    max_settle_steps: Annotated[int, Field(ge=1)] = 200_000
    spall_law: FAILURE_LAWS.name_type() = "tuler_butcher"
    fracture_strain_floor: Literal[FRACTURE_STRAIN_FLOORS] = "library"
    escape_velocity_km_s: Positive = 1.0
    erosion_step_fraction: Annotated[float, Field(ge=0, le=1)] = 0.25
    min_step_fraction: Fraction = 1.0e-3

    def grid_settings(self) -> dict:
        """The keywords of :func:`impactdyn.wall.solver_grid` these options set (the mesh's nodes)."""
        return {key: getattr(self, key) for key in ("mesh", "element_size_cm", "grading_ratio", "max_element_size_cm",
                                                    "refinement_thickness", "refinement_plane")}

    def mesh_settings(self) -> dict:
        """The keywords of :func:`impactdyn.wall.solver_mesh` these options set."""
        return self.grid_settings() | {"supports": self.supports}

    @property
    def hourglass_form(self) -> int:
        """The kernels' code of the hourglass form (its index in :data:`HOURGLASS_FORMS`)."""
        return HOURGLASS_FORMS.index(self.hourglass)

    @property
    def lsdyna_hourglass(self) -> tuple[int, float]:
        """(IHQ, QH) of LS-DYNA's *CONTROL_HOURGLASS for these options (:data:`LSDYNA_HOURGLASS_TYPE`)."""
        ihq = LSDYNA_HOURGLASS_TYPE[self.hourglass]
        return ihq, 1.0 if ihq == 6 else self.hourglass_coefficient


