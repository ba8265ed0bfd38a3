"""The compression-free tangent of Static's iterates far from equilibrium (docs/theory.md §6.5,
``Static(compression_free=...)``, elements/fibrous/tangent.py ``membrane_hessian``).

* On cells whose fibres are all compressed, under a linear tension law and no shear law, the
  compression-free cell Hessian is the material term alone, sum_f A0 w_f C grad(eps_f)
  grad(eps_f)^T, with the strains' gradients in (x, psi, S) by central differences of the
  strains (membrane.strains; tolerance 1e-6 of the largest entry: the differences' truncation
  error at a step of 1e-5 of the 10-mm cells). The exact Hessian differs from it there by
  the compressed fibres' stress terms (checked to be more than 1 %).
* The compiled loops give the numpy numbers (1e-12 of the largest entry), on sheets whose
  fibres are compressed and stretched, with tables and polynomial laws.
* Peirce's fibrous cantilever (the G986 stack, 20 cells, 3 increments; benchmarks/
  static_solver.py line 6) converges in at most 10 iterations per increment (7-14-11 with
  the exact tangent at every iterate), to the same chord angle (1e-6 deg).
* By default (``compression_free=None``) a model of the fibrous shell without contact takes
  the compression-free tangent far from equilibrium: the fibrous heavy cantilever of
  validation/cases at 10 cells (3 increments) in at most 30 Newton iterations in its first
  increment and 45 tangents in all (47-9-8 iterations and 64 tangents with the exact tangent
  at every iterate, 26-9-7 and 42 with it), its tip the same as the exact tangent's to 1e-6 mm
  (the tolerance of the solve, 1e-8 of the loads, moves the tip by less); a Mindlin strip and a
  model with contact keep the exact tangent.
* The compression of the increment's start is kept (elements/fibrous/compression_floor.py):
  taken at the state itself the tangent is the exact one, the compiled loops raise the strains
  to the same floors, and a fibrous column is loaded past its buckling load by equal load steps
  to the elastica.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from elements import FibrousShell, MindlinShell, RigidPlane
from elements.fibrous import geometry, hessian_kernels, membrane, tangent
from femcore import Mesh, Model
from femcore.assembly import tangent_matrix
from femcore.rotation import rotate_about
from materials import BendingLaw, ElasticShell, Fabric, ShearLaw, TensionLaw
from materials.presets import g986_stack
from solvers import Static
from solvers.newton import compression_free_ratio
from tests.test_fibrous_hessian_kernels import FABRICS, _cells
from validation import specimens
from validation.cases.fibrous_heavy_cantilever import strip as heavy_strip
from validation.references.elastica import buckled_cantilever_column, peirce_overhang

TENSION = 500.0  # N/mm


def _fabric() -> Fabric:
    """A 2-mm fabric of linear tension TENSION, no shear stiffness and unit bending."""
    return Fabric(
        thickness=2.0,
        areal_density=1e-9,
        tension=TensionLaw.linear(TENSION),
        shear=ShearLaw.linear(0.0),
        bending=BendingLaw.linear(1.0),
    )


def _compressed_cells():
    """A 3 x 2 sheet of 10-mm cells shrunk by 3 % (every fibre level compressed), jittered by
    0.05 mm, its directors tilted by up to ~0.1 rad: the block and its cells' corners,
    directors and normal sums."""
    fabric = _fabric()
    mesh = Mesh.rectangle(30.0, 20.0, nx=3, ny=2)
    model = Model(mesh)
    model.add(FibrousShell(fabric))
    compiled = model.compile()
    state = compiled.initial_state()
    rng = np.random.default_rng(5)
    positions = 0.97 * state.positions + rng.normal(scale=0.05, size=state.positions.shape)
    turn = np.cross(state.directors, rng.normal(scale=0.05, size=state.positions.shape))
    directors = rotate_about(state.directors, turn)
    block = compiled.blocks[0]
    conn = block.connectivity
    sums = geometry.normal_sums(block, positions)[conn]
    return block, positions[conn], directors[conn], sums


def _level_strains(block, x, v, sums) -> np.ndarray:
    """(m, 2 L) the strains of both fibre families at every level."""
    strain = membrane.strains(block, geometry.cell_geometry(block, x, v, True, sums))
    return np.concatenate([strain["eps1"], strain["eps2"]], axis=1)


def _strain_gradients(block, x, v, sums, step=1e-5) -> np.ndarray:
    """(m, 2 L, 27) d eps / d(x, psi, S) per corner by central differences; a director turns
    as V + psi x V (the tangent's convention, docs/theory.md §1.3)."""
    m = len(x)
    out = np.zeros((m, 2 * block.zeta.size, 27))
    for corner in range(3):
        for kind in range(3):
            for axis in range(3):
                column = 9 * corner + 3 * kind + axis
                shifted = []
                for sign in (1.0, -1.0):
                    xx, vv, ss = x.copy(), v.copy(), sums.copy()
                    if kind == 0:
                        xx[:, corner, axis] += sign * step
                    elif kind == 1:
                        psi = np.zeros((m, 3))
                        psi[:, axis] = sign * step
                        vv[:, corner] = rotate_about(v[:, corner], psi)
                    else:
                        ss[:, corner, axis] += sign * step
                    shifted.append(_level_strains(block, xx, vv, ss))
                out[:, :, column] = (shifted[0] - shifted[1]) / (2.0 * step)
    return out


def test_the_compression_free_hessian_of_compressed_fibres_is_their_material_term():
    block, x, v, sums = _compressed_cells()
    eps = _level_strains(block, x, v, sums)
    assert (eps < -0.005).all()  # every level of both families compressed
    gradient = _strain_gradients(block, x, v, sums)
    weights = np.concatenate([block.weights, block.weights])
    scale = TENSION * block.reference_area[:, None] * weights[None, :]
    expected = np.einsum("mf,mfi,mfj->mij", scale, gradient, gradient)
    got, d_sums = tangent.membrane_hessian(block, x, v, sums, compression_free=True)
    got = got.reshape(len(x), 27, 27)
    assert np.abs(got - expected).max() <= 1e-6 * np.abs(expected).max()
    assert not d_sums.any()  # no tension, no pull on the normal sums
    exact, _ = tangent.membrane_hessian(block, x, v, sums)
    assert np.abs(exact.reshape(len(x), 27, 27) - expected).max() > 1e-2 * np.abs(expected).max()


@pytest.mark.parametrize("name", sorted(FABRICS))
def test_the_compiled_compression_free_hessians_give_the_numpy_ones(name):
    block, x, v, sums = _cells(FABRICS[name](), True)
    expected, expected_sums = tangent.membrane_hessian(block, x, v, sums, compression_free=True)
    got, got_sums = hessian_kernels.membrane_hessians(block, x, v, sums, compression_free=True)
    assert np.abs(got - expected).max() <= 1e-12 * np.abs(expected).max()
    assert np.abs(got_sums - expected_sums).max() <= 1e-12 * np.abs(expected_sums).max()
    exact, _ = tangent.membrane_hessian(block, x, v, sums)
    assert np.abs(exact - expected).max() > 1e-6 * np.abs(expected).max()  # fibres compressed


def test_with_its_own_compression_kept_the_compression_free_hessian_is_the_exact_one():
    # The floor of each strain is the compression of the increment's start
    # (elements/fibrous/compression_floor.py): taken at the state itself, no strain is raised
    # and the tangent is the exact Hessian, to the last bit; a floor half way keeps half of
    # the compression's stress terms (the tensions are linear in the strain here).
    block, x, v, sums = _compressed_cells()
    eps = _level_strains(block, x, v, sums)
    levels = block.zeta.size
    own = (eps[:, :levels], eps[:, levels:])
    exact, _ = tangent.membrane_hessian(block, x, v, sums)
    kept, _ = tangent.membrane_hessian(block, x, v, sums, compression_free=True, floors=own)
    assert np.array_equal(kept, exact)
    free, _ = tangent.membrane_hessian(block, x, v, sums, compression_free=True)
    half = (own[0] / 2, own[1] / 2)
    between, _ = tangent.membrane_hessian(block, x, v, sums, compression_free=True, floors=half)
    assert np.allclose(between, (exact + free) / 2, rtol=0.0, atol=1e-9 * np.abs(exact).max())


@pytest.mark.parametrize("name", sorted(FABRICS))
def test_the_compiled_hessians_raise_the_strains_to_the_same_floors(name):
    block, x, v, sums = _cells(FABRICS[name](), True)
    levels = block.zeta.size
    eps = _level_strains(block, x, v, sums)
    floors = (np.minimum(eps[:, :levels], 0.0) / 2, np.minimum(eps[:, levels:], 0.0) / 3)
    expected, expected_sums = tangent.membrane_hessian(
        block, x, v, sums, compression_free=True, floors=floors
    )
    got, got_sums = hessian_kernels.membrane_hessians(
        block, x, v, sums, compression_free=True, floors=floors
    )
    assert np.abs(got - expected).max() <= 1e-12 * np.abs(expected).max()
    assert np.abs(got_sums - expected_sums).max() <= 1e-12 * np.abs(expected_sums).max()
    free, _ = tangent.membrane_hessian(block, x, v, sums, compression_free=True)
    assert np.abs(free - expected).max() > 1e-6 * np.abs(expected).max()  # floors matter


def _column_by_load_steps(**options):
    """The imperfect fibrous strip of tests/test_arc_step.py (100 x 5 mm, clamped, a dead tip
    load of 1.5 P_cr along it) by 10 equal load steps of Static(**options), its tip checked
    against the elastica of Timoshenko and Gere (Theory of Elastic Stability, 1961, §2.7)
    within the arc length's tolerance of that test (three times its 20-cell discretisation
    error): the result."""
    from tests.test_arc_step import ALONG_TOLERANCE, LATERAL_TOLERANCE, LENGTH, imperfect_column

    model, tip, bending = imperfect_column("fibrous")
    result = Static(increments=10, progress=False, **options).solve(model)
    assert result.frames[-1].load_factor == 1.0
    expected = buckled_cantilever_column(
        LENGTH, 1.5 * math.pi**2 * bending / (4 * LENGTH**2), bending
    )
    x, _, z = result.positions[tip].mean(axis=0)
    assert z == pytest.approx(expected["lateral"], rel=LATERAL_TOLERANCE["fibrous"])
    assert x == pytest.approx(expected["tip_x"], abs=ALONG_TOLERANCE["fibrous"])
    return result


def test_a_fibrous_column_is_loaded_past_its_buckling_load_by_equal_load_steps():
    # The column carries its load in compression: with the strains of the compression-free
    # tangent raised to zero, Newton lost the compression's geometric softening and stopped
    # at a load factor of 0.6625 (P_cr at 2/3) after 8 cuts. With the last converged state's
    # compression kept, 10 equal load steps reach the elastica.
    result = _column_by_load_steps()
    assert result.info["compression_free"] == 1e-2  # the default for a fibrous model
    assert result.info["compression_free_tangents"] > 0


def test_the_kept_compression_is_the_last_converged_state_s_not_a_predictor_s():
    # The secant predictor extrapolates the increment's start: a straight update shortens the
    # fibres that turn, and with the floors taken there (as first written) the column of the
    # test above stopped at a load factor of 0.6656 with predictor=True. Taken from the last
    # converged state the same 10 load steps reach the elastica.
    _column_by_load_steps(predictor=True)


def test_the_kept_compression_is_computed_again_for_a_state_changed_in_place():
    # real_compression keeps its floors for the state it was given; a State is mutable, so a
    # state whose positions were changed in place (the solvers never do) is not served the
    # floors of what it was: the sheet shrunk by 10 % has warp floors ln(0.9) = -0.1054.
    from elements.fibrous.compression_floor import real_compression

    model = Model(Mesh.rectangle(30.0, 20.0, nx=3, ny=2))
    model.add(FibrousShell(_fabric()))
    compiled = model.compile()
    state = compiled.initial_state()
    block = compiled.blocks[0]
    assert not real_compression(block, state)[0].any()  # unstrained: no compression
    state.positions[:] *= 0.9
    warp, weft = real_compression(block, state)
    assert warp == pytest.approx(math.log(0.9), rel=1e-9)
    assert weft == pytest.approx(math.log(0.9), rel=1e-9)


def test_peirce_fibrous_cantilever_converges_in_at_most_ten_iterations_per_increment():
    fabric = g986_stack()
    overhang = peirce_overhang(fabric.areal_density * specimens.GRAVITY, fabric.bending)
    mesh, model = specimens.fibrous_strip(overhang["overhang"], 10.0, fabric, 20)
    compiled = model.compile()
    # Plain Newton steps (no level projection, Static's default on a fibrous model, which
    # takes both to 6-5-6): the tangent's own effect.
    plain = {"increments": 3, "level_projection": False}
    result = Static(compression_free=1e-2, **plain).solve(compiled)
    exact = Static(compression_free=0.0, **plain).solve(compiled)  # never
    assert max(result.info["iterations_per_increment"]) <= 10
    assert result.info["compression_free_tangents"] > 0
    assert exact.info["compression_free_tangents"] == 0
    tip = mesh.nodes("right")

    def chord(res):
        x, _, z = res.positions[tip].mean(axis=0)
        return math.degrees(math.atan2(-z, x))

    assert chord(result) == pytest.approx(chord(exact), abs=1e-6)


def test_the_fibrous_heavy_cantilever_takes_the_compression_free_tangent_by_default():
    mesh, model = heavy_strip(10)
    compiled = model.compile()
    # Plain Newton steps, as above (with the level projection 6-6-4 and 9-6-4).
    result = Static(increments=3, level_projection=False).solve(compiled)
    exact = Static(increments=3, compression_free=0.0, level_projection=False).solve(compiled)
    assert result.info["compression_free"] == 1e-2
    assert result.info["compression_free_tangents"] > 0
    assert exact.info["compression_free_tangents"] == 0
    assert result.info["iterations_per_increment"][0] <= 30  # 47 with the exact tangent
    assert result.info["evaluations"]["tangent"] <= 45  # 64
    tip = mesh.nodes("right")
    got, expected = result.positions[tip].mean(axis=0), exact.positions[tip].mean(axis=0)
    assert np.abs(got - expected).max() <= 1e-6


# A plane placed anyhow: only whether a contact is there counts, not where it starts.
@pytest.mark.filterwarnings("ignore::femcore.entry_error.EntryWarning")
def test_the_exact_tangent_stays_by_default_on_the_mindlin_shell_and_with_contact():
    """The default ratio: 0 without a block that offers the compression-free tangent, 0 with
    an interaction (a rigid plane under the fibrous sheet)."""
    mesh = Mesh.rectangle(20.0, 10.0, 2, 1)
    fibrous = Model(mesh)
    fibrous.add(FibrousShell(_fabric()))
    assert compression_free_ratio(Static().compression_free, fibrous.compile()) == 1e-2
    assert (
        compression_free_ratio(Static(compression_free=0.0).compression_free, fibrous.compile())
        == 0.0
    )
    fibrous.contact(RigidPlane((0.0, 0.0, -0.9), (0.0, 0.0, 1.0)), penalty=100.0)
    assert compression_free_ratio(Static().compression_free, fibrous.compile()) == 0.0
    mindlin = Model(mesh)
    mindlin.add(MindlinShell(ElasticShell(7e4, 0.0, 1.0, 1e-9)))
    assert compression_free_ratio(Static().compression_free, mindlin.compile()) == 0.0


def test_a_negative_compression_free_ratio_is_refused():
    with pytest.raises(ValueError, match="compression_free"):
        Static(compression_free=-1.0)


# A plane placed anyhow: only whether a contact is there counts, not where it starts.
@pytest.mark.filterwarnings("ignore::femcore.entry_error.EntryWarning")
def test_the_model_gives_the_compression_free_tangent_of_the_blocks_that_offer_it():
    """``CompiledModel.tangent_parts(..., compression_free=True)`` on the compressed sheet
    pressed on a plane (a fibrous block and a contact): the fibrous block's own
    compression-free tangent (``tangent(state, compression_free=True)``) and the contact's
    own tangent, assembled, are the model's bit for bit (the same arrays summed in the same
    order: tolerance 0); without the keyword, the exact tangent, which differs there (the
    compressed fibres' stress terms, more than 1e-6 of the largest entry)."""
    fabric = _fabric()
    model = Model(Mesh.rectangle(30.0, 20.0, nx=3, ny=2))
    model.add(FibrousShell(fabric))
    model.contact(RigidPlane((0.0, 0.0, -0.9), (0.0, 0.0, 1.0)), penalty=100.0)
    compiled = model.compile()
    state = compiled.initial_state()
    rng = np.random.default_rng(5)
    positions = 0.97 * state.positions + rng.normal(scale=0.05, size=state.positions.shape)
    state = replace(state, positions=positions)
    block, contact = compiled.parts
    assert len(contact.tangent(state, state.history[1])) > 0  # nodes pressed in
    frames = compiled.dofs.frames(state.directors)
    both = [0, 1]

    def assembled(parts):
        return tangent_matrix(compiled.dofs, parts, frames).toarray()

    free = assembled(compiled.tangent_parts(state, both, compression_free=True))
    own = [
        *block.tangent(state, state.history[0], compression_free=True),
        *contact.tangent(state, state.history[1]),
    ]
    assert np.array_equal(free, assembled(own))
    exact = assembled(compiled.tangent_parts(state, both))
    contact_parts = contact.tangent(state, state.history[1])
    assert np.array_equal(exact, assembled([*block.tangent(state), *contact_parts]))
    assert np.abs(free - exact).max() > 1e-6 * np.abs(exact).max()
