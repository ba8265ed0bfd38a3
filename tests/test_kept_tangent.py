"""solvers.kept_tangent: the tangent of a converged state is assembled and factorised once, for
its stability and for the next increment's first Newton iteration, and given again only at the
very configuration it was made at."""

from types import SimpleNamespace

import numpy as np
import pytest

from femcore.state import State
from solvers import Static, kept_tangent
from solvers.kept_tangent import KeptTangent
from validation.references.elastica import tip_loaded_cantilever
from validation.specimens import mindlin_strip


def _elastica():
    """The mindlin-elastica case: a 100 x 5 x 1 mm strip of 20 cells, P L^2 / EI = 3; (model,
    tip nodes, the elastica's tip drop mm)."""
    length, bending = 100.0, 1e5 * 5.0 / 12.0
    mesh, model = mindlin_strip(length, 5.0, 1.0, 1e5, cells=20)
    tip = mesh.nodes("right")
    model.force(tip, (0.0, 0.0, -3.0 * bending / length**2 / len(tip)))
    drop = tip_loaded_cantilever(length, 3.0 * bending / length**2, bending)["tip_deflection"]
    return model, tip, drop


def test_a_converged_states_tangent_serves_its_stability_and_the_next_increment(monkeypatch):
    # Every Newton iteration forms a tangent, and every converged state one for its stability
    # (its inertia); without a predictor the next increment starts from that state, whose
    # tangent is the same matrix: of 5 increments the 4 later ones reuse it. The solve is the
    # same to the bit (the same matrix, the same factors) and the tip within the case's 1 % of
    # the elastica (Bisshopp & Drucker 1945).
    model, tip, drop = _elastica()
    compiled = model.compile()
    kept = Static(increments=5, progress=False).solve(compiled)
    iterations = sum(kept.info["iterations_per_increment"])
    assert kept.info["evaluations"]["stability_tangents"] == 5
    assert kept.info["evaluations"]["tangent"] == iterations - 4
    assert kept.info["tangents_reused"] == 4
    monkeypatch.setattr(kept_tangent, "REUSE", False)
    every = Static(increments=5, progress=False).solve(compiled)
    assert every.info["evaluations"]["tangent"] == iterations
    assert every.info["tangents_reused"] == 0
    assert np.array_equal(kept.positions, every.positions)
    assert np.array_equal(kept.directors, every.directors)
    assert -kept.displacements[tip, 2].mean() == pytest.approx(drop, rel=1e-2)


def test_the_predictor_starts_elsewhere_and_reuses_nothing():
    # An extrapolated start is not the converged state: its tangent is assembled.
    model, _, _ = _elastica()
    result = Static(increments=5, predictor=True, progress=False).solve(model)
    assert result.info["tangents_reused"] == 0


def _state(n=4, load_factor=0.5, history=(None,)):
    rng = np.random.default_rng(0)
    directors = np.tile([0.0, 0.0, 1.0], (n, 1))
    return State(
        rng.normal(size=(n, 3)), directors, np.zeros((n, 3)), np.zeros((n, 3)), 0.0,
        load_factor, history,
    )  # fmt: skip


def _frames(n=4):
    return np.tile([1.0, 0.0, 0.0], (n, 1)), np.tile([0.0, 1.0, 0.0], (n, 1))


def _kept(interactions=()):
    kept = KeptTangent(SimpleNamespace(interactions=list(interactions)))
    state, frames = _state(), _frames()
    kept.keep(state, frames, "K_ff", "K_fp")
    return kept, state, frames


def test_the_kept_tangent_is_given_at_its_own_configuration_only():
    kept, state, frames = _kept()
    assert kept.at(state, frames) == ("K_ff", "K_fp")
    # the same values in other arrays: the same configuration
    copy = State(
        state.positions.copy(), state.directors.copy(), state.velocities, state.angular_velocities,
        state.time, state.load_factor, state.history,
    )  # fmt: skip
    assert kept.at(copy, (frames[0].copy(), frames[1].copy())) == ("K_ff", "K_fp")
    # a node moved in place (a State's arrays are mutable)
    state.positions[2, 0] += 1e-12
    assert kept.at(state, frames) is None


def test_other_frames_history_or_dashpots_get_no_kept_tangent():
    kept, state, frames = _kept()
    turned = (frames[1].copy(), frames[0].copy())
    assert kept.at(state, turned) is None
    renewed = State(
        state.positions, state.directors, state.velocities, state.angular_velocities,
        state.time, state.load_factor, (object(),),
    )  # fmt: skip
    assert kept.at(renewed, frames) is None
    assert kept.at(state, frames, dashpots=object()) is None
    kept.keep(state, frames, "K_ff", "K_fp", dashpots=object())  # an increment's own diagonal
    assert kept.at(state, frames) is None


def test_a_model_with_interactions_keeps_nothing():
    # Their tangent depends on more than the state: tools placed by the load factor, and
    # penalties the load path changes in place (the soft start of solvers/penalty_start.py).
    kept, state, frames = _kept(interactions=[object()])
    assert kept.at(state, frames) is None


def test_the_load_factor_alone_does_not_change_the_element_blocks_tangent():
    plain, state, frames = _kept()
    later = State(
        state.positions, state.directors, state.velocities, state.angular_velocities,
        state.time, 0.75, state.history,
    )  # fmt: skip
    assert plain.at(later, frames) == ("K_ff", "K_fp")
