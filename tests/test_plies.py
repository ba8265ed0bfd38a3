"""The stack as N sliding plies (elements/plies.py, elements/ply_contact.py, docs/theory.md
"The stack as plies"): the ply's fabric, the stack builder and its node maps, the material
lines, and the closed forms the plies must meet."""

import numpy as np
import pytest

from materials import BendingLaw, Fabric, ShearLaw, TensionLaw


# ---------------------------------------------------------------------- Law.scaled, plies
@pytest.mark.parametrize(
    "law",
    [
        TensionLaw.linear(1200.0),
        TensionLaw.linear(1200.0, tension_only=True),
        TensionLaw.table([0.0, 0.01, 0.02], [0.0, 5.0, 30.0]),
        ShearLaw.polynomial(0.1, 0.5, 2.0),
        BendingLaw.bilinear(7.5, 0.5, knee=1e-3),
    ],
    ids=repr,
)
def test_a_scaled_law_is_factor_times_the_law(law):
    x = np.linspace(-0.05, 0.05, 41)
    scaled = law.scaled(0.25)
    assert scaled.family == law.family and scaled.compression == law.compression
    for what in ("value", "slope", "energy"):
        assert np.allclose(getattr(scaled, what)(x), 0.25 * getattr(law, what)(x), rtol=1e-14)
    assert scaled.max_slope() == pytest.approx(0.25 * law.max_slope())


@pytest.mark.parametrize("factor", [0.0, -1.0, np.inf, "2", True, None])
def test_a_law_refuses_a_bad_scale(factor):
    with pytest.raises(ValueError, match="factor"):
        TensionLaw.linear(10.0).scaled(factor)


def test_the_ply_fabric_is_the_stack_shared_equally():
    stack = Fabric(
        thickness=6.0,
        areal_density=5.7e-9,
        tension=1200.0,
        shear=ShearLaw.linear(4.0),
        bending=BendingLaw.bilinear(7.5, 0.5, knee=1e-3),
        bending_weft=6.0,
    )
    ply = stack.plies(4)
    assert ply.thickness == 1.5 and ply.areal_density == pytest.approx(5.7e-9 / 4)
    chi = np.linspace(-0.01, 0.01, 21)
    for name in ("tension", "tension_weft", "shear", "bending", "bending_weft"):
        assert np.allclose(getattr(ply, name).value(chi), getattr(stack, name).value(chi) / 4)
    assert ply.tension_weft is ply.tension  # the weft followed the warp: it still does
    assert stack.plies(1) == stack


@pytest.mark.parametrize("count", [0, -2, 2.0, 2.5, "4", True, None])
def test_plies_refuses_a_count_that_is_not_a_positive_integer(count):
    stack = Fabric(thickness=1.0, areal_density=1e-9, tension=10.0, shear=1.0, bending=1.0)
    with pytest.raises(ValueError, match="count must be an integer >= 1"):
        stack.plies(count)


# ---------------------------------------------------------------------- the stack builder
from elements.plies import PlyStack  # noqa: E402
from femcore import Mesh  # noqa: E402
from solvers import Static  # noqa: E402
from validation.references.elastica import heavy_cantilever  # noqa: E402

DECK = Fabric(thickness=1.0, areal_density=1e-9, tension=1e4, shear=1.0, bending=1.0)


def test_the_stack_replicates_the_mid_surface_once_per_ply():
    mid = Mesh.rectangle(100.0, 5.0, nx=4, ny=1)
    stack = PlyStack(mid, DECK, 4)
    assert stack.mesh.n_nodes == 4 * mid.n_nodes and len(stack.mesh.triangles) == 4 * 8
    # z_k = -h/2 + (k - 1/2) h/N along the (flat, +z) normal
    assert np.allclose(stack.offsets, [-0.375, -0.125, 0.125, 0.375])
    for k in range(4):
        assert np.allclose(
            stack.mesh.points[stack.ply_nodes[k]], mid.points + [0, 0, stack.offsets[k]]
        )
    left = stack.nodes("left")
    assert np.array_equal(np.sort(left), np.sort(stack.mesh.nodes("left")))
    assert np.array_equal(stack.nodes([0]), stack.ply_nodes[:, 0])
    model = stack.model()
    assert len(model.blocks) == 4 and len(model.interactions) == 3


@pytest.mark.parametrize(
    "args, message",
    [
        ((None, DECK, 2), "triangle Mesh"),
        (("mesh", "fabric", 2), "Fabric"),
        (("mesh", DECK, 0), "count must be an integer"),
        (("mesh", DECK, 2.0), "count must be an integer"),
    ],
)
def test_the_stack_refuses_bad_input(args, message):
    mid = Mesh.rectangle(10.0, 5.0, nx=2, ny=1)
    args = tuple(mid if a == "mesh" else a for a in args)
    if args[1] == "fabric":
        args = (args[0], "fabric", args[2])
    with pytest.raises(ValueError, match=message):
        PlyStack(*args)
    with pytest.raises(ValueError, match="penalty"):
        PlyStack(mid, DECK, 2, penalty=-1.0)
    with pytest.raises(ValueError, match="node ids"):
        PlyStack(mid, DECK, 2).nodes([99])


@pytest.mark.parametrize("count", [2, 4, 8])
def test_material_lines_of_the_deck_of_cards_tilt_by_atan_theta(count):
    """Plies placed where inextensible frictionless plies bent about one centre sit (the
    deck of cards, docs/theory.md §1.7: ply k on the arc of radius R - z_k from the centre
    above the clamp, its node at arc length x at the angle x / (R - z_k); directors along
    the radius): the material line tilts from the arc's normal by atan(theta) and the
    thickness along it is h sqrt(1 + theta^2), theta = x / R. The closed form holds to
    first order in h / R = 0.016: measured 1.8e-3 deg and 7e-5 at every N (the ply points
    lie on a line to that order whatever N), held to 5e-3 deg and 2e-4."""
    mid = Mesh.rectangle(100.0, 5.0, nx=20, ny=1)
    stack = PlyStack(mid, DECK, count)
    radius = 100.0 / (np.pi / 2)
    positions = np.empty_like(stack.mesh.points)
    directors = np.empty_like(positions)
    x, y = mid.points[:, 0], mid.points[:, 1]
    for k, z in enumerate(stack.offsets):
        r = radius - z
        phi = x / r
        positions[stack.ply_nodes[k]] = np.column_stack(
            [r * np.sin(phi), y, radius - r * np.cos(phi)]
        )
        directors[stack.ply_nodes[k]] = np.column_stack([-np.sin(phi), 0 * phi, np.cos(phi)])
    lines = stack.material_lines(positions, directors)
    theta = x / radius
    normal = np.column_stack([-np.sin(theta), 0 * theta, np.cos(theta)])
    tilt = np.arccos(np.clip(np.sum(lines.direction * normal, axis=1), -1.0, 1.0))
    assert np.degrees(np.abs(tilt - np.arctan(theta))).max() <= 5e-3
    assert np.abs(lines.thickness / np.hypot(1.0, theta) - 1.0).max() <= 2e-4
    # The plies touch along the normal; along the tilted line, with each ply's own normal,
    # the gap is second order in h / R: measured 3.1e-3 mm at the free end (N = 4).
    assert np.abs(lines.gap).max() <= 5e-3
    # the mid-point is on the mid-surface arc (to second order in h / R: 3.6e-3 mm at the
    # free end, theta = 90 deg), and one ply's line is its director
    assert (
        np.abs(np.hypot(lines.midpoint[:, 0], lines.midpoint[:, 2] - radius) - radius).max() <= 1e-2
    )
    single = PlyStack(mid, DECK, 1)
    lone = single.material_lines(positions[stack.ply_nodes[0]], directors[stack.ply_nodes[0]])
    assert np.allclose(lone.direction, directors[stack.ply_nodes[0]])
    assert np.allclose(lone.thickness, 1.0)


# ---------------------------------------------------------------------- closed forms
SAG = Fabric(thickness=1.0, areal_density=1e-9, tension=1e4, shear=1.0, bending=100.0)


@pytest.mark.parametrize("count", [2, 4])
def test_frictionless_plies_each_sag_as_the_stack(count):
    """N frictionless plies clamped at x = 0 sag under gravity: each has 1/N of the bending
    and 1/N of the mass, so each follows the stack's heavy elastica (q L^3 / B = 0.098:
    the tip drops 1.23 mm, 1.2 % of L, q L^4 / (8 B) to 0.01 %). Reference:
    validation.references.elastica.heavy_cantilever (a boundary-value solve). Measured at
    10 x 1 cells with Static (Newton, the contact's own tangent): every ply's tip within
    1e-4 of the reference (the Mindlin ply alone, N = 1, 2e-5); tolerance 5e-4. The plies
    neither interpenetrate nor separate: |gap| along every material line below 1e-4 of
    h / N (measured 9e-5); tolerance 1e-3 of h / N."""
    mid = Mesh.rectangle(100.0, 5.0, nx=10, ny=1)
    stack = PlyStack(mid, SAG, count)
    model = stack.model()
    model.fix(stack.nodes("left"))
    model.gravity((0.0, 0.0, -9810.0))
    result = Static(increments=1, progress=False).solve(model)
    assert result.converged
    reference = heavy_cantilever(100.0, 1e-9 * 9810.0, 100.0)
    tips = result.positions[stack.ply_nodes[:, mid.nodes("right")], 2].mean(axis=1)
    deflection = stack.offsets - tips
    assert np.abs(deflection / reference["tip_deflection"] - 1.0).max() <= 5e-4
    lines = stack.material_lines(result.positions, result.directors)
    assert np.abs(lines.gap).max() <= 1e-3 * stack.ply_thickness


# ---------------------------------------------------------------------- the contact's penalty
def test_the_ramped_penalty_is_c2_and_nothing_apart():
    """elements.ply_contact.penalty_law: W, W' and W'' continuous at g = -delta and g = 0
    (the ramp's ends), W' = k (g + delta / 2) past the ramp, nothing for g >= 0, and W' and
    W'' the derivatives of W and W' (central differences)."""
    from elements.ply_contact import penalty_law

    k, delta = 3.0, 0.01
    for g0 in (-delta, 0.0):
        sides = penalty_law(np.array([g0 - 1e-12, g0 + 1e-12]), np.full(2, k), delta)
        for values in sides:
            assert abs(values[0] - values[1]) <= 1e-9 * k
    g = np.linspace(-3 * delta, 2 * delta, 101)
    energy, force, stiffness = penalty_law(g, np.full(g.size, k), delta)
    assert np.all(energy[g >= 0] == 0) and np.all(force[g >= 0] == 0)
    deep = g <= -delta
    assert np.allclose(force[deep], k * (g[deep] + delta / 2), rtol=1e-14)
    h = 1e-7
    up, down = (penalty_law(g + s, np.full(g.size, k), delta) for s in (h, -h))
    assert np.allclose((up[0] - down[0]) / (2 * h), force, atol=1e-7 * k * delta)
    # the third derivative jumps by k / delta at the ramp's ends (C2, not C3): a difference
    # across them is off by up to k h / (2 delta)
    assert np.allclose((up[1] - down[1]) / (2 * h), stiffness, atol=k * h / delta)


def test_the_stick_spring_is_the_normal_laws_stiffness_and_its_slope_the_third_derivative():
    """elements.ply_friction.stick_spring: k_t = W'' of penalty_law (k past the ramp, k |g| /
    delta on it, 0 for g >= 0; and k at any g <= 0 without smoothing), and its slope the
    central difference of W'' (exact for W'' linear in g on each side, off the ramp's ends and
    g = 0 where the third derivative jumps: tolerance 1e-6 of k / delta, the round-off of
    h = 1e-7 delta), so the elastic slip at the friction limit on the ramp, mu N / k_t, is
    mu |g| / 2."""
    from elements.ply_contact import penalty_law
    from elements.ply_friction import stick_spring

    k, delta, mu = 3.0, 0.01, 0.2
    g = np.linspace(-3 * delta, 2 * delta, 101)
    g = g[(np.abs(g) > 1e-6) & (np.abs(g + delta) > 1e-6)]
    stiffness = np.full(g.size, k)
    spring, slope = stick_spring(g, stiffness, delta)
    _, force, curvature = penalty_law(g, stiffness, delta)
    assert np.array_equal(spring, curvature)
    h = 1e-7 * delta
    up, down = (penalty_law(g + s, stiffness, delta)[2] for s in (h, -h))
    assert np.allclose(slope, (up - down) / (2 * h), rtol=0, atol=1e-6 * k / delta)
    ramp = (g < 0) & (g > -delta)
    assert np.allclose(mu * -force[ramp] / spring[ramp], mu * np.abs(g[ramp]) / 2, rtol=1e-12)
    plain = stick_spring(g, stiffness, 0.0)
    assert np.array_equal(plain[0], np.where(g <= 0, k, 0.0)) and not plain[1].any()


@pytest.mark.parametrize(
    "changes, message",
    [
        ({"rule": "edges"}, "rule must be one of"),
        ({"smoothing": -1.0}, "smoothing must be"),
        ({"smoothing": True}, "smoothing must be"),
    ],
)
def test_the_ply_contact_refuses_a_bad_rule_or_smoothing(changes, message):
    from elements.ply_contact import PlyContact

    with pytest.raises(ValueError, match=message):
        PlyContact("upper", "lower", **changes)
    with pytest.raises(ValueError, match=message):
        PlyStack(Mesh.rectangle(10.0, 5.0, nx=2, ny=1), DECK, 2, **changes)


# ---------------------------------------------------------------------- the deck, the heavy stack
def test_a_bent_deck_of_two_plies_tilts_its_material_lines_by_atan_theta():
    """Two frictionless plies clamped at x = 0, each bent by the end moment of its own arc
    concentric with the mid-surface's (validation case plies-deck-of-cards: 100 x 5 mm, h = 1
    mm, 90 deg, 10 x 1 cells, Static in 4 curved increments): the material line tilts from the
    normal by atan(theta) and measures h sqrt(1 + theta^2) along it (docs/theory.md §1.7).
    Measured at 10 cells: 0.28 deg and 0.51 % at most (first order in the cell size: 0.13 deg
    and 0.26 % at 20 cells); tolerances 0.35 deg and 0.65 %."""
    from validation.cases.plies_deck_of_cards import bend

    run = bend(2, 10)
    assert run.result.converged
    assert np.degrees(run.theta[-1]) == pytest.approx(90.0, abs=1.0)
    errors = run.errors()
    assert max(errors["tilt_inside_deg"], errors["tilt_end_deg"]) <= 0.35
    assert max(errors["thickness_inside"], errors["thickness_end"]) <= 0.0065


# The heavy stack of fibrous-heavy-cantilever (140 x 10 mm, h = 6 mm, q L^3 / B = 20.5) as 4
# frictionless plies against the FibrousShell: the coarse report's plies-deck-of-cards sags both
# on 20 x 1 cells and checks the mid-surfaces within 0.3 mm and, from the clamp to mid-span, the
# material line's angle within 0.65 deg of the fibrous director's (measured 0.22 mm and 0.48
# deg), which tests/test_validation_cli.py holds to; the same claims on 10 cells (0.9 mm and
# 1.5 deg, measured 0.71 and 1.19) would be a run of their own beside the report's.


# ---------------------------------------------------------------------- friction between plies
def test_a_ply_pressed_by_its_weight_slides_when_pulled_by_mu_times_its_weight():
    """Coulomb between two flat plies (PlyStack(friction=mu), elements/ply_contact.py): the
    lower ply held, the upper one pressed on it by its weight W and pulled along x by a
    prescribed displacement u (Static, gravity first, then u in 4 increments). While stuck the
    pull is the stick springs' k n u (k per node, n upper nodes); it cannot exceed mu W, at
    which the ply slides: the pull at u = 0.625, 1.25, 1.875, 2.5 mu W / (k n) is 0.625, 1, 1,
    1 mu W. The reaction's weight is exact (z equilibrium of the upper ply), the sliding pull
    is mu times the sum of the points' normal forces by the return mapping, and the stuck pull
    k n u has the anchors' offsets exactly u (a rigid slide of a flat ply), so all are held
    to the Newton residual, Static's tol = 1e-8 of the reference force (the weights and the
    reactions): tolerance 1e-8 of mu W; measured 1e-14. The directors are held (alpha, beta
    fixed): the plies' shells carry no load here, and the frictionless stack with free
    directors does not converge in this setup either (gravity phase, increment 1).
    """
    mu, k, g = 0.3, 1.0, 9810.0
    fabric = Fabric(thickness=1.0, areal_density=1e-6, tension=1e4, shear=1.0, bending=1.0)
    mid = Mesh.rectangle(10.0, 10.0, nx=2, ny=2)
    stack = PlyStack(mid, fabric, 2, penalty=k, friction=mu)
    model = stack.model()
    lower, upper = stack.ply_nodes
    model.fix(lower)
    model.fix(upper, ("alpha", "beta"))
    weight = stack.ply_fabric.areal_density * 100.0 * g  # the upper ply's, N
    slip = mu * weight / (k * len(upper))  # the stick springs reach mu W there, mm
    model.displace(upper, ux=2.5 * slip, uy=0.0)
    model.gravity((0.0, 0.0, -g))
    result = Static(increments=4, step_loads_first=True, progress=False).solve(model)
    assert result.converged
    pulled = [f for f in result.frames if f.load_factor > 1.0]
    pull = np.array([f.reactions[upper, 0].sum() for f in pulled]) / (mu * weight)
    assert np.allclose(pull, [0.625, 1.0, 1.0, 1.0], rtol=0, atol=1e-8)
    for frame in pulled:  # the lower ply takes the weight of both
        assert frame.reactions[lower, 2].sum() == pytest.approx(2.0 * weight, rel=1e-8)


@pytest.mark.parametrize("friction", [-0.1, np.inf, "0.3", True, None])
def test_plies_refuse_a_bad_friction(friction):
    with pytest.raises(ValueError, match="friction must be a Coulomb coefficient"):
        PlyStack(Mesh.rectangle(10.0, 5.0, nx=2, ny=1), DECK, 2, friction=friction)
