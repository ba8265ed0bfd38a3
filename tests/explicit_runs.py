"""A model run by the explicit step alone, each step committed: the landing and departure
tests' runs (tests/test_contact_landing.py, test_contact_departure.py, test_ply_landing.py,
test_ply_departure.py), where the records of every accepted step are what is checked."""

from __future__ import annotations

from solvers.step import LumpedMasses, explicit_step


def run_explicitly(model, steps: int, duration: float):
    """(the compiled model, its state at the end): ``model`` run over ``duration`` s in
    ``steps`` explicit steps of duration / steps, each committed."""
    compiled = model.compile()
    state = compiled.initial_state()
    masses = LumpedMasses.of(compiled, state)
    previous, dt = 0.0, duration / steps
    for _ in range(steps):
        outcome = explicit_step(compiled, state, dt, masses, dt_prev=previous, duration=duration)
        state, previous = compiled.commit(outcome.state), dt
    return compiled, state
