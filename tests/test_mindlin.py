"""MindlinShell (docs/theory.md §5): rotary inertia, bad input, the analytic tangent (§5.5) against
central differences of the element's loads, and linear and nonlinear benchmarks with
closed-form or series references (the linear ones solved with a dense finite-difference
stiffness on small meshes).

Its conformance to the element protocol (DESIGN §5: rigid motions, objectivity, f = dW/dx,
tangent, mass, stable step against the exact eigenvalues for a thick and a thin shell) is
checked by tests/test_conformance.py, cases "mindlin", "mindlin-thick" and "mindlin-thin"."""

import dataclasses
import warnings

import numpy as np
import pytest

from elements import MindlinShell, mindlin, mindlin_tables
from femcore import Mesh, Model
from femcore.rotation import rotate_about
from materials import ElasticShell
from tests.shell_helpers import stiffness_and_mass

MESH = Mesh.rectangle(40.0, 30.0, nx=4, ny=3)


def compiled(mesh=MESH, material=None, **options):
    model = Model(mesh)
    model.add(MindlinShell(material or ElasticShell(1000.0, 0.3, 2.0, 1e-9), **options))
    return model.compile()


def linear_solve(model):
    """Displacements (n, 5) of the linear problem K u = F at the reference state."""
    state = model.initial_state()
    stiffness, _ = stiffness_and_mass(model, state, step=1e-6)
    force, _ = model.external_load(1.0)
    free = np.column_stack([model.translation_free, ~model.rotation_fixed]).ravel()
    load = np.column_stack([force, np.zeros((model.n_nodes, 2))]).ravel()[free]
    u = np.zeros(5 * model.n_nodes)
    u[free] = np.linalg.solve(stiffness, load)
    return u.reshape(-1, 5)


# ------------------------------------------------------------------ inertia, input
def test_rotary_inertia_is_at_least_the_physical_one():
    material = ElasticShell(1000.0, 0.3, 2.0, 3e-9)
    model = compiled(material=material)
    mass, inertia = model.lumped_mass(model.initial_state())
    assert (inertia >= mass * 2.0**2 / 12 * (1 - 1e-12)).all()  # at least the physical h^2/12


def test_bad_input_is_refused():
    with pytest.raises(ValueError, match="nu"):
        ElasticShell(1000.0, 0.5, 1.0, 1e-9)
    with pytest.raises(ValueError, match="thickness"):
        ElasticShell(1000.0, 0.3, 0.0, 1e-9)
    with pytest.raises(ValueError, match="ElasticShell"):
        MindlinShell(3.0)
    with pytest.raises(ValueError, match="thickness_points"):
        MindlinShell(ElasticShell(1000.0, 0.3, 1.0, 1e-9), thickness_points=1)


# ------------------------------------------------------------------ tangent
def _deformed_state(model, rng, rotation=1.0):
    """A state far from the reference: the patch stretched (x 1.3 and x 0.8) and sheared,
    turned by a random rigid rotation, its nodes jittered by 0.8 mm, its directors turned by a
    further random rotation of about ``rotation`` rad at every node."""
    state = model.initial_state()
    turn, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    stretch = np.array([[1.3, 0.2, 0.0], [0.0, 0.8, 0.0], [0.0, 0.0, 1.0]])
    positions = state.positions @ stretch.T @ turn.T
    positions += rng.normal(scale=0.8, size=positions.shape)
    spin = rng.normal(scale=rotation / np.sqrt(3), size=state.directors.shape)
    directors = rotate_about(state.directors @ turn.T, spin)
    return dataclasses.replace(state, positions=positions, directors=directors)


_ARC = MESH.points[:, 0] / 30.0  # the patch wrapped on a cylinder of radius 30 mm
CYLINDER = MESH.with_points(
    np.column_stack([30.0 * np.sin(_ARC), MESH.points[:, 1], 30.0 * np.cos(_ARC)])
)
ORTHOTROPIC = ElasticShell.orthotropic(
    2e5, 5e4, 0.1, 3e4, 3e4, 2e4, 1.5, 1e-9, warp=(1.0, 0.3, 0.0)
)


@pytest.mark.parametrize("thickness_points", [2, 3, 5])
@pytest.mark.parametrize("mesh", [MESH, CYLINDER], ids=["flat", "cylinder"])
@pytest.mark.parametrize("material", [None, ORTHOTROPIC], ids=["isotropic", "orthotropic"])
def test_analytic_tangent_equals_the_difference_tangent(
    thickness_points, mesh, material, monkeypatch
):
    # docs/theory.md §5.5 against the central differences of the element's own loads, on
    # states with large rotations and stretched cells. Slices of 7 cells so that the 24
    # triangles take several slices and a partial one. Measured: below 1e-9 of the largest
    # entry (the differences' own truncation and round-off).
    monkeypatch.setattr(mindlin, "_TANGENT_SLICE", 7)
    model = compiled(mesh=mesh, material=material, thickness_points=thickness_points)
    block = model.blocks[0]
    rng = np.random.default_rng(thickness_points)
    for state in (model.initial_state(), _deformed_state(model, rng), _deformed_state(model, rng)):
        analytic = block.tangent(state)[0]
        reference = block.difference_tangent(state)[0]
        assert np.array_equal(analytic.nodes, reference.nodes)
        scale = np.abs(reference.blocks).max()
        assert np.abs(analytic.blocks - reference.blocks).max() <= 1e-6 * scale


def test_generalised_tangent_is_symmetric():
    # docs/theory.md §5.5: the spin term V g^T - (g . V) I differs from its symmetric part by
    # -1/2 [m]x, and m = V x g is perpendicular to V, so that part has no component in the
    # (alpha, beta) plane: K_ff in (u, alpha, beta) is symmetric at every state (measured
    # 1e-16 of its largest entry). Checked at the equilibrium of a strip rolled into a quarter
    # circle by an end moment and at a state far from it; Newton takes as many iterations as
    # with the finite-difference tangent of the whole model.
    from femcore.assembly import FreeTangentAssembler
    from solvers import Static
    from validation.specimens import mindlin_strip

    length, width, thickness, young = 200.0, 20.0, 1.0, 70e3
    mesh, model = mindlin_strip(length, width, thickness, young, cells=8, across=1)
    moment = 0.5 * np.pi * young * width * thickness**3 / 12 / length
    tip = mesh.nodes("right")
    model.moment(tip, (0.0, -moment / len(tip), 0.0), amplitude="linear")
    # Straight steps without chords: the acceptance tests of the curved steps and the chord
    # corrections (solvers.newton_curvature) compare energies that the tangents' 1e-10
    # difference may tip in the iterations where the residual ratio is still near 1.
    plain = {"increments": 2, "curved": False, "chords": 0}
    result = Static(**plain).solve(model)
    by_differences = Static(**plain, tangent="finite_difference").solve(model)
    assert (
        result.info["iterations_per_increment"] == by_differences.info["iterations_per_increment"]
    )
    compiled_model = model.compile()
    equilibrium = dataclasses.replace(
        compiled_model.initial_state(),
        positions=result.positions,
        directors=result.directors,
        load_factor=1.0,
    )
    rng = np.random.default_rng(3)
    elsewhere = dataclasses.replace(
        equilibrium,
        positions=result.positions + rng.normal(scale=2.0, size=result.positions.shape),
        directors=rotate_about(
            result.directors, rng.normal(scale=0.5, size=result.directors.shape)
        ),
    )
    block = compiled_model.blocks[0]
    assemble = FreeTangentAssembler(compiled_model.dofs)
    for state in (equilibrium, elsewhere):
        frames = compiled_model.dofs.frames(state.directors)
        k = assemble(list(block.tangent(state)), frames)[0].toarray()
        reference = assemble(list(block.difference_tangent(state)), frames)[0].toarray()
        scale = np.abs(k).max()
        assert np.abs(k - k.T).max() <= 1e-12 * scale
        assert np.abs(k - reference).max() <= 1e-6 * scale


# ------------------------------------------------------------------ linear benchmarks
@pytest.mark.parametrize("thickness", [10.0, 1.0, 0.1])  # L/h = 10, 100, 1000
def test_cantilever_strip_under_a_tip_load_does_not_lock(thickness):
    # Timoshenko beam: P L^3 / (3 E I) + P L / (kappa G A), nu = 0 (no plate effect).
    length, width, young, load = 100.0, 10.0, 1e5, 1e-3
    mesh = Mesh.rectangle(length, width, nx=20, ny=2)
    model = Model(mesh)
    model.add(MindlinShell(ElasticShell(young, 0.0, thickness, 1e-9)))
    model.fix("left")
    tip = mesh.nodes("right")
    model.force(tip, (0.0, 0.0, load / len(tip)))
    u = linear_solve(model.compile())
    inertia = width * thickness**3 / 12
    beam = load * length**3 / (3 * young * inertia) + load * length / (
        5 / 6 * young / 2 * width * thickness
    )
    assert u[tip, 2].mean() == pytest.approx(beam, rel=0.02)


@pytest.mark.parametrize(
    "support, coefficient, cells",
    # Central deflection w = c q a^4 / D of a square plate under uniform pressure, nu = 0.3:
    # Timoshenko & Woinowsky-Krieger, Theory of Plates and Shells (1959), Table 8 (simply
    # supported, 0.00406) and Table 35 (clamped, 0.00126). Quarter plates, a/h = 100.
    [("simply supported", 0.00406235, 12), ("clamped", 0.00126532, 16)],
)
def test_square_plate_under_uniform_pressure(support, coefficient, cells):
    a, h, young, nu, pressure, g = 100.0, 1.0, 1e4, 0.3, 1e-3, 9810.0
    mesh = Mesh.rectangle(a / 2, a / 2, nx=cells, ny=cells)
    model = Model(mesh)
    # Pressure as the weight of the plate: the lumped load q A / 3 per triangle corner.
    model.add(MindlinShell(ElasticShell(young, nu, h, pressure / (h * g))))
    if support == "clamped":
        model.fix("left")
        model.fix("bottom")
    else:
        model.fix("left", ["uz"])
        model.fix("bottom", ["uz"])
    model.fix("right", ["ux", "alpha"])  # symmetry planes x = a/2 and y = a/2
    model.fix("top", ["uy", "beta"])
    model.gravity((0.0, 0.0, -g))
    u = linear_solve(model.compile())
    rigidity = young * h**3 / (12 * (1 - nu**2))
    centre = mesh.n_nodes - 1
    assert -u[centre, 2] == pytest.approx(coefficient * pressure * a**4 / rigidity, rel=0.02)


def test_quarter_ring_cantilever_matches_castigliano():
    # A thin quarter ring (R/h = 100) clamped at one end with a radial tip load P bends in its
    # plane: M = P R cos(theta), so the tip moves pi P R^3 / (4 E I) (Castigliano; membrane
    # and shear terms are 1e-4 of it). Checks the curved reference geometry (directors from
    # the nodal normals) and the Static solver on a curved shell.
    from solvers import Static

    radius, width, thickness, young, load = 100.0, 10.0, 1.0, 1e5, 1e-4
    flat = Mesh.rectangle(np.pi * radius / 2, width, nx=20, ny=2)
    s, y = flat.points[:, 0], flat.points[:, 1]
    mesh = flat.with_points(
        np.column_stack([radius * np.cos(s / radius), y, radius * np.sin(s / radius)])
    )
    model = Model(mesh)
    model.add(MindlinShell(ElasticShell(young, 0.0, thickness, 1e-9)))
    model.fix("left")
    tip = mesh.nodes("right")
    model.force(tip, (0.0, 0.0, -load / len(tip)))
    result = Static(increments=1).solve(model)
    inertia = width * thickness**3 / 12
    expected = np.pi * load * radius**3 / (4 * young * inertia)
    assert -result.displacements[tip, 2].mean() == pytest.approx(expected, rel=0.01)


def test_scordelis_lo_roof():
    # MacNeal & Harder, Finite Elem. Anal. Des. 1 (1985) 3: R = 25, L = 50, t = 0.25 (ft),
    # E = 4.32e8, nu = 0, 90 psf self-weight, rigid diaphragms; vertical displacement of the
    # free-edge midpoint 0.3024 ft (linear). Quarter model, 32 x 32 cells. The benchmark is
    # linear: at the full 90 psf a geometrically nonlinear solve is 16% stiffer (0.25 ft), so
    # the load is scaled by 1e-4 and the answer scaled back.
    from solvers import Static

    radius, length, thickness, young, scale = 25.0, 50.0, 0.25, 4.32e8, 1e-4
    angle = np.radians(40.0)
    flat = Mesh.rectangle(length / 2, radius * angle, nx=32, ny=32)
    x, s = flat.points[:, 0], flat.points[:, 1]
    mesh = flat.with_points(
        np.column_stack([x, radius * np.sin(s / radius), radius * np.cos(s / radius)])
    )
    model = Model(mesh)
    # 90 psf as the weight of the shell (g = 1).
    with warnings.catch_warnings():  # the benchmark's units (ft, lb), not mm, N, t
        warnings.simplefilter("ignore", UserWarning)
        section = ElasticShell(young, 0.0, thickness, 90.0 * scale / thickness)
    model.add(MindlinShell(section))
    model.fix("left", ["ux", "alpha"])  # mid-span symmetry
    model.fix("bottom", ["uy", "beta"])  # crown symmetry
    model.fix("right", ["uy", "uz"])  # rigid diaphragm
    model.gravity((0.0, 0.0, -1.0))
    result = Static(increments=1).solve(model)
    node = np.flatnonzero(np.isclose(x, 0.0) & np.isclose(s, radius * angle))[0]
    assert -result.displacements[node, 2] / scale == pytest.approx(0.3024, rel=0.02)


def test_cantilever_under_a_large_tip_load_follows_the_elastica():
    # P L^2 / EI = 3: the tip drops by 0.603 L (Bisshopp & Drucker 1945; here from the
    # boundary-value solve in validation/references/elastica.py, which gives their 0.3017 L
    # at P L^2 / EI = 1). Thin strip, L/h = 100, nu = 0, 20 elements.
    from solvers import Static
    from validation.references.elastica import tip_loaded_cantilever
    from validation.specimens import mindlin_strip

    length, width, thickness, young = 100.0, 5.0, 1.0, 1e5
    mesh, model = mindlin_strip(length, width, thickness, young, cells=20)
    bending = young * width * thickness**3 / 12
    load = 3.0 * bending / length**2
    tip = mesh.nodes("right")
    model.force(tip, (0.0, 0.0, -load / len(tip)))
    result = Static(increments=5).solve(model)
    reference = tip_loaded_cantilever(length, load, bending)
    moved = result.displacements[tip].mean(axis=0)
    assert reference["tip_deflection"] == pytest.approx(0.603 * length, rel=1e-3)
    assert -moved[2] == pytest.approx(reference["tip_deflection"], rel=0.01)
    assert length + moved[0] == pytest.approx(reference["tip_x"], rel=0.01)
    # Thin-shell limit (Kirchhoff): with L/h = 100 the directors stay normal to the bent
    # mid-surface (slope up to 60 deg here) - the opposite of the fibrous shell, whose
    # directors slip. Each element's normal against the mean of its corner directors.
    corners = result.positions[mesh.triangles]
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    mean = result.directors[mesh.triangles].mean(axis=1)
    mean /= np.linalg.norm(mean, axis=1)[:, None]
    assert np.degrees(np.arccos(np.clip(np.sum(normals * mean, 1), -1, 1))).max() < 2.0


def test_pinched_cylinder_with_rigid_diaphragms():
    # MacNeal & Harder (1985): R = 300, L = 600, t = 3, E = 3e6, nu = 0.3, two opposite unit
    # loads at mid-length, rigid diaphragms at the ends; radial displacement under the load
    # 1.8248e-5. One octant, 48 x 48 cells (3-node shells converge slowly on this problem:
    # 0.46, 0.80, 0.95, 0.98 of the reference at 8, 16, 32, 48 cells per side).
    from solvers import Static

    radius, length, thickness = 300.0, 600.0, 3.0
    flat = Mesh.rectangle(length / 2, radius * np.pi / 2, nx=48, ny=48)
    x, s = flat.points[:, 0], flat.points[:, 1]
    mesh = flat.with_points(
        np.column_stack([x, radius * np.sin(s / radius), radius * np.cos(s / radius)])
    )
    model = Model(mesh)
    model.add(MindlinShell(ElasticShell(3e6, 0.3, thickness, 1e-9)))
    model.fix("left", ["uy", "uz"])  # rigid diaphragm at x = 0
    model.fix("right", ["ux", "alpha"])  # symmetry plane x = L/2
    model.fix("bottom", ["uy", "beta"])  # symmetry plane y = 0
    model.fix("top", ["uz", "beta"])  # symmetry plane z = 0
    loaded = mesh.nodes(lambda X, Y, Z: np.isclose(X, length / 2) & np.isclose(Y, 0.0))
    model.force(loaded, (0.0, 0.0, -0.25))  # a quarter of the unit load on the octant
    result = Static(increments=1).solve(model)
    assert -result.displacements[loaded[0], 2] == pytest.approx(1.8248e-5, rel=0.02)


@pytest.mark.parametrize("warp, modulus", [((1.0, 0.0, 0.0), 2e5), ((0.0, 1.0, 0.0), 5e4)])
def test_orthotropic_strip_bends_with_the_modulus_along_it(warp, modulus):
    # E1 = 2e5 along the warp, E2 = 5e4 across it, nu12 = 0: a cantilever along x is as stiff
    # as E1 when the warp is x and as E2 when it is y (Euler-Bernoulli, L/h = 100).
    length, width, thickness, load = 100.0, 10.0, 1.0, 1e-3
    material = ElasticShell.orthotropic(2e5, 5e4, 0.0, 3e4, 3e4, 3e4, thickness, 1e-9, warp=warp)
    mesh = Mesh.rectangle(length, width, nx=20, ny=2)
    model = Model(mesh)
    model.add(MindlinShell(material))
    model.fix("left")
    tip = mesh.nodes("right")
    model.force(tip, (0.0, 0.0, load / len(tip)))
    u = linear_solve(model.compile())
    beam = load * length**3 / (3 * modulus * width * thickness**3 / 12)
    assert u[tip, 2].mean() == pytest.approx(beam, rel=0.02)


def test_section_forces_under_an_end_moment():
    # Linear cantilever under an end moment M: a uniform bending moment M / b per unit width,
    # no membrane force, no shear force (statics).
    length, width, thickness, moment = 100.0, 10.0, 1.0, 1e-3
    mesh = Mesh.rectangle(length, width, nx=10, ny=2)
    model = Model(mesh)
    model.add(MindlinShell(ElasticShell(1e5, 0.0, thickness, 1e-9)))
    model.fix("left")
    tip = mesh.nodes("right")
    model.moment(tip, (0.0, -moment / len(tip), 0.0))
    from solvers import Static

    fields = Static(increments=1).solve(model).frames[-1].fields["triangle"]
    m11 = fields["bending_moment"][:, 0]
    assert np.abs(m11).mean() == pytest.approx(moment / width, rel=0.02)
    assert np.abs(fields["membrane_force"]).max() < 1e-3 * moment / thickness
    assert np.abs(fields["shear_force"]).max() < 0.05 * moment / width


# ---------------------------------------------------------------------- compiled kernel
@pytest.mark.parallel
@pytest.mark.parametrize("points", [2, 3])
def test_the_compiled_kernel_gives_the_numpy_forces_and_energy(points):
    """elements/kernels.py against the vectorised reference on a jittered, tilted patch:
    the same sums in another order, so agreement to 1e-12 of the largest value."""
    mesh = Mesh.rectangle(40.0, 30.0, nx=4, ny=3)
    material = ElasticShell.orthotropic(
        70e3, 20e3, 0.3, 5e3, 4e3, 3e3, 1.0, 2.7e-9, warp=(1.0, 1.0, 0.0)
    )
    values = {}
    for kernel in ("numpy", "compiled"):
        model = Model(mesh)
        model.add(MindlinShell(material, thickness_points=points, kernel=kernel))
        compiled = model.compile()
        state = compiled.initial_state()
        rng = np.random.default_rng(3)
        state.positions = state.positions + rng.normal(scale=0.5, size=state.positions.shape)
        turn = np.cross(state.directors, rng.normal(scale=0.3, size=state.positions.shape))
        state.directors = rotate_about(state.directors, turn)
        force, moment = compiled.internal_force(state)
        values[kernel] = (force, moment, compiled.strain_energy(state))
    for reference, compiled_value in zip(values["numpy"][:2], values["compiled"][:2]):
        scale = np.abs(reference).max()
        assert np.abs(compiled_value - reference).max() <= 1e-12 * scale
    assert values["compiled"][2] == pytest.approx(values["numpy"][2], rel=1e-12)


def _jittered_pair(points=2, warp=(1.0, 1.0, 0.0)):
    """The numpy and the compiled block on one orthotropic patch, and a jittered, tilted
    state of it."""
    mesh = Mesh.rectangle(40.0, 30.0, nx=4, ny=3)
    material = ElasticShell.orthotropic(70e3, 20e3, 0.3, 5e3, 4e3, 3e3, 1.0, 2.7e-9, warp=warp)
    models = {}
    for kernel in ("numpy", "compiled"):
        model = Model(mesh)
        model.add(MindlinShell(material, thickness_points=points, kernel=kernel))
        models[kernel] = model.compile()
    state = models["numpy"].initial_state()
    rng = np.random.default_rng(5)
    state.positions = state.positions + rng.normal(scale=0.5, size=state.positions.shape)
    turn = np.cross(state.directors, rng.normal(scale=0.3, size=state.positions.shape))
    state.directors = rotate_about(state.directors, turn)
    return models, state


@pytest.mark.parametrize("points", [2, 5])
def test_the_compiled_level_stiffness_is_the_sum_of_the_point_matrices(points):
    """The packed D^_z the compiled bind forms cell by cell equals sum_p L_p^T D_pz L_p of
    the numpy point tables, to 1e-12 of its largest entry; its reference products and
    areas are numpy's."""
    models, _ = _jittered_pair(points)
    block = models["compiled"].blocks[0]
    reference = mindlin_tables._packed(mindlin_tables._level_stiffness_of(block.weighted_stiffness))
    assert block.level_stiffness.shape == (len(block.connectivity), points, 28)
    scale = np.abs(reference).max()
    assert np.abs(block.level_stiffness - reference).max() <= 1e-12 * scale
    # the reference products and areas of the same loop against numpy's
    x0, v0 = block._reference_cells()
    metric = block._metric(block._vectors(x0, v0))
    products = np.concatenate(
        [np.stack([metric["11"], metric["22"], metric["12"]], -1), metric["tying"]], -1
    )
    assert np.abs(block.reference_measures - products).max() <= 1e-12 * np.abs(products).max()
    area = 0.5 * np.linalg.norm(np.cross(x0[:, 1] - x0[:, 0], x0[:, 2] - x0[:, 0]), axis=1)
    np.testing.assert_allclose(block.reference_area, area, rtol=1e-12)


def test_the_force_pass_returns_the_strain_energy_it_met():
    """internal_force_and_energy: the compiled block's one pass gives the forces, moments
    and energy of its two calls, and the numpy block's default (the two calls) the same
    to 1e-12."""
    models, state = _jittered_pair()
    for model in models.values():
        block = model.blocks[0]
        force, moment, energy = block.internal_force_and_energy(state)
        alone_force, alone_moment = block.internal_force(state)
        np.testing.assert_array_equal(force, alone_force)
        np.testing.assert_array_equal(moment, alone_moment)
        assert energy == block.strain_energy(state) > 0.0
        summed = model.internal_force_and_energy(state)
        np.testing.assert_array_equal(summed[0], alone_force)
        assert summed[2] == model.strain_energy(state)
    numpy_values = models["numpy"].internal_force_and_energy(state)
    compiled_values = models["compiled"].internal_force_and_energy(state)
    assert compiled_values[2] == pytest.approx(numpy_values[2], rel=1e-12)


@pytest.mark.parametrize("warp", [(1.0, 1.0, 0.0), None])
def test_the_compiled_section_forces_are_the_numpy_ones(warp):
    """The compiled cell fields (lamina maps formed on the fly) against the numpy path's
    point tables, to 1e-12 of the largest value of each field."""
    if warp is None:
        mesh = Mesh.rectangle(40.0, 30.0, nx=4, ny=3)
        models = {}
        for kernel in ("numpy", "compiled"):
            model = Model(mesh)
            model.add(MindlinShell(ElasticShell(70e3, 0.3, 1.0, 2.7e-9), kernel=kernel))
            models[kernel] = model.compile()
        _, state = _jittered_pair()
    else:
        models, state = _jittered_pair(3, warp)
    reference = models["numpy"].blocks[0].cell_fields(state)
    fields = models["compiled"].blocks[0].cell_fields(state)
    assert fields.keys() == reference.keys()
    for name, values in reference.items():
        assert fields[name].shape == values.shape
        scale = np.abs(values).max()
        assert scale > 0.0
        assert np.abs(fields[name] - values).max() <= 1e-12 * scale, name


def test_a_block_keeps_no_point_tables_for_the_compiled_step():
    """What the compiled path reads per triangle stays small: the packed level stiffness and
    the reference products (560 bytes at two levels), no point-wise 5 x 5 tables, no
    scatter tables (forces, fields, masses and stable steps alike)."""
    models, state = _jittered_pair()
    block = models["compiled"].blocks[0]
    block.internal_force_and_energy(state)
    block.cell_fields(state)
    block.lumped_mass(state)
    block.cell_stable_dt(state)
    assert block._point_tables is None and block._weighted is None
    assert block._scatter is None  # the numpy path's index tables neither
    per_cell = (block.level_stiffness.nbytes + block.reference_measures.nbytes) / len(
        block.connectivity
    )
    assert per_cell == 560


def test_an_unknown_kernel_is_refused():
    with pytest.raises(ValueError, match="kernel must be"):
        MindlinShell(ElasticShell(70e3, 0.3, 1.0, 2.7e-9), kernel="fortran")


def test_congruent_cells_share_one_element_eigenvalue_problem():
    """The stable step's calibration solves one eigenvalue problem per reference shape (two
    on a structured rectangle) and gives each cell what its own problem gives, to 1e-13."""
    model = compiled(mesh=Mesh.rectangle(40.0, 30.0, nx=8, ny=6))
    block = model.blocks[0]
    x0, v0 = block._reference_cells()
    first, shape_of = mindlin_tables._congruent_cells(x0, v0)
    assert len(first) == 2 and shape_of.shape == (len(x0),)
    block.cell_stable_dt(model.initial_state())
    own = block.element_omega2(x0, v0) / block._cheap_omega2(x0)
    np.testing.assert_allclose(block._step_calibration, own, rtol=1e-13)
    # a jittered mesh: every cell its own shape
    rng = np.random.default_rng(2)
    jittered = x0 + rng.uniform(-0.1, 0.1, size=x0.shape)
    assert len(mindlin_tables._congruent_cells(jittered, v0)[0]) == len(x0)


@pytest.mark.parallel
def test_a_mindlin_run_gives_the_same_bits_on_one_thread_and_on_all():
    """Bind tables, forces, energy, section forces and 30 explicit steps (the fused
    rotational update included) of a sagging sheet are the same to the last bit whatever
    the threads."""
    from solvers import CentralDifference
    from tests.thread_runs import on_one_thread_and_on_all

    def run():
        model = Model(Mesh.rectangle(60.0, 40.0, nx=12, ny=8))
        model.add(MindlinShell(ElasticShell(70e3, 0.3, 1.0, 2.7e-9)))
        model.fix("left")
        model.gravity((0.0, 0.0, -9810.0))
        compiled_model = model.compile()
        dt = 0.9 * compiled_model.stable_dt(compiled_model.initial_state())
        result = CentralDifference(duration=30 * dt, dt=dt, progress=False).solve(compiled_model)
        frame = result.frames[-1]
        state = dataclasses.replace(
            compiled_model.initial_state(), positions=frame.positions, directors=frame.directors
        )
        return [
            compiled_model.blocks[0].level_stiffness,
            np.hstack(compiled_model.internal_force(state)),
            frame.positions,
            frame.directors,
            frame.fields["triangle"]["bending_moment"],
            np.array([compiled_model.strain_energy(state)]),
        ]

    one, every = on_one_thread_and_on_all(run)
    assert np.abs(one[2] - Mesh.rectangle(60.0, 40.0, nx=12, ny=8).points).max() > 1e-8
    for a, b in zip(one, every):
        np.testing.assert_array_equal(a, b)


def test_the_compiled_cell_steps_are_the_numpy_ones():
    """The explicit solver's cell bound every 10 steps: one compiled loop, numpy's steps to
    1e-13 on a jittered, tilted state."""
    models, state = _jittered_pair()
    steps = {kernel: model.blocks[0].cell_stable_dt(state) for kernel, model in models.items()}
    np.testing.assert_allclose(steps["compiled"], steps["numpy"], rtol=1e-13)
