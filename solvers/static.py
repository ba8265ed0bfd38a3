"""Static: Newton-Raphson on the free DOFs, along the load or along the arc length of the
equilibrium path (docs/theory.md §6.5, §6.6).

Loads and prescribed displacements with a named amplitude are scaled by one load factor lambda,
all of them (gravity and "step" loads included) ramped linearly with it, as a static step does:
named amplitudes shape time histories in dynamics only. Those with a user amplitude a (a
callable) follow it: a(lambda) times their full value at each load factor on the load path (a
load then unload); the arc-length path, which scales one load pattern, refuses one that is not
proportional (docs/theory.md §6.5, "How the loads are ramped"). Each converged increment gives
one frame.

Two ways along the path (``path``):

- "load": ``increments`` equal load-factor steps; an increment that does not converge is cut in
  half and retried from the last converged state.
- "arc_length": Crisfield's cylindrical arc-length method (solvers.arc_length): lambda is an
  unknown, and each increment moves a fixed distance along the path in the space of the nodal
  motions (translations, and director rotations times the element size), so that limit points
  (the load passes a maximum), snap-backs and post-buckling branches are followed instead of
  jumped over. The step length adapts to the number of iterations the previous increment
  needed; the last increment lands on lambda = 1 exactly.

At each load factor: Newton-Raphson with the watchdog line search (solvers.newton), from a
predictor on the arc-length path (and on the load path with ``predictor=True``): from the
second increment on, the previous increment extrapolated (the secant of the path, translations
and director rotations). The negative pivots of each converged tangent count its negative
eigenvalues, and with ``seek_stable`` an unstable equilibrium is left along its buckling mode
(solvers.stability).
"""

from __future__ import annotations

import os

import numpy as np

from femcore.memory import STATIC_BYTES_PER_CELL, check_model_memory
from femcore.model import CompiledModel, Model
from femcore.results import Result
from solvers.arc_length import (
    DESIRED_ITERATIONS,
    arc_length_path,
    check_arc_options,
    check_proportional,
)
from solvers.augmentation import augment_contacts
from solvers.blas_threads import one_blas_thread
from solvers.common import (
    check_flag,
    check_held,
    check_integer,
    check_non_negative,
    check_positive_or_none,
    check_progress,
    check_tolerance,
    compiled_model,
)
from solvers.interrupts import check_outputs, keeps_writes
from solvers.load_path import LOAD_DEFAULTS, check_load_options, load_path
from solvers.newton_curvature import CORRECTIONS
from solvers.output import output_path
from solvers.stabilisation import check_stabilise, report_stabilisation
from solvers.static_run import StaticRun

__all__ = ["PATHS", "Static", "StaticRun"]

PATHS = ("load", "arc_length")


class Static:
    """Quasi-static solver: Newton-Raphson on the free DOFs with a sparse tangent.

    increments : load path: the number of equal load-factor steps (one frame each); arc-length
        path: sets the first step, whose load-factor increment is 1 / increments, and the
        resolution of the later ones, which adapt: no longer than the first while the path
        keeps its stiffness, and once it has softened no step carrying more than 1 /
        increments of load (solvers.arc_step, docs/theory.md §6.6 "Step length").
    tol : convergence when ||r_forces|| <= tol F_ref and ||r_moments|| <= tol F_ref L_e (or,
        at the round-off floor, when a full Newton step moves no DOF by more than 1e-9 of an
        element or 1e-9 rad while the ratio is below 1e-3, or, on the load path and in the
        arc-length corrector, without interactions and stabilisation, when the ratio is at most
        10 times the rounding of the residual that a rigid translation of the iterate shows,
        and at most 1e-6: solvers.round_off), with
        F_ref = max(||F_ext||, ||F_int||, ||M_ext|| / L_e, ||M_int|| / L_e) (the internal
        forces include the reactions) and L_e the median element edge.
    max_iterations : Newton iterations per (sub-)increment before it is cut in half.
    line_search : the Armijo line search of the load path (module docstring); without it
        every Newton step is taken whole (after the step cap below).
    max_cuts : how many times an increment may be cut (halved; arc length: docs/theory.md §6.6).
        Load path: a first increment that fails is tried once more before it is cut, with the
        frictional contacts' stick springs stiff first (solvers/stick_start.py: plies laid on
        each other hold nothing tangentially at the first iterate otherwise).
    stall_iterations : load path: cut an attempt whose ratio stayed above 0.1 that long.
    first_turn : load path: an increment whose first Newton step, from the last converged
        state, turns a director by more than this (rad) is cut before it is iterated, to the
        largest 1/2^k of it whose first step turns none by more (None, the default: never;
        solvers.load_path, docs/theory.md §6.5 "Increments sized by the first step"). The
        cuts are listed in ``info["first_turn_cuts"]`` as (load factor tried, turn, share
        kept) and are not counted in ``info["cuts"]``; after max_cuts of them in one
        increment its attempts are iterated unchecked. The load path's steps after an arc
        length's jump (``at_limit="jump"``) are checked too, the jump's first step not.
    update_turn : the largest director rotation of a Newton update taken by the line search
        (rad; None, the default: solvers.line_search.MAX_ROTATION, 0.5). A smaller cap keeps a
        turning ply stack's updates within the second-order errors its contact's ramp holds
        (the 4- and 8-ply heavy stacks of plies-deck-of-cards at 0.03: 345 -> 205 and 409 ->
        195 tangents, plies-heavy-cantilever's 233 -> 177; docs/theory.md §6.5, "Updates of a
        turning stack").
    ply_penalty_start : load path: each increment first converged with the frictionless ply
        contacts' penalties times this share in (0, 1), then with the full ones from there
        (None, the default: not; solvers/penalty_start.py, docs/theory.md §6.5, "The deck's
        last increment"); ``info["soft_start_iterations"]`` counts the first phases.
    augmentations : load path, with an augmented contact (``Contact(augmented=True)``,
        elements/augmented_contact.py): the most Uzawa passes per increment (default 20).
        After an increment converges, each augmented contact's multipliers take its springs'
        forces and the increment is solved again from there, until the penetration and the
        elastic slip are within the contact's tolerance; an increment still outside it after
        this many passes is accepted, listed in ``info["augmentations_short"]`` and warned
        about at the end. The passes per increment are in ``info["augmentations"]``, the
        penetration and elastic slip left at each frame in ``info["augmented_penetration"]``
        and ``info["augmented_slip"]`` (mm).
    path : "load" (default) or "arc_length" (module docstring). The arc-length path's own
        options (max_increments, arc_iterations, arc_chords, at_limit) given other than their
        defaults with path="load" are refused (they would be ignored), and so are the load
        path's (predictor, first_turn, ply_penalty_start, follow_tools,
        follow_tools_after_cut) with path="arc_length" and at_limit="follow".
    max_increments : arc-length path: a phase's most increments (default 20 x increments + 20).
    arc_iterations : arc-length path: the iterations Crisfield's step rule aims an increment
        at (default 5: the next length l sqrt(5 / iterations); docs/theory.md §6.6).
    arc_chords : arc-length path: the residual ratio at or below which an iteration steps with
        the factorisation of an earlier iterate of its increment, while each such step lowers
        the ratio tenfold (default 0: never; solvers.arc_length, docs/theory.md §6.6, "Chord
        steps"); Crisfield's rule counts the factorisations. ``info["arc_chords"]`` counts them.
        At most ``LARGEST_CHORD_RATIO`` (1e-2).
    at_limit : arc-length path, at a limit point (the load factor would have to fall):
        "follow" (default) the path down and on, as it is; "jump": go on with load steps of
        1 / increments from there to the end of the phase, which land on the stable branch
        beyond the snap (seek_stable, line search), as a test under growing load or
        displacement does. Each such limit is listed in ``info["jumps"]``.
    predictor : load path: start each increment after the first of a phase from the previous
        increment extrapolated (module docstring) instead of the last converged state. Off by
        default: it cost iterations on the strips and the plies (docs/theory.md §6.5).
    seek_stable : when the tangent of a converged state has negative eigenvalues (an unstable
        equilibrium: a compressed plate that stayed flat), leave it along its lowest mode and
        settle on the stable branch. Load path: the Newton steps that meet an indefinite
        tangent are turned downhill along its negative modes (a "saddle-free" step) and a
        converged saddle is pushed along its mode and Newton goes on from there, up to three
        times per increment; the stable branch beyond a snap-through or a bifurcation is then
        found (the jump a quasi-static test shows), not the unstable part of the path.
        Arc-length path: where the count of negative eigenvalues grows while the load keeps its
        direction (a bifurcation, not a limit point), the next increment starts along the
        buckling mode (up to three times per phase). Each switch is listed in
        ``info["branch_switches"]``, the eigen-solves of the load path (turns and saddles)
        counted in ``info["mode_searches"]``.
        A negative pivot whose eigenvalue lies within the tangent's round-off of zero (a
        zero-energy mode: the uniform tilt of a fibrous body's free directors) is neutral:
        neither counted in ``info["negative_eigenvalues"]`` nor followed (solvers.neutral_modes;
        docs/theory.md §6.5, "Neutral modes").
        Either way a mode is followed only when a push along it (half an element, or down to a
        fiftieth of one, relaxed with its amplitude held) lowers the total potential energy
        beyond round-off (solvers.stability.push_descends); a saddle that no push descends
        from, or whose push Newton does not converge from (``info["escapes_failed"]``), is
        kept (``info["saddles_kept"]``, load path) and the next increment follows it by plain
        Newton: a flat fabric sheared in its plane stays flat. A converged state with cells
        turned inside out (``CompiledModel.inverted_cells``) is refused: the increment is
        cut, and a solve that runs out of cuts names the cells.
        A tangent with more negative eigenvalues than the six the downhill turn computes (a
        wrinkling flange) gets the step of K + delta diag|K| instead, the smallest delta
        leaving no negative pivot (solvers.inertia; every such step of a stabilised
        increment, only the climbing ones otherwise; the deltas in ``info["shifted"]``).
    step_loads_first : apply the loads whose amplitude is "step" (gravity by default) first,
        over load factors 0 to 1 with the prescribed displacements held at zero, then the
        other loads and the prescribed displacements over 1 to 2 (a specimen hangs under its
        weight before a support moves it). Frames then run over load factors 0 to 2.
    tangent : "element" (default): each block's own ``tangent`` where it has one, coloured
        finite differences of ``internal_force`` for the others; "finite_difference": coloured
        finite differences for every block.
    stabilise : load path: c >= 0, the viscous stabilisation of the increments (1/s^2 per unit
        load factor; 0, the default: none): each node is held to where it was at the last
        converged increment by a dashpot c m_i / dlambda (m_i its lumped mass; its director by
        c I_i / dlambda), so that a blank that is a mechanism until the tools hold it (a
        flange that wrinkles) is formed by Newton, as implicit forming codes do
        (solvers.stabilisation). The energy the dashpots dissipated is reported against the
        strain energy in ``info["stabilisation"]``, with a UserWarning past
        STABILISATION_BOUND (5 %) of it at the end.
    chords : load path: after each whole Newton step, up to this many chord corrections
        K^-1 r with the step's own factorisation, each kept while it lowers the total
        potential energy (default 1; 0: none). They take the place of tangents where the
        first steps of an increment stretch a turning strip, and after a curved step they take
        its third-order remainder; a correction costs a force and an energy evaluation and a
        solve. Counted in ``info["chord_corrections"]``; not in increments with prescribed
        motion or contact.
    curved : each Newton step on a definite tangent with the second-order term of its path
        (solvers.newton_curvature; default True): two force evaluations and a solve with the
        step's factors, where a straight step of a turning strip would stretch it. With the
        default chords=1: the Mindlin cantilever of benchmarks/static_solver.py in 4-5-5-5-5
        Newton iterations (9-9-9-8-8 with straight steps and no chord), the elastica and the
        roll-up of validation/cases in at most 6. Counted in ``info["curved_steps"]``; not
        with contact or other interactions, unless ``curved_with_contact``.
    correction : with ``curved``, how much of a curved step's second-order correction w is
        taken: "fitted" (the default) the share a in [1/4, 1] at which the parabola through
        ||r||^2 at the step's end with a = 0, 1/2, 1 is least (three force evaluations more);
        "whole" all of it, the solver before (solvers.newton_curvature, docs/theory.md §6.5,
        "Curved steps"). The whole correction overshot on the first update of the Mindlin
        cantilevers' increments, into a compressed, indefinite iterate: the 2560-triangle
        strip of benchmarks/kratos_cantilever.py 4-5-5-5-4 -> 5-4-4-4-4 iterations and no
        mode search, the elastica 4-6-5-4-4 -> 4-4-4-4-4. Models with a fibrous block or with
        interactions (``curved_with_contact``) take the whole correction either way (the fit
        cost iterations there: the plies of plies-deck-of-cards 882 -> 924).
    curved_with_contact : the curved steps also with interactions that keep no contact sets
        and no history, whose forces the gaps alone decide (the plies' frictionless contact,
        elements/ply_contact.py; not with friction; needs ``curved``; default False;
        docs/theory.md §6.5, "Curved steps of a sliding stack"). The plies of a deck bent by
        end moments take 5-9 iterations an increment instead of 12 and can be
        loaded in 4 increments instead of 8 (validation/cases/plies_deck_of_cards.py); the
        fibrous plies of plies-bai-5.1 and the heavy stacks took 1.8-2 x the tangents with it.
    fibre_projection : each Newton step's end moved back onto the fibre lengths its first
        order asks for (solvers.newton_fibres; default True), on the blocks that give fibre
        edges (MindlinShell(fabric)): the tension stiffness of a fabric's fibres makes the
        stretch a turning step leaves the whole next residual. Peirce's cantilever of
        MindlinShell(fabric) in 4-5-5 iterations (8-12-12 without). Counted in
        ``info["fibre_projections"]`` (steps) and ``info["fibre_projection_sweeps"]``; not with
        contact or other interactions.
    level_projection : each Newton step moving a node by over 1e-2 element sizes corrected, at
        the least energy in the iteration's tangent, so that the level strains and shear
        angles the step keeps nearly constant end where its first order puts them
        (solvers.newton_levels; default True, on FibrousShell blocks; False turns it off):
        Peirce's cantilever 6-5-6 iterations (9-9-10 without); heavy cantilever 0.4-0.6 x the
        CPU; bias pulled 6-4-4-3 (4-4-4-4). ``info["level_projections"]`` counts the steps
        corrected; not with interactions, prescribed motions, or on indefinite tangents.
    compression_free : the residual ratio above which an iteration's tangent leaves the fibres'
        compression out of the fibrous shell's stress terms (docs/theory.md §6.5); 0: never. None
        (the default): solvers.newton.COMPRESSION_FREE (1e-2) on a model with a block that offers
        that tangent (the fibrous shell) and no interaction, 0 otherwise. Far from equilibrium a
        step's remainder compresses fibres thousands of times stiffer than the bending, and the
        geometric stiffness of that spurious compression makes the tangent indefinite (75 negative
        eigenvalues on Peirce's strip), whose downhill turns then steer the next steps. The residual
        is untouched, so the equilibrium is the same; near it (and at every converged state whose
        stability is judged, and at the first iterate of each increment, a converged state whose
        compression is real) the tangent is exact. The fibrous heavy cantilever at 10 cells 47-9-8
        -> 26-9-7 iterations, at 40 cells 47-27-19 -> 49-11-9, Peirce's fibrous cantilever 7-14-11
        -> 10-9-10 (79 -> 75 forces; the same tips to 1e-6 mm; benchmarks/fibrous_newton.py). Not by
        default with contact: the 12-cell hemisphere drape (tests/test_hemisphere_static.py)
        converges with it but with 6 cuts instead of 2. Counted in
        ``info["compression_free_tangents"]``, the ratio used in ``info["compression_free"]``.
    follow_tools : load path: start each increment with the nodes that touch a moving tool
        (and no tool that stays) carried by the tool's prescribed translation over the
        increment (default False): otherwise the tool stands where the increment puts it from
        the first iteration, inside the body by its whole step (the hemisphere drape's punch:
        up to 9.2 mm, 30 blank thicknesses, per tenth of its stroke), and the penalty
        springs' forces there dominate the first Newton steps.
    follow_tools_after_cut : load path: the tool-following start of ``follow_tools`` for the
        sub-increments of an increment that was cut only (default False): an increment that
        converges from the plain start keeps it, and one whose attempt failed is retried, at
        the half step, with the touching nodes carried by the tool (docs/theory.md §6.5).
    progress : show a progress bar on stderr, its share the load factor reached (None: unless
        under pytest or with FIBRESHELL_PROGRESS=0, solvers.progress.resolve_progress).
    output : a ``.pvd`` path: each frame written there (a VTU file each, the ParaView index
        rewritten after each) as its increment converges (a killed run leaves them); all kept.

    Prescribed displacements enter each iteration consistently: the update solves
    K_ff dq_f = r_f - K_fp dq_p for the part dq_p of the prescribed motion not yet applied, so
    the first iteration of an increment moves the structure with the imposed nodes instead of
    dragging them alone. Except with a frictional ply contact, where that first step, on the
    tangent of a state whose touching points all stick, turns a director past the update cap
    or lets go of a touching point (``info["imposed_alone_opened"]``): the imposed motion is
    then applied alone and the return mapping there says which points slide
    (``info["imposed_alone"]``); an attempt that took that first step and fails is tried
    once more with the imposed motion applied alone before the increment is cut
    (``info["imposed_alone_retries"]``; solvers/imposed_alone.py, docs/theory.md §6.5,
    "Prescribed motion against stuck points").

    Stability: every converged state gets the number of negative eigenvalues of the tangent
    K_ff at that state, counted from the pivots of its LDL^T (``info["negative_eigenvalues"]``,
    one entry per frame after the first), those within round-off of zero left out (``seek_stable``
    above). Newton converges one update after its last
    factorisation, so the tangent at the converged state is assembled and factorised once more
    (``info["evaluations"]["stability_tangents"]``; StaticRun.factor_at), unless the last one
    was made there (docs/theory.md §6.5, "The stability of a converged state"); the next
    increment's first iteration takes that tangent and its factors again where it starts from
    that state in a model without interactions (solvers/kept_tangent.py,
    ``info["tangents_reused"]``, not in ``"tangent"``). Load factors
    with a non-zero count (unstable equilibria, past a limit point or a bifurcation) are listed
    in ``info["indefinite_at"]``. A singular tangent is regularised for one update (see
    solvers.newton.newton) and reported if the increment then fails.
    """

    def __init__(
        self,
        increments: int = 10,
        tol: float = 1e-8,
        max_iterations: int = 50,
        line_search: bool = True,
        max_cuts: int = 8,
        stall_iterations: int | None = None,
        first_turn: float | None = None,
        update_turn: float | None = None,
        augmentations: int = 20,
        tangent: str = "element",
        seek_stable: bool = True,
        step_loads_first: bool = False,
        path: str = "load",
        max_increments: int | None = None,
        arc_iterations: int = DESIRED_ITERATIONS,
        arc_chords: float = 0.0,
        at_limit: str = "follow",
        predictor: bool = False,
        stabilise: float = 0.0,
        chords: int = 1,
        curved: bool = True,
        fibre_projection: bool = True,
        level_projection: bool = True,
        compression_free: float | None = None,
        follow_tools: bool = False,
        follow_tools_after_cut: bool = False,
        progress: bool | None = None,
        output: str | os.PathLike[str] | None = None,
        curved_with_contact: bool = False,
        ply_penalty_start: float | None = None,
        correction: str = "fitted",
    ):
        self.increments = check_integer(increments, "increments")
        self.tol = check_tolerance(tol)
        self.max_iterations = check_integer(max_iterations, "max_iterations")
        self.line_search = check_flag(line_search, "line_search")
        self.max_cuts = check_integer(max_cuts, "max_cuts", minimum=0)
        stall = stall_iterations
        self.stall_iterations = None if stall is None else check_integer(stall, "stall_iterations")
        self.first_turn = check_positive_or_none(first_turn, "first_turn", "rad")
        self.update_turn = check_positive_or_none(update_turn, "update_turn", "rad")
        start = ply_penalty_start
        self.ply_penalty_start = (
            None if start is None else check_tolerance(start, "ply_penalty_start")
        )
        self.augmentations = check_integer(augmentations, "augmentations", minimum=0)
        if tangent not in ("element", "finite_difference"):
            raise ValueError(f"tangent must be 'element' or 'finite_difference', got {tangent!r}")
        self.tangent = tangent
        if path not in PATHS:
            raise ValueError(f"path must be one of {PATHS}, got {path!r}")
        self.path = path
        self.max_increments = (
            20 * self.increments + 20
            if max_increments is None
            else check_integer(max_increments, "max_increments")
        )
        self.arc_iterations, self.arc_chords, self.at_limit = check_arc_options(
            path, max_increments, arc_iterations, arc_chords, at_limit
        )
        self.predictor = check_flag(predictor, "predictor")
        self.stabilise = check_stabilise(stabilise, path)
        self.chords = check_integer(chords, "chords", minimum=0)
        self.curved = check_flag(curved, "curved")
        self.curved_with_contact = check_flag(curved_with_contact, "curved_with_contact")
        if self.curved_with_contact and not self.curved:
            raise ValueError(
                "curved_with_contact=True given with curved=False: the curved steps it lets "
                "through with the plies' contact are off; expected curved=True with it"
            )
        if correction not in CORRECTIONS:
            raise ValueError(
                f"correction must be one of {CORRECTIONS} (the share of a curved step's "
                f"second-order correction taken), got {correction!r}"
            )
        self.correction = correction
        self.fibre_projection = check_flag(fibre_projection, "fibre_projection")
        self.level_projection = check_flag(level_projection, "level_projection")
        self.compression_free = (
            None
            if compression_free is None
            else check_non_negative(compression_free, "compression_free", "a residual ratio")
        )
        self.follow_tools = check_flag(follow_tools, "follow_tools")
        self.follow_tools_after_cut = check_flag(follow_tools_after_cut, "follow_tools_after_cut")
        self.seek_stable = check_flag(seek_stable, "seek_stable")
        self.step_loads_first = check_flag(step_loads_first, "step_loads_first")
        check_load_options(
            path,
            self.at_limit,
            {name: getattr(self, name) for name in LOAD_DEFAULTS},
        )
        self.progress = check_progress(progress)
        self.output = None if output is None else output_path(output, ".pvd", "output")

    @keeps_writes
    @one_blas_thread
    def solve(self, model: Model | CompiledModel) -> Result:
        """Solve every increment.

        Parameters
        ----------
        model : Model or CompiledModel

        Returns
        -------
        femcore.results.Result
            The reference state and one frame per increment (``time`` = load factor), with
            ``info``: iterations per increment (of the attempts that converged; those of
            the attempts that were cut are summed in ``iterations_cut``), cuts, the
            negative-eigenvalue count of each frame, branch switches, evaluation counts and
            the linear-solver statistics.

        Raises
        ------
        ValueError
            When ``model`` is not a Model, or the loads push the model along a rigid motion
            that no support holds at its starting shape (a net force along a translation: no
            equilibrium exists; loaded rotations: a mechanism there, whose equilibrium may lie a
            finite motion away, for DynamicRelaxation; the message names the motion), or a
            load with a user amplitude that is not proportional on the arc-length path, or
            a model held by frictionless contact leaves a rigid motion free (a slide along
            the tool; the message names it), or the solve would need more memory than is
            available (femcore.memory, about 30 kB per element cell at least).
        ConvergenceError
            When an increment cannot be completed: ``error.result`` holds the converged
            frames and the last good state, ``error.load_factor`` the load factor reached.
        solvers.interrupts.Interrupted
            On SIGINT or SIGTERM inside ``solvers.interruptible()``: the increment in progress
            is finished, and the converged frames are in ``error.result``.
        femcore.writable.OutputError
            An ``output`` folder that cannot be written or is too full for the first frames
            (before the run), or a write that failed during it.
        """
        # Trial states of a wild update may overflow; every residual is checked for
        # finiteness and such an update is cut back, so numpy's warnings would only be noise.
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            return self._solve(model)

    def _solve(self, model: Model | CompiledModel) -> Result:
        compiled = compiled_model(model, "Static")
        check_held(compiled)
        check_outputs(compiled.mesh, self.output)
        # The tangent and its factorisation dwarf the model: refuse what cannot fit, up front.
        n_cells = sum(len(block.cell_ids) for block in compiled.blocks)
        check_model_memory(n_cells, STATIC_BYTES_PER_CELL, "a static solve")
        if self.path == "arc_length":
            check_proportional(compiled)
        run = StaticRun(self, compiled)
        if self.path != "load" and augment_contacts(compiled, run.state)[1] is not None:
            raise ValueError(
                "an augmented contact (augmented=True) needs path='load': the Uzawa passes "
                "solve an increment again at its load factor, which the arc-length path does "
                "not keep"
            )
        with run.progress:
            phases = 2 if self.step_loads_first else 1
            for phase in range(phases):
                run.phase = phase
                if self.path == "load":
                    load_path(self, run, phase)
                elif arc_length_path(run, phase):  # stopped at a limit point to jump
                    load_path(self, run, phase, jump=True)
            report_stabilisation(run)
            run.report_augmentation()
            return run.result(True)

    # ------------------------------------------------------------------ loads
    def loads(self, model: CompiledModel, load_factor: float):
        """Dead forces, moments and imposed displacements (n, 3) at a load factor lambda.

        Those with a named amplitude are ramped together, lambda times their full value, or with
        ``step_loads_first`` the "step" loads over [0, 1] (displacements 0) and the rest over
        [1, 2]; those with a user amplitude follow it, a(lambda) times their full value (with
        ``step_loads_first``: a(lambda - 1) over [1, 2], a(0) before). The solver takes
        differences of these, never lambda times the loads at 1 (docs/theory.md §6.5)."""
        force, moment = model.external_load(1.0, quasi_static=True, user=False)
        imposed = model.prescribed_displacement(1.0, quasi_static=True, user=False)
        if not self.step_loads_first:
            loads = load_factor * force, load_factor * moment, load_factor * imposed
            return self._with_user_amplitudes(model, loads, load_factor)
        # A "step" amplitude is 1 for any positive progress, a ramped one is proportional.
        step_force, step_moment = model.external_load(1e-300, quasi_static=True, user=False)
        first = min(load_factor, 1.0)
        then = max(load_factor - 1.0, 0.0)
        loads = (
            first * step_force + then * (force - step_force),
            first * step_moment + then * (moment - step_moment),
            then * imposed,
        )
        return self._with_user_amplitudes(model, loads, then)

    @staticmethod
    def _with_user_amplitudes(model: CompiledModel, loads: tuple, progress: float) -> tuple:
        """``loads`` (forces, moments, displacements) plus those with a user amplitude at
        ``progress`` (as they are where there are none: the same bits)."""
        if not model.user_amplitudes():
            return loads
        force, moment = model.external_load(progress, quasi_static=True, user=True)
        imposed = model.prescribed_displacement(progress, quasi_static=True, user=True)
        return loads[0] + force, loads[1] + moment, loads[2] + imposed
