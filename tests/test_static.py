"""solvers.Static: Newton-Raphson with the element and the coloured finite-difference tangents."""

import numpy as np
import pytest
import scipy.sparse as sp

from elements import Cable, FibrousShell, MindlinShell
from femcore import Mesh, Model
from materials import BendingLaw, ElasticShell, Fabric, ShearLaw
from solvers import ConvergenceError, DynamicRelaxation, Static
from tests.shell_helpers import fabric, on_cylinder, stiffness_and_mass
from validation import specimens
from validation.references.elastica import tip_loaded_cantilever
from validation.specimens import mindlin_strip


def fibrous_strip(tension=1200.0, cells=10):
    fabric = Fabric(
        thickness=6.0,
        areal_density=5.7e-9,
        tension=tension,
        shear=ShearLaw.linear(4.0),
        bending=BendingLaw.linear(7.5),
    )
    return specimens.fibrous_strip(100.0, 10.0, fabric, cells)


def test_coloured_tangent_equals_the_dense_jacobian():
    mesh, model = fibrous_strip(cells=6)
    compiled = model.compile()
    state = compiled.initial_state()
    rng = np.random.default_rng(3)
    state.positions = state.positions + rng.normal(scale=0.3, size=state.positions.shape)
    sparse = compiled.stiffness(state, "finite_difference").toarray()
    free = compiled.dofs.free.ravel()
    dense, _ = stiffness_and_mass(compiled, state, step=1e-6 * compiled.element_size)
    assert np.abs(sparse[np.ix_(free, free)] - dense).max() <= 1e-6 * np.abs(dense).max()


def _bent_model(element, seed=1):
    """A 4 x 3 patch wrapped on a cylinder, jittered, with jittered directors (no symmetry
    left for an error to hide behind); the left edge fixed."""
    mesh = Mesh.rectangle(4.0, 3.0, nx=4, ny=3)
    rng = np.random.default_rng(seed)
    positions, directors = on_cylinder(mesh.points, 5.0)
    model = Model(mesh)
    model.add(element)
    model.fix("left")
    compiled = model.compile()
    state = compiled.initial_state()
    state.positions = positions + rng.normal(scale=0.05, size=positions.shape)
    tilted = directors + rng.normal(scale=0.05, size=directors.shape)
    state.directors = tilted / np.linalg.norm(tilted, axis=1)[:, None]
    return compiled, state


@pytest.mark.parametrize(
    "element",
    [
        MindlinShell(ElasticShell(1e3, 0.3, 0.3, 1e-9)),
        FibrousShell(fabric(), bending_geometry="reference", clamped="left"),
        FibrousShell(fabric(), bending_geometry="reference"),
    ],
    ids=["mindlin", "fibrous-clamped-edge", "fibrous"],
)
def test_element_tangent_equals_the_finite_difference_tangent(element):
    # The elements' own stiffness (Mindlin: per-triangle central differences; fibrous:
    # per-cell tension/shear plus the differentiated bending of Eq. 37) against the coloured
    # finite differences of the assembled internal force, on the free unknowns. Both are
    # differences of step 1e-6: agreement to 1e-6 of the largest entry is their accuracy.
    compiled, state = _bent_model(element)
    free = compiled.dofs.free.ravel()
    reference = compiled.stiffness(state, "finite_difference").toarray()[np.ix_(free, free)]
    own = compiled.stiffness(state).toarray()
    own = own[np.ix_(free, free)]
    assert np.abs(own - reference).max() <= 1e-6 * np.abs(reference).max()


def test_fibrous_tangent_with_current_bending_coefficients_is_close():
    # With c_as from the current geometry (Bai, the default) the tangent holds them fixed, as
    # the force does; the neglected dc/dx terms are small on a strongly distorted patch.
    compiled, state = _bent_model(FibrousShell(fabric()))
    free = compiled.dofs.free.ravel()
    reference = compiled.stiffness(state, "finite_difference").toarray()[np.ix_(free, free)]
    own = compiled.stiffness(state).toarray()
    own = own[np.ix_(free, free)]
    assert np.abs(own - reference).max() <= 0.05 * np.abs(reference).max()


def test_cable_tangent_is_exact():
    mesh = Mesh.line((0.0, 0.0, 0.0), (10.0, 2.0, 1.0), 3)
    model = Model(mesh)
    model.add(Cable(axial_stiffness=100.0, mass_per_length=1e-6))
    compiled = model.compile()
    state = compiled.initial_state()
    state.positions = state.positions + np.random.default_rng(2).normal(scale=0.3, size=(4, 3))
    reference = compiled.stiffness(state, "finite_difference").toarray()
    own = compiled.stiffness(state).toarray()
    assert np.abs(own - reference).max() <= 1e-6 * np.abs(reference).max()


def test_newton_converges_quadratically_with_the_element_tangent():
    # Mindlin cantilever under a large tip load (P L^2 / EI = 3): with the element's own
    # tangent the end of each increment is quadratic; the finite-difference tangent (equal to
    # it to ~1e-10) follows the same iterations to the same state.
    length, width, thickness, young = 100.0, 5.0, 1.0, 1e5
    mesh, model = mindlin_strip(length, width, thickness, young, cells=10)
    load = 3.0 * young * width * thickness**3 / 12 / length**2
    tip = mesh.nodes("right")
    model.force(tip, (0.0, 0.0, -load / len(tip)))
    own = Static(increments=3).solve(model)
    for history in own.info["residual_history"]:
        # Quadratic: once below 1e-3, at most 3 more iterations reach the 1e-8 tolerance
        # (1e-3 -> 1e-6 -> 1e-12); a linearly converging iteration would need many more.
        first = next(i for i, ratio in enumerate(history) if ratio < 1e-3)
        assert len(history) - 1 - first <= 3, history
    numeric = Static(increments=3, tangent="finite_difference").solve(model)
    assert numeric.info["tangent"]["finite_difference"] == ["MindlinShellBlock"]
    assert own.positions == pytest.approx(numeric.positions, abs=1e-6 * length)


def _chain(shortening, lateral):
    """Two 5 mm bars in a line along x, the far end moved by ``shortening`` along x, a
    lateral force on the middle node; out-of-plane motion fixed."""
    mesh = Mesh.line((0.0, 0.0, 0.0), (10.0, 0.0, 0.0), 2)
    model = Model(mesh)
    model.add(Cable(axial_stiffness=1e3, mass_per_length=1e-6))
    model.fix("start")
    model.fix(np.arange(3), "uz")
    model.fix(2, "uy")
    model.displace("end", ux=shortening)
    if lateral:
        model.force(1, (0.0, lateral, 0.0))
    return model


def test_a_straight_compressed_chain_is_reported_unstable():
    # Pushed in without a lateral force, the straight chain is an equilibrium with N < 0: its
    # middle node has the lateral stiffness 2 N / l < 0 (no bending stiffness: Euler load 0).
    # Pulled out, it is stable.
    pushed = Static(increments=2, seek_stable=False).solve(_chain(-0.1, 0.0))
    assert pushed.info["indefinite_at"] == [0.5, 1.0]
    assert pushed.positions[1, 1] == 0.0
    pulled = Static(increments=2, seek_stable=False).solve(_chain(0.1, 0.0))
    assert pulled.info["indefinite_at"] == []


def test_two_compressed_chains_count_two_negative_eigenvalues():
    # Two straight chains pushed in, side by side in one model: two negative eigenvalues
    # (2 N / l < 0 at each middle node), so det K > 0; the pivots of the LDL^T still count
    # them (Sylvester's law of inertia), and the state is reported unstable.
    mesh = Mesh(
        np.array([[0, 0, 0], [5, 0, 0], [10, 0, 0], [0, 20, 0], [5, 20, 0], [10, 20, 0.0]]),
        lines=np.array([[0, 1], [1, 2], [3, 4], [4, 5]]),
    )
    model = Model(mesh)
    model.add(Cable(axial_stiffness=1e3, mass_per_length=1e-6))
    model.fix([0, 3])
    model.fix(np.arange(6), "uz")
    model.fix([2, 5], "uy")
    model.displace([2, 5], ux=-0.1)
    result = Static(increments=2, seek_stable=False).solve(model)
    assert result.info["negative_eigenvalues"] == [2, 2]
    assert result.info["indefinite_at"] == [0.5, 1.0]


def test_seek_stable_leaves_the_unstable_straight_chain_for_the_buckled_one():
    # The chain pushed in by 2 mm with the default seek_stable: the straight state is pushed
    # off along its buckling mode and the solver settles where the bars are unstressed, the
    # middle node sqrt(5^2 - 4^2) = 3 mm aside (N = 0 there: exact geometry).
    result = Static(increments=1).solve(_chain(-2.0, 0.0))
    assert result.info["branch_switches"]
    assert result.info["mode_searches"] >= 1  # the saddle's modes, at least
    assert result.info["indefinite_at"] == []
    assert abs(result.positions[1, 1]) == pytest.approx(3.0, rel=1e-8)


def test_a_compressed_chain_pushed_sideways_buckles_to_its_rest_length():
    # With a small lateral force the solver leaves the unstable straight state (its first
    # tangent is singular, N = 0) and finds the buckled one. Closed form: the middle node at
    # (4.95, y) with 2 N y / l = F, N = EA (l / 5 - 1), l = sqrt(4.95^2 + y^2): y = 0.70546,
    # nearly the inextensible sqrt(5^2 - 4.95^2) = 0.70534.
    from scipy.optimize import brentq

    def unbalance(y):
        length = np.hypot(4.95, y)
        return 2 * 1e3 * (length / 5.0 - 1.0) * y / length - 1e-3

    expected = brentq(unbalance, 0.6, 0.8, xtol=1e-14)
    result = Static(increments=1).solve(_chain(-0.1, 1e-3))
    assert result.positions[1, 1] == pytest.approx(expected, rel=1e-8)
    assert result.info["indefinite_at"] == []


def _von_mises_truss():
    """Von Mises truss (half-span 10, rise 1, EA 1e4) pushed down through a soft spring
    (1 N/mm: a 10 mm cable of EA 10) whose top end is lowered by 6 mm. Returns the model and
    the closed form: apex drop w, the truss's force F(w) and the spring-end travel
    t(w) = w + F(w) / k, which rises, falls (the unstable part, dt/dw < 0) and rises again."""
    half_span, rise, stiffness, spring = 10.0, 1.0, 1e4, 1.0
    points = np.array([[-half_span, 0, 0], [half_span, 0, 0], [0, 0, rise], [0, 0, rise + 10]])
    mesh = Mesh(points, lines=np.array([[0, 2], [1, 2], [2, 3]]))
    model = Model(mesh)
    model.add(Cable(axial_stiffness=stiffness, mass_per_length=1e-6), cells=[0, 1])
    model.add(Cable(axial_stiffness=10.0 * spring, mass_per_length=1e-6), cells=[2])
    model.fix([0, 1])
    model.fix([2, 3], ("ux", "uy"))
    model.displace(3, uz=-6.0)
    rest = np.hypot(half_span, rise)

    def truss_force(w):
        length = np.hypot(half_span, rise - w)
        return -2 * stiffness * (length / rest - 1) * (rise - w) / length

    def travel(w):
        return w + truss_force(w) / spring

    return model, rise, truss_force, travel


def test_load_control_jumps_the_snap_through_onto_the_far_stable_branch():
    # Past the limit point the path folds back; load steps cannot follow it. The energy line
    # search leads Newton to the stable branch beyond the snap (the jump a test machine
    # shows): there the apex balances the spring, F(w) = k (6 - w), solved from the closed
    # form, and the tangent is positive definite.
    from scipy.optimize import brentq

    model, rise, truss_force, travel = _von_mises_truss()
    far = brentq(lambda w: travel(w) - 6.0, 1.5 * rise, 6.0, xtol=1e-12)
    with pytest.warns(UserWarning, match="load control jumped between load factors") as said:
        result = Static(increments=12).solve(model)
    assert rise - result.positions[2, 2] == pytest.approx(far, rel=1e-6)
    assert result.info["negative_eigenvalues"][-1] == 0
    # The jump is reported, once: at the start of the one load step that crosses the first
    # limit of the closed form (0.7082, between 8/12 and 9/12), the last state on the near
    # branch. Every frame is stable (no negative eigenvalue): only the Newton iterates of
    # that step met the unstable stretch.
    first_limit, _ = truss_limit_loads(travel)
    assert result.info["negative_eigenvalues"] == [0] * 12
    assert len(result.info["jumps"]) == 1 and len(said) == 1
    assert result.info["jumps"][0] < first_limit <= result.info["jumps"][0] + 1.0 / 12
    # The arc length with at_limit="jump" follows the path to the limit point and then does
    # the same: it stops there (the first limit of the closed form) and lands on the far branch.
    jumped = Static(increments=12, path="arc_length", at_limit="jump").solve(model)
    assert rise - jumped.positions[2, 2] == pytest.approx(far, rel=1e-6)
    dense_w = np.linspace(0.0, 1.0, 100_001)
    first_limit = travel(dense_w).max() / 6.0
    assert jumped.info["jumps"] == [pytest.approx(first_limit, abs=0.02)]


def truss_limit_loads(travel) -> tuple[float, float]:
    """The load factors of the two limit points of ``_von_mises_truss``'s closed form t(w) = 6
    lambda: where t first turns down, and its least value on the far branch (w > 0.5)."""
    dense_w = np.linspace(0.0, 2.5, 250_001)
    dense_t = travel(dense_w)
    return dense_t[np.argmax(np.diff(dense_t) < 0)] / 6.0, dense_t[dense_w > 0.5].min() / 6.0


def assert_on_the_truss_closed_form(result, rise, travel) -> tuple[np.ndarray, float]:
    """The arc-length path of ``_von_mises_truss`` on its closed form: every frame on t(w) =
    6 lambda to 1e-6, ending at lambda = 1; the unstable frames (a negative eigenvalue) those
    with dt/dw < 0; the two limit loads those of the closed form to the step's resolution
    (lambda is flat at a limit, 1e-3). Returns the frames' load factors and the first limit."""
    w = np.array([rise - frame.positions[2, 2] for frame in result.frames])
    lam = np.array([frame.load_factor for frame in result.frames])
    assert lam[-1] == 1.0
    assert np.abs(travel(w) - 6.0 * lam).max() <= 1e-6
    dense_w = np.linspace(0.0, 2.5, 250_001)
    dense_t = travel(dense_w)
    slope = np.gradient(dense_t, dense_w)
    expected_unstable = np.interp(w[1:], dense_w, slope) < 0.0
    unstable = np.array(result.info["negative_eigenvalues"]) > 0
    assert np.array_equal(unstable, expected_unstable)
    first_limit, second_limit = truss_limit_loads(travel)
    limits = result.info["limit_points"]
    assert len(limits) == 2
    assert limits[0] == pytest.approx(first_limit, abs=1e-3 * 6)
    assert limits[1] == pytest.approx(second_limit, abs=1e-3 * 6)
    return lam, first_limit


def test_arc_length_follows_the_snap_through_along_its_closed_form_path():
    # Crisfield's arc length follows the whole path: up to the first limit point, down the
    # unstable part (the spring end travels back, lambda falls below zero) and up the far
    # branch to the full 6 mm. Every frame lies on the closed form t(w) = 6 lambda, the
    # unstable frames are those with dt/dw < 0, and the two limit loads are those of the
    # closed form (to the step resolution: lambda is flat at a limit, 1e-3).
    model, rise, truss_force, travel = _von_mises_truss()
    result = Static(increments=12, path="arc_length").solve(model)
    lam, first_limit = assert_on_the_truss_closed_form(result, rise, travel)
    rising = lam[: np.argmax(np.diff(lam) < 0) + 1]
    assert lam.min() < 0.0 and rising.max() <= first_limit + 1e-9


def test_an_empty_phase_of_the_arc_length_path_is_passed_over():
    # step_loads_first with no "step" load (no gravity): the first phase applies nothing and
    # gives one frame at load factor 1; the displacement then follows over 1-2 and ends on
    # the same equilibrium as the single-phase run.
    model, rise, truss_force, travel = _von_mises_truss()
    single = Static(increments=12, path="arc_length", at_limit="jump").solve(model)
    phased = Static(increments=12, path="arc_length", at_limit="jump", step_loads_first=True).solve(
        model
    )
    assert phased.frames[1].load_factor == 1.0
    assert phased.frames[-1].load_factor == 2.0
    assert phased.positions == pytest.approx(single.positions, abs=1e-9)


def test_a_failed_increment_keeps_the_last_good_state_and_says_where():
    # Plain Newton (no line search) with two iterations per increment cannot pass the limit
    # point: the solver stops there with the load factor it reached and that frame kept.
    model, rise, truss_force, travel = _von_mises_truss()
    with pytest.raises(ConvergenceError, match="load factor") as failure:
        Static(increments=12, line_search=False, max_iterations=3, max_cuts=2).solve(model)
    reached = failure.value.load_factor
    assert 0.0 < reached < 1.0
    last = failure.value.result.frames[-1]
    assert last.load_factor == reached
    w = rise - last.positions[2, 2]
    assert travel(w) == pytest.approx(6.0 * reached, abs=1e-6)


@pytest.mark.slow
def test_static_and_dynamic_relaxation_agree_on_the_fibrous_cantilever():
    mesh, model = fibrous_strip(tension=120.0)
    static = Static(increments=2).solve(model)
    relaxed = DynamicRelaxation(tol=1e-6, max_iterations=100_000).solve(model)
    tip = mesh.nodes("right")
    assert static.positions[tip] == pytest.approx(relaxed.positions[tip], rel=1e-3, abs=1e-2)
    assert static.info["iterations_per_increment"][-1] < 30


def _sagging_cable():
    """30 links over 100 mm, one end fixed, the other moved 20 mm in, under gravity."""
    mesh = Mesh.line((0.0, 0.0, 0.0), (100.0, 0.0, 0.0), 30)
    model = Model(mesh)
    model.add(Cable(axial_stiffness=5.0e3, mass_per_length=1.0e-6))
    model.fix("start")
    model.displace("end", ux=-20.0, uy=0.0, uz=0.0)
    model.gravity((0.0, 0.0, -9810.0))
    return mesh, model


@pytest.mark.slow
def test_static_and_dynamic_relaxation_agree_on_a_sagging_cable():
    # The cable is elastic under conservative loads: one equilibrium, whatever the path
    # (test_step_loads_first_hangs_the_structure_before_moving_it), so the relaxation takes the
    # pull in 2 increments (10-14 thousand iterations each, whatever their size): they end
    # 6.4e-7 mm from Static's positions, 8 increments 1.8e-6 mm (measured; 1e-3 asked).
    mesh, model = _sagging_cable()
    static = Static(increments=8).solve(model)
    relaxed = DynamicRelaxation(increments=2, tol=1e-7).solve(model)
    assert static.positions == pytest.approx(relaxed.positions, rel=1e-3, abs=1e-3)


def test_newton_squares_the_residual_near_the_solution_of_the_rollup():
    # The strip rolled into a quarter circle in four increments (the test below): with the
    # element tangent consistent with the director update (docs/theory.md §6.5), once the
    # residual ratio r is below 1e-2 each iteration gives r_next <= 100 r^2 (quadratic; a
    # linearly converging iteration keeps r_next / r roughly constant instead). Measured with
    # straight steps: 8 iterations per increment, final orders log(r_next) / log(r) of
    # 2.0-2.15; the first three or four iterations of an increment are the pre-asymptotic
    # phase of a quarter-turn rotation step (the straight update stretches the strip); with
    # the curved steps 4-5-5-4.
    length, width, thickness, young = 100.0, 10.0, 1.0, 1e5
    mesh, model = mindlin_strip(length, width, thickness, young, cells=20)
    bending = young * width * thickness**3 / 12
    tip = mesh.nodes("right")
    model.moment(tip, (0.0, -0.5 * np.pi * bending / length / len(tip), 0.0), amplitude="linear")
    result = Static(increments=4).solve(model)
    for history in result.info["residual_history"]:
        first = next(i for i, ratio in enumerate(history) if ratio < 1e-2)
        for ratio, following in zip(history[first:-1], history[first + 1 :]):
            assert following <= 100.0 * ratio**2 or following <= 1e-8, history
    assert max(result.info["iterations_per_increment"]) <= 10


def test_cantilever_rolls_up_into_a_circle_under_an_end_moment():
    # Closed form: an end moment M bends an inextensible strip into an arc of radius EI / M.
    length, width, thickness, young = 100.0, 10.0, 1.0, 1e5
    mesh, model = mindlin_strip(length, width, thickness, young, cells=20)
    bending = young * width * thickness**3 / 12
    moment = 0.25 * 2 * np.pi * bending / length  # a quarter circle
    tip = mesh.nodes("right")
    model.moment(tip, (0.0, -moment / len(tip), 0.0), amplitude="linear")
    result = Static(increments=4).solve(model)
    radius = bending / moment
    x, _, z = result.positions[tip].mean(axis=0)
    assert x == pytest.approx(radius, rel=0.01)
    assert z == pytest.approx(radius, rel=0.01)


def test_an_unsupported_structure_is_refused_before_iterating():
    # A cable pulled at one end with nothing holding it: it would only translate (statics),
    # and Static says which rigid motion is free (tests/test_rigid_motions.py).
    mesh = Mesh.line((0.0, 0.0, 0.0), (10.0, 0.0, 0.0), 2)
    model = Model(mesh)
    model.add(Cable(axial_stiffness=1.0, mass_per_length=1e-6))
    model.force("end", (1.0, 0.0, 0.0))
    with pytest.raises(ValueError, match="translation along x"):
        Static(increments=1, max_cuts=1).solve(model)


def test_bad_options_are_refused():
    with pytest.raises(ValueError, match="tol"):
        Static(tol=2.0)
    with pytest.raises(ValueError, match="increments"):
        Static(increments=0)


def test_dynamic_relaxation_continues_from_a_static_state():
    # The fallback of the validation cases past a limit point: Static to half the load, then
    # DynamicRelaxation from that equilibrium to the full load; it ends where a Static run to
    # the full load ends.
    mesh, model = _sagging_cable()
    half = Static(increments=4).solve(model)
    middle = half.frames[2]
    assert middle.load_factor == pytest.approx(0.5)
    full = Static(increments=8).solve(model)
    # 2 increments from the half load (each costs 10-14 thousand iterations whatever its
    # size); 4 ended within 1.8e-6 mm of the full Static run, 2 within 1.2e-6 (measured).
    relaxed = DynamicRelaxation(increments=2, tol=1e-7).solve(
        model, start=(middle.positions, middle.directors, middle.load_factor)
    )
    assert relaxed.frames[1].load_factor == pytest.approx(0.5)
    assert relaxed.positions == pytest.approx(full.positions, rel=1e-3, abs=1e-3)
    with pytest.raises(ValueError, match="start load factor"):
        DynamicRelaxation().solve(model, start=(middle.positions, middle.directors, 1.0))


def test_step_loads_first_hangs_the_structure_before_moving_it():
    # Gravity ("step") alone over load factors 0-1 with the end held, then the end moved over
    # 1-2. An elastic cable has one equilibrium per load, so both paths end in the same state;
    # at load factor 1 the end has not moved yet and the cable hangs under its full weight.
    mesh, model = _sagging_cable()
    together = Static(increments=8).solve(model)
    sequenced = Static(increments=4, step_loads_first=True).solve(model)
    assert len(sequenced.frames) == 9
    hanging = sequenced.frames[4]
    assert hanging.load_factor == pytest.approx(1.0)
    end = mesh.nodes("end")
    assert hanging.positions[end] == pytest.approx(mesh.points[end], abs=1e-12)
    weight = 1.0e-6 * 100.0 * 9810.0
    assert hanging.reactions[:, 2].sum() == pytest.approx(weight, rel=1e-6)
    assert sequenced.positions == pytest.approx(together.positions, abs=1e-6)


def test_static_and_dynamic_relaxation_agree_on_the_mindlin_cantilever():
    # Tip load P L^2 / EI = 1 on a 100 x 5 x 4 mm strip (L/h = 25, so that dynamic relaxation
    # needs only ~9000 iterations): the tip moves 30 mm down and 5.6 mm in; both solvers
    # agree to 1e-4 of the largest displacement (measured 1.3e-6).
    length, width, thickness, young = 100.0, 5.0, 4.0, 1e5
    mesh, model = mindlin_strip(length, width, thickness, young, cells=10)
    load = young * width * thickness**3 / 12 / length**2
    tip = mesh.nodes("right")
    model.force(tip, (0.0, 0.0, -load / len(tip)))
    static = Static(increments=3).solve(model)
    relaxed = DynamicRelaxation(increments=3, tol=1e-6).solve(model)
    scale = np.abs(static.displacements).max()
    assert scale > 25.0
    assert np.abs(relaxed.positions - static.positions).max() <= 1e-4 * scale


def test_the_lowest_modes_do_not_depend_on_what_ran_before():
    # ARPACK starts from a random vector unless given one; the stability search must give the
    # same modes, bit for bit, however many eigen-solves the process did before.
    from solvers.stability import lowest_modes

    n = 400
    rng = np.random.default_rng(1)
    a = sp.random(n, n, density=0.02, random_state=2)
    k_ff = (a + a.T + sp.diags(np.linspace(-1.0, 5.0, n))).tocsc()
    first = lowest_modes(k_ff)
    lowest_modes(k_ff + sp.diags(rng.uniform(size=n)))  # something else in between
    again = lowest_modes(k_ff)
    assert np.array_equal(first[0], again[0]) and np.array_equal(first[1], again[1])


def _tip_loaded_strip():
    """A Mindlin strip 200 x 20 x 1 mm of 20 x 2 cells under a tip load P L^2 / EI = 3."""
    mesh, model = mindlin_strip(200.0, 20.0, 1.0, 70e3, cells=20, across=2)
    tip = mesh.nodes("right")
    bending = 70e3 * 20.0 / 12.0
    model.force(tip, (0.0, 0.0, -3.0 * bending / 200.0**2 / len(tip)), amplitude="linear")
    return model, tip


def test_chord_corrections_take_the_place_of_tangents_and_reach_the_same_equilibrium():
    # The first steps of each increment stretch the turning strip; chord steps with the
    # kept factors, kept while the potential energy falls, undo that where a tangent would.
    # Measured: 9-9-9-8-8 tangents without, 5-7-5-5-5 with 4 corrections per step.
    # Both with straight steps (curved=False): the curved steps take the stretch back too.
    model, tip = _tip_loaded_strip()
    plain = Static(increments=5, chords=0, curved=False, progress=False).solve(model)
    corrected = Static(increments=5, chords=4, curved=False, progress=False).solve(model)
    assert plain.info["chord_corrections"] == 0
    assert corrected.info["chord_corrections"] > 0
    assert sum(corrected.info["iterations_per_increment"]) <= 0.7 * sum(
        plain.info["iterations_per_increment"]
    )
    assert max(corrected.info["iterations_per_increment"]) <= 7
    drop = plain.positions[tip].mean(axis=0)
    assert np.abs(corrected.positions[tip].mean(axis=0) - drop).max() <= 1e-6 * np.abs(drop).max()


def _elastica():
    """The mindlin-elastica case (validation/cases/mindlin_elastica.py): a 100 x 5 x 1 mm strip
    of 20 cells, P L^2 / EI = 3 in 5 increments; (model, tip nodes, elastica tip drop)."""
    length, bending = 100.0, 1e5 * 5.0 / 12.0
    mesh, model = mindlin_strip(length, 5.0, 1.0, 1e5, cells=20)
    tip = mesh.nodes("right")
    model.force(tip, (0.0, 0.0, -3.0 * bending / length**2 / len(tip)))
    drop = tip_loaded_cantilever(length, 3.0 * bending / length**2, bending)["tip_deflection"]
    return model, tip, drop


def _rollup():
    """The mindlin-rollup case (validation/cases/mindlin_rollup.py): a 100 x 10 x 1 mm strip of
    20 cells rolled into a quarter circle in 4 increments; (model, tip nodes, radius EI / M)."""
    length, bending = 100.0, 1e5 * 10.0 / 12.0
    mesh, model = mindlin_strip(length, 10.0, 1.0, 1e5, cells=20)
    tip = mesh.nodes("right")
    moment = 0.5 * np.pi * bending / length
    model.moment(tip, (0.0, -moment / len(tip), 0.0), amplitude="linear")
    return model, tip, bending / moment


def test_the_elastica_converges_in_at_most_six_iterations_per_increment():
    # Straight steps took 8 per increment (the first two spent taking back the stretch of the
    # turned chord); curved steps and one chord correction: 4-6-5-4-4. The equilibrium is the
    # same: the tip drop within the case's 1 % of the elastica (Bisshopp & Drucker 1945, the
    # boundary-value solve; measured 0.04 %) and within 1e-6 of the straight steps' drop (both
    # converge to the residual ratio 1e-8).
    model, tip, drop = _elastica()
    result = Static(increments=5, progress=False).solve(model)
    assert max(result.info["iterations_per_increment"]) <= 6
    assert result.info["curved_steps"] > 0
    assert -result.displacements[tip, 2].mean() == pytest.approx(drop, rel=1e-2)
    straight = Static(increments=5, curved=False, chords=0, progress=False).solve(model)
    assert result.positions == pytest.approx(straight.positions, abs=1e-6 * drop)


def test_the_rollup_converges_in_at_most_six_iterations_per_increment():
    # Straight steps: 8 per increment; curved steps and one chord correction: 4-5-5-4. The tip
    # on the circle of radius EI / M to the case's 1 % (measured 0.09 %).
    model, tip, radius = _rollup()
    result = Static(increments=4, progress=False).solve(model)
    assert max(result.info["iterations_per_increment"]) <= 6
    x, _, z = result.positions[tip].mean(axis=0)
    assert x == pytest.approx(radius, rel=1e-2)
    assert z == pytest.approx(radius, rel=1e-2)


def test_the_tip_loaded_cantilever_converges_in_at_most_six_iterations_per_increment():
    # The strip of benchmarks/static_solver.py (200 x 20 x 1 mm, P L^2 / EI = 3, 5 increments)
    # on 20 x 2 cells. Measured: straight steps 9-9-9-8-8 (as on its 80 x 16 cells); curved
    # steps alone 7-7-7-5-5, one chord correction alone 6-8-10-8-7, both (the default)
    # 5-6-6-5-5. The tip drop within 1 % of the elastica (0.603 L).
    model, tip = _tip_loaded_strip()
    result = Static(increments=5, progress=False).solve(model)
    assert max(result.info["iterations_per_increment"]) <= 6
    bending = 70e3 * 20.0 / 12.0
    drop = tip_loaded_cantilever(200.0, 3.0 * bending / 200.0**2, bending)["tip_deflection"]
    assert -result.displacements[tip, 2].mean() == pytest.approx(drop, rel=1e-2)


def test_an_increment_of_plies_that_fails_is_cut_after_one_attempt():
    # The plies' contact has no contact set to freeze: the frozen attempt of an increment is
    # already the unilateral law's, and a second attempt would repeat it iteration for
    # iteration. A two-ply deck bent by end moments in one increment of two Newton iterations
    # (and no cut) cannot converge: it stops after those two iterations' two tangents, not
    # four (``iterations_cut`` counts an attempt's residual ratios after its first, 1 here).
    from elements.plies import PlyStack

    mid = Mesh.rectangle(100.0, 5.0, nx=4, ny=1)
    deck = Fabric(
        thickness=1.0,
        areal_density=1e-9,
        tension=1e4,
        shear=ShearLaw.linear(1.0),
        bending=BendingLaw.linear(1.0),
    )
    stack = PlyStack(mid, deck, 2)
    model = stack.model()
    model.fix(stack.nodes("left"))
    model.moment(stack.nodes("right"), (0.0, -0.05, 0.0), amplitude="linear")
    with pytest.raises(ConvergenceError, match="load factor") as failure:
        Static(increments=1, seek_stable=False, max_iterations=2, max_cuts=0, progress=False).solve(
            model
        )
    info = failure.value.result.info
    assert info["contact_set_fallbacks"] == 0
    assert info["evaluations"]["tangent"] == 2
    assert info["iterations_cut"] == 1


def test_arc_iterations_aims_the_arc_length_steps_and_keeps_the_closed_form_path():
    # Crisfield's rule scales the next step length by sqrt(arc_iterations / iterations taken),
    # within [1/2, 2] and never above the longest step (docs/theory.md §6.6 "Step length"):
    # aimed at 10 iterations the steps grow where those taken are fewer, and some step is
    # longer than the default's aim of 5 would allow; every frame still lies on the truss'
    # closed form t(w) = 6 lambda.
    model, rise, truss_force, travel = _von_mises_truss()
    default = Static(increments=12, path="arc_length").solve(model)
    aimed = Static(increments=12, path="arc_length", arc_iterations=10).solve(model)
    w = np.array([rise - frame.positions[2, 2] for frame in aimed.frames])
    lam = np.array([frame.load_factor for frame in aimed.frames])
    assert lam[-1] == 1.0
    assert np.abs(travel(w) - 6.0 * lam).max() <= 1e-6
    # The motion lengths of the increments (translations only: cables have no directors).
    lengths = [
        float(np.linalg.norm(b.positions - a.positions))
        for a, b in zip(aimed.frames[:-1], aimed.frames[1:])
    ]
    # The iterations Crisfield's rule counts: down to the settled ratio (solvers.arc_step).
    from solvers.arc_step import iterations_spent

    info = aimed.info
    counts = [
        iterations_spent(history, count, 0, 1e-8)
        for history, count in zip(info["residual_history"], info["iterations_per_increment"])
    ]
    ratios = [after / before for before, after in zip(lengths[:-1], lengths[1:])]
    bound = [float(np.clip(np.sqrt(10 / max(n, 1)), 0.5, 2.0)) for n in counts[:-1]]
    assert all(r <= b * (1 + 1e-9) for r, b in zip(ratios, bound))
    default_aim = [float(np.clip(np.sqrt(5 / max(n, 1)), 0.5, 2.0)) for n in counts[:-1]]
    assert any(r > b * (1 + 1e-6) for r, b in zip(ratios, default_aim))
    # No more increments than at the default aim (47 each when this was written: the first
    # step's length caps most of the truss's steps either way since Crisfield's rule counts
    # the iterations down to the settled ratio, solvers.arc_step; 51 at the default before).
    assert len(aimed.frames) <= len(default.frames)


@pytest.mark.parametrize("bad", [0, 2.5, True, "5"])
def test_arc_iterations_must_be_a_whole_number_of_at_least_one(bad):
    with pytest.raises(ValueError, match="arc_iterations must be an integer >= 1"):
        Static(path="arc_length", arc_iterations=bad)
