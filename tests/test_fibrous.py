"""FibrousShell (Bai et al. 2020; docs/theory.md §1-4): the gradient with the current bending
coefficients, the rotary inertia, the curvature of the rotation-free bending, the fibre
ordering and the Table 1 law.

Its conformance to the element protocol (DESIGN §5: rigid motions, objectivity, f = dW/dx per
part, tangent, mass, stable step against the exact eigenvalues) is checked by
tests/test_conformance.py, cases "fibrous", "fibrous-reference-bending" and
"fibrous-bai-fabric". References here: the curvature checks use the closed-form curvature of the
imposed surfaces; the moments, statics of a free body.
"""

import dataclasses

import numpy as np
import pytest

from elements import FibrousShell, MindlinShell
from elements.fibrous import (
    bending,
    geometry,
    lobatto_levels,
    side_tables,
    tangent,
    thickness_along_directors,
)
from femcore import Mesh, Model
from femcore.rotation import rotate_about
from materials import BendingLaw, ElasticShell, Fabric, ShearLaw, TensionLaw
from tests.shell_helpers import compiled, fabric, on_cylinder, position_gradient

RNG = np.random.default_rng(7)


def deformed(model, amplitude=0.6, tilt=0.3, seed=0):
    """A state with random nodal displacements (mm) and director tilts (rad)."""
    rng = np.random.default_rng(seed)
    state = model.initial_state()
    state.positions = state.positions + rng.normal(scale=amplitude, size=state.positions.shape)
    turn = np.cross(state.directors, rng.normal(scale=tilt, size=state.positions.shape))
    state.directors = rotate_about(state.directors, turn)
    return state


MESH = Mesh.rectangle(40.0, 30.0, nx=4, ny=3)


# ------------------------------------------------------------------ current bending, inertia
def _gradient(energy, state, step=1e-6):
    """Central-difference dW/dx (n,3) and dW/dpsi (n,3) without its drilling part."""
    n = state.n_nodes
    force = position_gradient(energy, state, step)
    moment = np.zeros((n, 3))
    for node in range(n):
        for j in range(3):
            psi = np.zeros((n, 3))
            psi[node, j] = step
            plus, minus = state.copy(), state.copy()
            plus.directors = rotate_about(state.directors, psi)
            minus.directors = rotate_about(state.directors, -psi)
            moment[node, j] = (energy(plus) - energy(minus)) / (2 * step)
    v = state.directors
    return force, moment - np.sum(moment * v, axis=1)[:, None] * v


def test_current_bending_coefficients_give_the_gradient_to_first_order_in_the_folds():
    # Bai and S3 hold c_as fixed in the variation: the neglected term is theta * dc, so at
    # folds of ~1e-3 rad on an in-plane distorted patch it is ~1e-3 of the force.
    model = compiled(MESH)
    block = model.blocks[0]
    state = model.initial_state()
    state.positions = state.positions + RNG.normal(scale=[0.5, 0.5, 0.005], size=(MESH.n_nodes, 3))
    force, _ = block.internal_force_parts(state)["bending"]
    fd_force, _ = _gradient(lambda s: block.strain_energy_parts(s)["bending"], state)
    assert np.abs(force - fd_force).max() <= 2e-2 * np.abs(fd_force).max()


def test_paper_thickness_variation_switch_drops_only_the_h_m_term():
    # Bai Eq. 28 omits delta h_m (docs/theory.md §2.5): with top and bottom fibres loaded alike
    # (directors normal, in-plane stretch) the term vanishes and both options agree.
    stretch = compiled(MESH)
    paper = compiled(MESH, thickness_variation=False)
    state = stretch.initial_state()
    state.positions = state.positions * [1.01, 0.995, 1.0]
    f1, m1 = stretch.internal_force(state)
    f2, m2 = paper.internal_force(state)
    assert np.allclose(f1, f2, atol=1e-12 * np.abs(f1).max())
    tilted = deformed(stretch)
    assert not np.allclose(stretch.internal_force(tilted)[1], paper.internal_force(tilted)[1])


def test_rotary_inertia_is_eq_39():
    material = fabric(areal_density=2.5e-9, thickness=4.0)
    model = compiled(MESH, material)
    mass, inertia = model.lumped_mass(model.initial_state())
    assert inertia == pytest.approx(mass * 4.0**2 / 4.0, rel=1e-12, abs=0.0)  # I = m h_m^2 / 4


@pytest.mark.parametrize("tilt", [0.6, 1.4])
def test_rotary_inertia_follows_the_lever_of_a_tilted_director(tilt):
    """Directors tilted from the normal: a rotation moves the fibre levels by h_m / cos(tilt)
    (h_m = h / cos(tilt) turns with them), and I = m (h_m / cos(tilt))^2 / 4 = m (h /
    cos^2)^2 / 4; past the guard (cos(1.4) = 0.17 < 0.2) the guard's value, m (h / 0.2^2)^2 / 4."""
    material = fabric(areal_density=2.5e-9, thickness=4.0)
    for thickness in ("nodal", "element"):
        model = compiled(MESH, material, thickness=thickness)
        state = model.initial_state()
        state.directors = rotate_about(
            state.directors, np.tile([0.0, tilt, 0.0], (MESH.n_nodes, 1))
        )
        mass, inertia = model.lumped_mass(state)
        cosine = max(np.cos(tilt), 0.2)
        assert inertia == pytest.approx(mass * (4.0 / cosine**2) ** 2 / 4.0, rel=1e-9)


# ------------------------------------------------------------------ curvature (docs/theory.md §4.2)
def _curvatures(model, surface, epsilon=1e-6):
    """Warp and weft curvature of every cell when nodes are lifted to z = epsilon f(x, y)."""
    state = model.initial_state()
    x, y = model.reference_positions[:, 0], model.reference_positions[:, 1]
    state.positions[:, 2] = epsilon * surface(x, y)
    fields = model.blocks[0].cell_fields(state)
    return fields["warp_curvature"] / epsilon, fields["weft_curvature"] / epsilon


@pytest.mark.parametrize(
    "surface, warp, weft",
    [
        (lambda x, y: x**2 / 2, -1.0, 0.0),  # cylindrical bending along warp: chi = -w,xx
        (lambda x, y: y**2 / 2, 0.0, -1.0),  # ... along weft
        (lambda x, y: (x**2 + y**2) / 2, -1.0, -1.0),
        (lambda x, y: (x + y) ** 2 / 2, -1.0, -1.0),
        (lambda x, y: x * y, 0.0, 0.0),  # a pure twist bends no fibre
    ],
)
def test_constant_curvature_is_exact_on_interior_elements(surface, warp, weft):
    mesh = Mesh.rectangle(6.0, 7.8, nx=6, ny=6)  # a = 1, b = 1.3 as in docs/theory.md §4.2
    model = compiled(mesh)
    interior = (model.blocks[0].neighbour >= 0).all(axis=1)
    chi_warp, chi_weft = _curvatures(model, surface)
    assert np.allclose(chi_warp[interior], warp, atol=1e-6)
    assert np.allclose(chi_weft[interior], weft, atol=1e-6)


def test_clamped_edge_option_gives_the_exact_curvature_at_the_wall():
    # docs/theory.md §4.5: bending against a rigid wall, w = kappa x^2 / 2 from the clamped edge x
    # = 0.
    mesh = Mesh.rectangle(6.0, 4.0, nx=6, ny=2)
    clamp = Model(mesh)
    clamp.add(FibrousShell(fabric(), clamped="left"))
    clamp.fix("left")  # a clamped edge is held by the supports
    model = clamp.compile()
    chi_warp, _ = _curvatures(model, lambda x, y: x**2 / 2)
    at_wall = np.flatnonzero(model.blocks[0].clamped_side.any(axis=1))
    assert at_wall.size == 2
    assert np.allclose(chi_warp[at_wall], -1.0, atol=1e-6)
    free_model = compiled(mesh)  # without the option the wall is a free edge
    assert not np.allclose(_curvatures(free_model, lambda x, y: x**2 / 2)[0][at_wall], -1.0)


def test_the_model_level_tables_are_the_blocks_tables_over_the_mesh_triangles():
    """elements.fibrous.side_tables and thickness_along_directors: each block's rows at its
    triangles (neighbours as mesh triangle ids), two blocks side by side, the left one
    clamped; a model without a FibrousShell raises."""
    mesh = Mesh.rectangle(6.0, 4.0, nx=6, ny=2)
    left = np.flatnonzero(mesh.points[mesh.triangles].mean(axis=1)[:, 0] < 3.0)
    right = np.setdiff1d(np.arange(len(mesh.triangles)), left)
    model = Model(mesh)
    model.add(FibrousShell(fabric(), clamped="left"), cells=left)
    model.add(FibrousShell(fabric(), thickness="element"), cells=right)
    model.fix("left")
    built = model.compile()
    state = deformed(built)
    sides = side_tables(built)
    thickness = thickness_along_directors(built, state.positions, state.directors)
    for block in built.blocks:
        cells = block.cell_ids
        expected = np.where(block.neighbour >= 0, cells[block.neighbour], -1)
        assert np.array_equal(sides["neighbour"][cells], expected)
        assert np.array_equal(sides["connectivity"][cells], block.connectivity)
        for name in ("clamped_side", "interior_side", "held_cell"):
            assert np.array_equal(sides[name][cells], getattr(block, name))
        own = block.thickness_along_directors(state.positions, state.directors)
        assert np.array_equal(thickness["connectivity"][cells], block.connectivity)
        for name in ("cosine", "thickness", "guarded"):
            assert np.array_equal(thickness[name][cells], own[name])
    assert sides["clamped_side"][left].any() and not sides["clamped_side"][right].any()
    # The blocks do not couple: no neighbour across the line x = 3.
    assert np.isin(sides["neighbour"][left], np.append(left, -1)).all()
    mindlin = Model(mesh)
    mindlin.add(MindlinShell(ElasticShell(E=70e3, nu=0.3, thickness=1.0, density=2.7e-9)))
    with pytest.raises(ValueError, match="no FibrousShell"):
        side_tables(mindlin.compile())


def test_table_1_law_is_the_moment_carried_across_a_section_of_a_bent_strip():
    # A strip bent onto a cylinder of curvature chi must carry the Table 1 moment M(chi) per
    # unit width across any section: the moment about the section of the nodal forces on
    # the part beyond it (statics of a free body), compared with the closed-form law.
    law = BendingLaw.bilinear(7.5, 0.5, knee=1e-3)  # Bai Table 1, continuous reading
    width = 10.0
    mesh = Mesh.rectangle(100.0, width, nx=20, ny=2)
    material = Fabric(
        thickness=6.0, areal_density=5.7e-9, tension=1e-9, shear=ShearLaw.linear(0.0), bending=law
    )
    model = compiled(mesh, material)
    beyond = mesh.points[:, 0] > 50.0 + 1e-9
    for chi in [-3e-3, -1e-3, -5e-4, 2e-4, 8e-4, 1.5e-3, 5e-3, 2e-2]:
        state = model.initial_state()
        state.positions, state.directors = on_cylinder(mesh.points, -1.0 / chi)
        force, _ = model.blocks[0].internal_force_parts(state)["bending"]
        assert np.abs(force[beyond].sum(axis=0)).max() < 1e-10  # a pure couple
        moment = np.cross(state.positions[beyond], force[beyond]).sum(axis=0)[1] / width
        # The nodes lie on the arc, so each element is a chord, shorter than its 5 mm of
        # fabric by e = (5 chi)^2 / 24: the element curvature (fold / chord) and the moment per
        # unit of reference width (A0 / chord) both gain e, i.e. at most 2e overall.
        chord_error = (5.0 * chi) ** 2 / 24
        assert moment == pytest.approx(float(law.value(chi)), rel=2 * chord_error + 1e-6)


# ------------------------------------------------------------------ fibre ordering (Eq. 9)
def _stretch_strains(mesh, **options):
    model = compiled(mesh, **options)
    state = model.initial_state()
    state.positions = state.positions * [1.02, 1.0, 1.0]  # stretch along x only
    fields = model.blocks[0].cell_fields(state)
    return fields["warp_strain"], fields["weft_strain"], model.blocks[0]


def test_both_diagonals_are_fibre_aligned_and_warp_follows_the_given_direction():
    rectangle = Mesh.rectangle(20.0, 10.0, nx=2, ny=2)
    warp, weft, block = _stretch_strains(rectangle)
    assert np.allclose(warp, np.log(1.02)) and np.allclose(weft, 0.0, atol=1e-15)
    # The other diagonal: corner 0 is then reached weft-first, so edge 0-1 is weft.
    p = rectangle.points
    other = Mesh(
        p, [[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4], [3, 4, 7], [3, 7, 6], [4, 5, 8], [4, 8, 7]]
    )
    warp, weft, block = _stretch_strains(other)
    assert (~block.xi_is_warp).any()
    assert np.allclose(warp, np.log(1.02)) and np.allclose(weft, 0.0, atol=1e-15)
    warp, weft, _ = _stretch_strains(rectangle, warp=(0.0, 1.0, 0.0))
    assert np.allclose(weft, np.log(1.02)) and np.allclose(warp, 0.0, atol=1e-15)


def test_a_triangle_without_fibre_edges_is_named():
    mesh = Mesh([[0, 0, 0], [10, 0, 0], [5, 8, 0]], [[0, 1, 2]])
    with pytest.raises(ValueError, match="triangle 0 .* no corner"):
        compiled(mesh)


def test_levels_default_to_simpson_and_bad_options_are_refused():
    zeta, weights = lobatto_levels(3)
    assert zeta == pytest.approx([-1.0, 0.0, 1.0]) and weights == pytest.approx(
        [1 / 6, 2 / 3, 1 / 6]
    )
    zeta, weights = lobatto_levels(5)
    assert weights.sum() == pytest.approx(1.0) and np.sum(weights * zeta**2) == pytest.approx(1 / 3)
    material = fabric()
    for kwargs, message in [
        ({"levels": 1}, "levels must be >= 2"),
        ({"levels": ([0.0, 0.0], [0.5, 0.5])}, "off the mid-surface"),
        ({"levels": ([-2.0, 1.0], [0.5, 0.5])}, "in \\[-1, 1\\]"),
        ({"warp": (0.0, 0.0, 0.0)}, "warp"),
        ({"bending_geometry": "nodal"}, "bending_geometry"),
        ({"fibre_angle_tolerance": 60}, "tolerance"),
    ]:
        with pytest.raises(ValueError, match=message):
            FibrousShell(material, **kwargs)
    with pytest.raises(ValueError, match="materials.Fabric"):
        FibrousShell(3.0)
    model = Model(MESH)
    model.add(FibrousShell(material, clamped=[0, 2]))  # two nodes that make no edge
    with pytest.raises(ValueError, match="no edge of the block"):
        model.compile()


def test_outputs_reach_the_result_fields():
    model = compiled(MESH)
    state = deformed(model, amplitude=0.1, tilt=0.05)
    fields = model.fields(state)
    for name in ["warp_strain", "weft_strain", "shear_angle_deg"]:
        assert fields["triangle"][name].shape == (len(MESH.triangles), 3)
    for name in ["warp_curvature", "weft_curvature", "warp_moment", "weft_moment"]:
        assert fields["triangle"][name].shape == (len(MESH.triangles),)
    thickness = fields["point"]["thickness"]
    assert thickness.shape == (MESH.n_nodes,) and (thickness >= 3.0).all()


def test_a_director_near_the_surface_hits_the_guard_and_is_reported():
    # docs/theory.md §1.4: h_m = h / max(V.n, 0.2); a director tilted 85 deg would give 11.5 h.
    model = compiled(MESH)
    state = model.initial_state()
    node = 6
    state.directors[node] = [np.sin(np.radians(85)), 0.0, np.cos(np.radians(85))]
    block = model.blocks[0]
    assert block.guarded_nodes(state).tolist() == [node]
    thickness = block.thickness_along_directors(state.positions, state.directors)
    corners = block.connectivity == node
    assert np.allclose(thickness["thickness"][corners], 3.0 / 0.2)
    assert model.fields(state)["point"]["thickness_guarded"][node] == 1.0


@pytest.mark.parametrize("warp, stiffness", [((1.0, 0.0, 0.0), 72.0), ((0.0, 1.0, 0.0), 68.0)])
def test_warp_and_weft_bend_with_their_own_stiffness(warp, stiffness):
    # Bai Table 2: B = 72 N mm (warp), 68 N mm (weft). The strip is bent along x, which is the
    # warp or the weft depending on the given warp direction.
    width, chi = 10.0, 2e-3
    mesh = Mesh.rectangle(100.0, width, nx=20, ny=2)
    material = Fabric(
        thickness=15.0,
        areal_density=6.93e-9,
        tension=1e-9,
        shear=0.0,
        bending=72.0,
        bending_weft=68.0,
    )
    model = compiled(mesh, material, warp=warp)
    state = model.initial_state()
    state.positions, state.directors = on_cylinder(mesh.points, 1.0 / chi)
    force, _ = model.blocks[0].internal_force_parts(state)["bending"]
    beyond = mesh.points[:, 0] > 50.0 + 1e-9
    moment = np.cross(state.positions[beyond], force[beyond]).sum(axis=0)[1] / width
    assert moment == pytest.approx(-stiffness * chi, rel=2 * (5.0 * chi) ** 2 / 24 + 1e-6)


def checkerboard_bias_mesh(n: int = 4, size: float = 10.0) -> Mesh:
    """An n x n grid of squares rotated by 45 deg (fibres at +/-45 deg to x, as in a bias
    extension specimen), the squares split along alternating diagonals, so that half of the
    right angles point one way along the fibres and half the other."""
    i, j = np.meshgrid(np.arange(n + 1), np.arange(n + 1), indexing="xy")
    flat = np.column_stack([i.ravel() * size, j.ravel() * size, np.zeros(i.size)])
    ids = np.arange(flat.shape[0]).reshape(n + 1, n + 1)
    triangles = []
    for row in range(n):  # builds the test mesh, not a time step
        for col in range(n):
            p00, p10 = ids[row, col], ids[row, col + 1]
            p01, p11 = ids[row + 1, col], ids[row + 1, col + 1]
            if (row + col) % 2:
                triangles += [(p00, p10, p01), (p10, p11, p01)]
            else:
                triangles += [(p00, p10, p11), (p00, p11, p01)]
    c = np.cos(np.pi / 4)
    rotation = np.array([[c, -c, 0.0], [c, c, 0.0], [0.0, 0.0, 1.0]])
    return Mesh(flat @ rotation.T, triangles=np.array(triangles))


@pytest.mark.parametrize("stretch", [0.1, -0.05])
def test_shear_angle_is_positive_when_the_warp_weft_angle_closes_in_every_cell(stretch):
    # Warp along (1, 1), weft along (-1, 1): stretching y by (1 + e) turns them into (1, 1 + e)
    # and (-1, 1 + e), whose angle closes by asin((e^2 + 2e) / (1 + (1 + e)^2)) (opens for
    # e < 0). The same uniform deformation must give the same shear angle, with that sign,
    # in every cell whichever corner its right angle is at.
    c = np.cos(np.pi / 4)
    model = Model(checkerboard_bias_mesh())
    model.add(FibrousShell(fabric(), warp=(c, c, 0.0)))
    compiled_model = model.compile()
    assert set(compiled_model.blocks[0].shear_sign.tolist()) == {-1.0, 1.0}
    state = compiled_model.initial_state()
    state.positions = state.positions * np.array([1.0, 1.0 + stretch, 1.0])
    gamma = np.radians(compiled_model.fields(state)["triangle"]["shear_angle_deg"])
    closed_form = np.arcsin((stretch**2 + 2 * stretch) / (1 + (1 + stretch) ** 2))
    assert np.abs(gamma - closed_form).max() <= 1e-12


def test_forces_stay_the_energy_gradient_where_the_shear_sign_flips():
    # Cells of both orientations (shear_sign -1 and +1) under a sheared, jittered state.
    material = fabric()
    c = np.cos(np.pi / 4)
    model = Model(checkerboard_bias_mesh(3))
    model.add(FibrousShell(material, warp=(c, c, 0.0), bending_geometry="reference"))
    compiled_model = model.compile()
    state = compiled_model.initial_state()
    rng = np.random.default_rng(5)
    state.positions = state.positions * np.array([1.0, 1.08, 1.0]) + rng.normal(
        scale=0.2, size=state.positions.shape
    )
    force, _ = compiled_model.internal_force(state)
    step = 1e-6
    numerical = np.zeros_like(force)
    for node in range(state.n_nodes):  # a finite-difference reference, not a time step
        for axis in range(3):
            plus, minus = state.copy(), state.copy()
            plus.positions[node, axis] += step
            minus.positions[node, axis] -= step
            numerical[node, axis] = (
                compiled_model.strain_energy(plus) - compiled_model.strain_energy(minus)
            ) / (2 * step)
    # Central differences of step 1e-6 on an energy of this size: 1e-6 of the largest force.
    assert np.abs(force - numerical).max() <= 1e-6 * np.abs(force).max()


# ------------------------------------------------------------------ tangent
def _cell_hessian_by_differences(block, x, v, sums, step=1e-5):
    """d(tangent.cell_gradient)/d(x, psi, S) (m, 3, 9, 3, 9), one central difference per
    unknown of every cell."""
    m = len(x)
    hessian = np.empty((m, 3, 9, 3, 9))
    for node in range(3):
        for comp in range(9):
            plus = [x.copy(), v.copy(), sums.copy()]
            minus = [x.copy(), v.copy(), sums.copy()]
            if comp < 3 or comp >= 6:
                which = 0 if comp < 3 else 2
                plus[which][:, node, comp % 3] += step
                minus[which][:, node, comp % 3] -= step
            else:
                psi = np.zeros((m, 3))
                psi[:, comp - 3] = step
                plus[1][:, node] = rotate_about(v[:, node], psi)
                minus[1][:, node] = rotate_about(v[:, node], -psi)
            difference = tangent.cell_gradient(block, *plus) - tangent.cell_gradient(block, *minus)
            hessian[:, :, :, node, comp] = difference / (2 * step)
    return hessian


@pytest.mark.parametrize("variation", [True, False])
def test_the_membrane_hessian_is_the_derivative_of_each_cells_gradient(variation):
    """The closed form of the cells' tension + shear stiffness in (x, psi, S) against central
    differences of their gradient, on a jittered state with tilted directors, a nonlinear
    shear law and one director tilted past the guard of h_m (V.n < 0.2 there)."""
    material = Fabric(
        thickness=3.0,
        areal_density=1e-9,
        tension=300.0,
        shear=ShearLaw.polynomial(0.2, -0.1, 2.0),
        bending=BendingLaw.linear(20.0),
    )
    model = compiled(MESH, material, thickness_variation=variation)
    state = deformed(model, amplitude=0.8, tilt=0.2)
    state.directors[5:6] = rotate_about(state.directors[5:6], np.array([[1.45, 0.0, 0.0]]))
    block = model.blocks[0]
    conn = block.connectivity
    x, v = state.positions[conn], state.directors[conn]
    sums = geometry.normal_sums(block, state.positions)[conn]
    assert geometry.cell_geometry(block, x, v, True, sums)["guarded"].any()
    exact, d_sums = tangent.membrane_hessian(block, x, v, sums)
    assert np.array_equal(d_sums, tangent.cell_gradient(block, x, v, sums)[..., 6:])
    differences = _cell_hessian_by_differences(block, x, v, sums)
    assert np.abs(exact - differences).max() < 1e-6 * np.abs(exact).max()


# ---------------------------------------------------------------------- compiled kernel
def nonlinear_fabric():
    """Every kind of law the compiled loops evaluate: tension tables (tension-only warp, with
    strains beyond the last knot on the jittered sheet), a cubic-quintic shear polynomial and
    bilinear and tabulated bending."""
    return Fabric(
        thickness=3.0,
        areal_density=1e-9,
        tension=TensionLaw.table([0.0, 0.01, 0.05], [0.0, 20.0, 400.0], tension_only=True),
        tension_weft=TensionLaw.table([-0.02, 0.0, 0.03], [-2.0, 0.0, 90.0]),
        shear=ShearLaw.polynomial(5.0, 40.0, 300.0),
        bending=BendingLaw.bilinear(20.0, 2.0, knee=0.01),
        bending_weft=BendingLaw.table([0.0, 0.005, 0.05], [0.0, 0.2, 0.5]),
    )


def polynomial_fabric():
    """Odd polynomial laws only, the warp's tension-only (the compiled loops evaluate each
    polynomial across a chunk of cells, elements/fibrous/level_lanes.py ``law_row``)."""
    return Fabric(
        thickness=3.0,
        areal_density=1e-9,
        tension=TensionLaw.linear(800.0, tension_only=True),
        tension_weft=TensionLaw.linear(300.0),
        shear=ShearLaw.polynomial(5.0, 40.0, 300.0),
        bending=BendingLaw.bilinear(20.0, 2.0, knee=0.01),
    )


def linear_fabric(padded=False):
    """Linear laws only, as the presets' tension and shear, the warp's tension-only (the
    compiled loops evaluate three linear laws by one loop across a chunk of cells,
    elements/fibrous/level_lanes.py ``linear_lanes``); ``padded``: the same laws written as odd
    polynomials with a zero cubic term, which those loops evaluate law by law (``law_row``)."""

    def written(law):
        if not padded:
            return law
        return dataclasses.replace(law, odd_coefficients=law.odd_coefficients + (0.0,))

    return Fabric(
        thickness=3.0,
        areal_density=1e-9,
        tension=written(TensionLaw.linear(800.0, tension_only=True)),
        tension_weft=written(TensionLaw.linear(300.0)),
        shear=written(ShearLaw.linear(5.0)),
        bending=BendingLaw.bilinear(20.0, 2.0, knee=0.01),
    )


@pytest.mark.parallel
@pytest.mark.parametrize(
    "thickness, variation, tilt, clamped, options",
    [
        ("nodal", True, 0.3, False, {}),
        ("element", True, 0.3, False, {}),
        ("nodal", False, 0.3, False, {}),
        ("nodal", True, 1.6, False, {}),
        ("nodal", True, 0.3, True, {}),
        ("nodal", True, 0.3, False, {"bending_geometry": "reference", "nonlinear": True}),
        ("element", True, 0.3, True, {"nonlinear": True}),
        ("nodal", True, 0.3, False, {"polynomial": True}),
        ("nodal", True, 0.3, False, {"linear": True}),
    ],
)
def test_the_compiled_pieces_give_the_numpy_forces(thickness, variation, tilt, clamped, options):
    """FibrousShell(kernel="compiled") (the geometry, strains, laws, nodal normal sums and
    their forces by the loops of elements/fibrous/kernels.py) against the vectorised reference
    on a jittered, tilted sheet: the same sums in another order, so 1e-12 of the largest force,
    moment and nodal thickness (the rotary inertia's), and of the energy."""
    options = dict(options)
    material = nonlinear_fabric() if options.pop("nonlinear", False) else fabric()
    material = polynomial_fabric() if options.pop("polynomial", False) else material
    material = linear_fabric() if options.pop("linear", False) else material
    mesh = Mesh.rectangle(40.0, 30.0, nx=4, ny=3)
    rng = np.random.default_rng(7)
    jitter = rng.normal(scale=0.8, size=(mesh.n_nodes, 3))
    turn = rng.normal(scale=tilt, size=(mesh.n_nodes, 3))  # 1.6: some corners at the guard
    loads = {}
    for kernel in ("numpy", "compiled"):
        model = Model(mesh)
        model.add(
            FibrousShell(
                material,
                thickness=thickness,
                thickness_variation=variation,
                clamped="left" if clamped else None,
                kernel=kernel,
                **options,
            )
        )
        if clamped:  # the left edge bends against the wall of its reference plane
            model.fix("left")
        built = model.compile()
        state = built.initial_state()
        state.positions = state.positions + jitter
        state.directors = rotate_about(state.directors, np.cross(state.directors, turn))
        loads[kernel] = (
            *built.internal_force(state),
            built.blocks[0].nodal_thickness(state),
            built.strain_energy(state),
        )
    for reference, value in zip(loads["numpy"][:3], loads["compiled"][:3]):
        assert np.abs(value - reference).max() <= 1e-12 * np.abs(reference).max()
    assert loads["compiled"][3] == pytest.approx(loads["numpy"][3], rel=1e-12)


@pytest.mark.parametrize("thickness", ["nodal", "element"])
def test_three_linear_laws_in_one_loop_give_the_polynomial_loops_numbers_to_the_last_bit(
    thickness,
):
    """The compiled loops' one loop for three linear laws (level_lanes.py ``linear_lanes``)
    and their loops for any odd polynomial (``law_row``, here the same laws with a zero cubic
    term: c x + 0 and c x^2 / 2 + 0 are c x and c x^2 / 2 exactly) give the same forces,
    moments and energies to the last bit, on a sheet whose fibres are stretched and
    compressed (the warp tension-only: its compressed fibres carry nothing)."""
    loads, strains = [], []
    for padded in (False, True):
        built = compiled(MESH, linear_fabric(padded), thickness=thickness, kernel="compiled")
        state = deformed(built, amplitude=0.8, tilt=0.3, seed=5)
        block = built.blocks[0]
        force, moment, energy = block.internal_force_and_energy(state)
        parts = np.array(list(block.strain_energy_parts(state).values()))
        loads.append((force, moment, np.array([energy]), parts))
        strains.append(block.fibre_strains(state)[:, : 2 * len(block.zeta)])  # eps1, eps2
    assert (strains[0] < 0.0).any() and (strains[0] > 0.0).any()
    assert np.abs(loads[0][0]).max() > 0.0
    for linear, polynomial in zip(loads[0], loads[1]):
        np.testing.assert_array_equal(linear, polynomial)


@pytest.mark.parametrize("thickness", ["nodal", "element"])
def test_one_pass_gives_the_forces_and_the_energy_of_the_two_calls_to_the_last_bit(thickness):
    """internal_force_and_energy (one pass over the cells that meets the energy on its way
    to the forces) returns the forces of internal_force and the energy of strain_energy to
    the last bit, with every kind of law (tables, polynomials) and a clamped edge; the numpy
    path makes the two calls."""
    mesh = Mesh.rectangle(40.0, 30.0, nx=4, ny=3)
    for kernel in ("compiled", "numpy"):
        model = Model(mesh)
        shell = FibrousShell(nonlinear_fabric(), thickness=thickness, clamped="left", kernel=kernel)
        model.add(shell)
        model.fix("left")
        built = model.compile()
        state = deformed(built, amplitude=0.8, tilt=0.3, seed=3)
        block = built.blocks[0]
        force, moment, energy = block.internal_force_and_energy(state)
        separate = block.internal_force(state)
        np.testing.assert_array_equal(force, separate[0])
        np.testing.assert_array_equal(moment, separate[1])
        assert energy == block.strain_energy(state)
        assert energy > 0.0


@pytest.mark.parametrize("thickness", ["nodal", "element"])
def test_the_compiled_fields_are_the_numpy_ones(thickness):
    """The fields of a frame (strains, shear angles, curvatures, moments, section forces; the
    thickness along the director, where it hit the guard, the director tilt) by the compiled
    passes agree with the numpy path to 1e-12 of their largest value on a jittered sheet
    with a clamped edge and directors tilted up to the guard."""
    mesh = Mesh.rectangle(40.0, 30.0, nx=4, ny=3)
    fields = {}
    for kernel in ("numpy", "compiled"):
        model = Model(mesh)
        shell = FibrousShell(nonlinear_fabric(), thickness=thickness, clamped="left", kernel=kernel)
        model.add(shell)
        model.fix("left")
        built = model.compile()
        state = deformed(built, amplitude=0.8, tilt=1.2, seed=5)
        block = built.blocks[0]
        fields[kernel] = block.cell_fields(state) | block.node_fields(state)
    assert fields["numpy"]["thickness_guarded"].any()
    assert fields["numpy"].keys() == fields["compiled"].keys()
    for name, reference in fields["numpy"].items():
        value = fields["compiled"][name]
        assert np.abs(value - reference).max() <= 1e-12 * max(np.abs(reference).max(), 1e-300)


def test_each_side_between_two_cells_is_evaluated_once_for_both():
    """The side pass of the compiled force (supports.py ``shared_sides``, kernels.py
    ``_side_folds``) evaluates each side that couples two cells once: every such (cell,
    side) is in its table exactly once, as a row's cell or as the cell across (the block's
    ``across_cell``, ``across_side`` of the row's), the rows' cells being the lower of the
    two; the mesh is oriented alike on both sides (sign +1); and the folds and curvature
    coefficients it gives each cell are those of the cell's own evaluation (the numpy
    bending.py ``geometry``) to 1e-12 of the largest (radians, 1/mm: the same formula, the
    neighbour's copy rounded as its partner sees it), with a clamped edge, on a jittered
    sheet."""
    mesh = Mesh.rectangle(40.0, 30.0, nx=4, ny=3)
    geometries = {}
    for kernel in ("numpy", "compiled"):
        model = Model(mesh)
        model.add(FibrousShell(fabric(), clamped="left", kernel=kernel))
        model.fix("left")
        built = model.compile()
        block = built.blocks[0]
        state = deformed(built, amplitude=0.8, tilt=0.3, seed=11)
        geometries[kernel] = bending.geometry(block, state.positions)
    table, sign = block.shared_sides, block.shared_sign
    # 9 bytes a side held by the block (its cell and side as int32, an int8 sign): the
    # cell across and the side's nodes are read from the block's own tables
    assert table.shape == (len(table), 2)
    assert table.nbytes + sign.nbytes == 9 * len(table)
    cell, side = table[:, 0], table[:, 1]
    other, other_side = block.across_cell[cell, side], block.across_side[cell, side]
    seen = np.zeros((len(block.connectivity), 3), dtype=int)
    np.add.at(seen, (cell, side), 1)
    np.add.at(seen, (other, other_side), 1)
    np.testing.assert_array_equal(seen, block.interior_side.astype(int))
    assert (cell < other).all()
    np.testing.assert_array_equal(sign, 1)
    for name in ("fold", "coefficients"):
        reference, value = geometries["numpy"][name], geometries["compiled"][name]
        assert np.abs(value - reference).max() <= 1e-12 * np.abs(reference).max()


def test_each_compiled_loop_has_one_signature():
    """The loops of elements/fibrous/kernels.py and geometry_kernels.py take every array of
    floats writable (``loop_array``): the build, which passes the mesh's read-only points, and
    the steps, which pass the state's, run the same machine code (numba types a read-only
    array apart and would build the loop twice)."""
    from elements.fibrous import geometry_kernels
    from femcore import jit

    if not jit.AVAILABLE:
        pytest.skip("numba is not installed")
    model = Model(MESH)
    model.add(FibrousShell(fabric(), clamped="left"))
    model.fix("left")
    model = model.compile()  # the build: the reference normal sums and bending geometry
    state = deformed(model, seed=2)
    model.internal_force(state)
    model.fields(state)
    for loop in (
        geometry_kernels._normals_pass,
        geometry_kernels._side_folds,
        geometry_kernels._bending_sides,
    ):
        # the builds that ran (femcore/jit.py ``_Parallel``: the plain one on one thread)
        builds = [b for b in (loop.serial, loop._parallel) if b is not None and b.signatures]
        assert builds, loop.__name__
        for build in builds:
            assert len(build.signatures) == 1, loop.__name__
