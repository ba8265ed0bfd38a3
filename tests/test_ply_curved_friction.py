"""Coulomb friction on the curved faces (elements/ply_curved_friction.py, docs/theory.md §9.3a
"Curved faces"): a stuck point's loads are the gradient of the energy the block reports for
it, k_t |s|^2 / 2 with s measured across the curved face's turning normal (the force, the
couple and the lift), and the tangent is the derivative of the loads, stuck and sliding.

The model: the [0/45] pair of tests/test_ply_surface.py on the 50-mm sphere, 30-mm plies of
10-mm cells (3 x 3; 41 touching points, 54 in the mirrored pass),
faces 0.1 mm into each other, jittered by 0.02 mm, mu = 0.3, every touching point anchored
on its facing patch at its projection's coordinates moved by 5e-4 (even points, ~5e-3 mm:
they stick) or 5e-2 (odd, ~0.5 mm: they slide). The reference: central differences of
``strain_energy`` and of the loads at every node, translations and director turns
(femcore.interaction_checks), held to 1e-6 of the largest entry. The steps are 1e-6 mm (the
energy) and 1e-7 mm (the loads), not the kit's default 4e-5 mm (1e-6 of the plies' size): a
stuck point lies 0.33 % of its friction limit from sliding, 1.6e-5 mm of slip, which the
default step carries past it (the loads are E's gradient on either side, not across).
"""

import numpy as np
import pytest
from friction_histories import kept_anchors, shifted_anchors

from elements import (
    ply_curved_friction,
    ply_curved_friction_kernels,
    ply_curved_tangent,
    ply_projection,
)
from elements.layup import Layup
from femcore.interaction_checks import (
    check_added_force,
    check_energy,
    check_force_is_energy_gradient,
    check_tangent,
)
from tests.test_ply_surface import PLY, _on_sphere

MU = 0.3


def _anchored(faces: str, smoothing=None, stuck_only: bool = True, mirrored: bool = False):
    """(block, state, history) of the pair with friction (module docstring); with
    ``stuck_only`` the sliding points' anchors dropped; with ``mirrored`` the mirrored pass
    (the bottom ply's nodes against the top ply's curved face)."""
    layup = Layup(
        PLY, (0.0, 45.0), 30.0, cells=3, rule="gauss", faces=faces, surface="curved",
        penalty=100.0, friction=MU, smoothing=smoothing,
        lower_rule="vertices" if mirrored else None,
    )  # fmt: skip
    block = layup.model().compile().interactions[1 if mirrored else 0]
    state = _on_sphere(layup, 0.1, jitter=0.02)
    history = shifted_anchors(block.facing(state), 0.0005, 0.05)
    if stuck_only:
        history = kept_anchors(history, block.friction_state(state, history).stuck)
    return block, state, history


@pytest.mark.parametrize("faces", ["normal", "director"])
@pytest.mark.parametrize("smoothing", [None, 0.05], ids=["deeper", "on the ramp"])
def test_a_stuck_points_loads_on_the_curved_face_are_the_gradient_of_its_energy(faces, smoothing):
    """Passes at an rtol of 1e-7 (faces along the normals) and 1e-6 (along the directors),
    the rounding allowance included (the 40-mm plies of 4 x 4 cells: 1e-8 and 1e-6). The
    loads before (k_t s alone, spread by the flat shape functions on the upper ply, without
    the couple, the lift or the normals' part) were off by 1.5e-4 to 1.6e-3 of it; without the
    stick spring's slope on the ramp (its part of the lift), by 2.4 times the allowance."""
    block, state, history = _anchored(faces, smoothing)
    sliding = block.friction_state(state, history)
    facing = block.facing(state)
    assert sliding.stuck.sum() >= 12 and not sliding.sliding.any()
    on_ramp = sliding.stuck & (facing.gap > -block.smoothing)
    assert on_ramp.sum() >= (3 if smoothing else 0)
    check_force_is_energy_gradient(block, state, history, step=1e-6)


@pytest.mark.parametrize(
    "faces, stuck_only",
    [("normal", True), ("normal", False), ("director", False)],
    ids=["stuck", "stuck and sliding", "stuck and sliding, faces along the directors"],
)
def test_the_curved_frictions_tangent_is_the_derivative_of_its_loads(faces, stuck_only):
    """Passes at an rtol of 1e-7, the rounding allowance included (so did the 40-mm plies
    of 4 x 4 cells); without the derivative along the anchor patch's normals, off by about 680
    times the allowance."""
    block, state, history = _anchored(faces, stuck_only=stuck_only)
    sliding = block.friction_state(state, history)
    assert sliding.stuck.sum() >= 15 and (stuck_only or sliding.sliding.sum() >= 15)
    assert check_tangent(block, state, history, step=1e-7)


def test_the_mirrored_passs_curved_friction_loads_and_tangent():
    """The mirrored pass (``points="lower"``), faces along the normals: 27 stuck and 27
    sliding points; the stuck points' loads the energy's gradient, the tangent the loads'
    derivative, as above."""
    block, state, history = _anchored("normal", stuck_only=False, mirrored=True)
    sliding = block.friction_state(state, history)
    assert block.mirrored and sliding.stuck.sum() >= 20 and sliding.sliding.sum() >= 20
    assert check_tangent(block, state, history, step=1e-7)
    block, state, history = _anchored("normal", mirrored=True)
    check_force_is_energy_gradient(block, state, history, step=1e-6)


def test_plies_apart_carry_no_curved_friction_loads():
    # no point touches (the faces 0.5 mm apart): no stuck nor sliding point, zero loads
    layup = Layup(
        PLY, (0.0, 45.0), 40.0, cells=4, rule="gauss", faces="normal", surface="curved",
        penalty=100.0, friction=MU,
    )  # fmt: skip
    block = layup.model().compile().interactions[0]
    state = _on_sphere(layup, -0.5)
    assert not block.facing(state).touching.any()
    force, moment = block.internal_force(state, block.initial_history())
    assert not np.any(force) and not np.any(moment)


def _local(stuck_only: bool = False):
    """The frictional points' local data and arguments (stuck and sliding, on the 0.05-mm
    ramp and deeper), real and with a complex step on every column in turn."""
    block, state, history = _anchored("normal", smoothing=0.05, stuck_only=stuck_only)
    sliding = block.friction_state(state, history)
    facing = block.facing(state)
    surface = ply_curved_tangent.surface_normals(block, state)
    _, _, _, _, data, arguments = ply_curved_friction._frictional_points(
        block, state, sliding, history, facing, surface
    )
    size = data.shape[1]
    stepped = np.repeat(data, size, axis=0).astype(complex)
    stepped[np.arange(len(stepped)), np.tile(np.arange(size), len(data))] += 1j * 1e-30
    repeated = tuple(np.repeat(a, size, axis=0) for a in arguments)
    return block, data, arguments, stepped, repeated


def _compiled_and_reference(block, data, arguments):
    compiled = ply_curved_friction_kernels.local_loads(
        data, *arguments, block.smoothing, block.friction, block.stick == "penalty",
        ply_curved_friction.STEPS,
    )  # fmt: skip
    return compiled, ply_curved_friction.local_loads_numpy(block, data, *arguments)


def test_the_compiled_local_loads_are_the_references():
    """The compiled pass against ``local_loads_numpy``, real and at every complex step:
    within 1e-12 of the largest load and of the largest derivative (the order of the sums
    and the closed-form 2 x 2 solves; measured 6e-17 and 7e-16)."""
    block, data, arguments, stepped, repeated = _local()
    compiled, reference = _compiled_and_reference(block, data, arguments)
    np.testing.assert_allclose(compiled, reference, atol=1e-12 * np.abs(reference).max())
    compiled, reference = _compiled_and_reference(block, stepped, repeated)
    for part in ("real", "imag"):
        ours, theirs = getattr(compiled, part), getattr(reference, part)
        np.testing.assert_allclose(ours, theirs, atol=1e-12 * np.abs(theirs).max())


@pytest.mark.parallel
def test_the_compiled_local_loads_on_threads_are_the_ones_on_one():
    """Each point's row is its own: the pass on numba's threads gives the one-thread
    numbers to the bit."""
    import numba

    block, _, _, stepped, repeated = _local()
    threads = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        one = _compiled_and_reference(block, stepped, repeated)[0]
    finally:
        numba.set_num_threads(threads)
    assert np.array_equal(_compiled_and_reference(block, stepped, repeated)[0], one)


def test_the_compiled_local_loads_refuse_arrays_of_other_rows():
    block, data, arguments, _, _ = _local()
    with pytest.raises(ValueError, match="expected"):
        ply_curved_friction_kernels.local_loads(
            data[:-1], *arguments, block.smoothing, block.friction, False, 3
        )
    with pytest.raises(ValueError, match="steps"):
        ply_curved_friction_kernels.local_loads(
            data, *arguments, block.smoothing, block.friction, False, -1
        )


def test_the_numpy_path_gives_the_compiled_loads_and_tangent(monkeypatch):
    """With the ply kernels off the block's friction loads and tangent are the numpy
    reference's, within 1e-12 of the largest."""
    block, state, history = _anchored("normal", stuck_only=False)
    compiled = block.internal_force(state, history)[0]
    matrix = block.tangent(state, history)[1].matrix.toarray()
    monkeypatch.setattr(ply_projection, "COMPILED", False)
    block, state, history = _anchored("normal", stuck_only=False)
    reference = block.internal_force(state, history)[0]
    reference_matrix = block.tangent(state, history)[1].matrix.toarray()
    np.testing.assert_allclose(compiled, reference, atol=1e-12 * np.abs(reference).max())
    np.testing.assert_allclose(
        matrix, reference_matrix, atol=1e-12 * np.abs(reference_matrix).max()
    )


@pytest.mark.parametrize("faces", ["normal", "director"])
def test_the_curved_frictions_energies_and_sums_conform(faces):
    """The conformance kit's energy checks (stored energy and dissipation >= 0, an accepted
    step dissipating no negative energy, the history given left as it was) and the model's
    sum of the loads (``add_internal_force`` adds ``internal_force``'s to the bit), stuck and
    sliding."""
    block, state, history = _anchored(faces, stuck_only=False)
    check_energy(block, state, history)
    check_added_force(block, state, history)
