"""Dynamic relaxation's count of halvings (``info["cuts"]``) and of iterations (``steps``)
survive its stops and its checkpoints (solvers/relaxation_cuts.py, docs/theory.md §6.4d): a
resumed run reads the same as the run never interrupted, and a stop's ``error.result`` counts
every part of the increment it stopped in."""

import numpy as np
import pytest

import solvers.relaxation as relaxation
from solvers import ConvergenceError, DynamicRelaxation
from solvers.relaxation_cuts import InvalidState, relax_in_halves
from tests.test_relaxation_acceptance import strip_held_for_a_pull


def all_in_the_first_half(tau):
    """The amplitude that reaches the whole pull at load factor 0.5 (the first of two
    increments) and holds it."""
    return np.minimum(1.0, 2.0 * np.asarray(tau, dtype=float))


def pulled_strip():
    """A 40 x 10 mm fibrous strip (4 x 1 cells, linear tension 10 N/mm) pulled along its
    warp to 2.5 times its length in the first of two increments: a jump of its end node far
    past the law's peak (lambda = e), which relaxation halves (2 halvings, 1 s)."""
    _, model = strip_held_for_a_pull()
    model.displace("right", ux=1.5 * 40.0, amplitude=all_in_the_first_half)
    return model


class Killed(Exception):
    """The run killed just after its first checkpoint was written."""


def test_a_resume_after_a_cut_counts_the_same_cuts_and_steps(tmp_path, monkeypatch):
    # Before: cuts was counted afresh after a resume (0 against the uninterrupted run's).
    reference = DynamicRelaxation(increments=2, progress=False).solve(pulled_strip())
    assert reference.converged and reference.info["cuts"] == 2
    assert reference.info["iterations_per_increment"][1] <= 1  # nothing moves in the second
    # its uniform stretch 2.5: the reaction b C ln(lambda) / lambda (docs/theory.md §2.3)
    # to the relaxation's tol of 1e-4, with room for the 4-cell strip's ends
    assert reference.frames[-1].reactions[:, 0].max() * 2 == pytest.approx(
        10.0 * 10.0 * np.log(2.5) / 2.5, rel=1e-3
    )

    saved = relaxation.save_checkpoint

    def save_then_die(path, payload):
        saved(path, payload)
        raise Killed

    checkpoint = tmp_path / "relax.ckpt"
    monkeypatch.setattr(relaxation, "save_checkpoint", save_then_die)
    with pytest.raises(Killed):
        DynamicRelaxation(increments=2, progress=False).solve(pulled_strip(), checkpoint=checkpoint)
    monkeypatch.setattr(relaxation, "save_checkpoint", saved)
    resumed = DynamicRelaxation(increments=2, progress=False).solve(
        pulled_strip(), checkpoint=checkpoint
    )
    assert resumed.info["cuts"] == reference.info["cuts"]
    assert resumed.steps == reference.steps
    np.testing.assert_array_equal(resumed.positions, reference.positions)


def test_a_stop_in_a_later_part_counts_the_earlier_parts():
    # A fake relaxation: the whole increment fails acceptance after 7 iterations, its first
    # half passes in 10, the second half runs out of iterations after 3. Before: the stop
    # carried 3 steps and no cuts.
    calls = []

    def relax(state, level):
        calls.append(level)
        if level == 1.0 and len(calls) == 1:
            raise InvalidState("too far", 7)
        if level == 1.0:
            raise ConvergenceError("ran out", None, steps=3)
        return state, 10, 0.0, None, None

    start = pulled_strip().compile().initial_state()
    with pytest.raises(ConvergenceError) as stop:
        relax_in_halves(relax, start, 0.0, 1.0, 1)
    assert calls == [1.0, 0.5, 1.0]
    assert stop.value.steps == 7 + 10 + 3 and stop.value.cuts == 1


def test_a_stopped_relaxation_reports_its_cuts():
    # Stopped by its iteration limit in the first increment: error.result says how many
    # halvings were made (none) beside its steps. Before: no "cuts" in error.result.info.
    solver = DynamicRelaxation(increments=2, max_iterations=5, progress=False)
    with pytest.raises(ConvergenceError, match="within 5 iterations") as stop:
        solver.solve(pulled_strip())
    assert stop.value.result.info["cuts"] == 0 and stop.value.result.steps == 5
