"""A diverged explicit run leaves no checkpoint past its last good state: its outputs are cut
back to that state, and a checkpoint of a later one (a save comes every 10 steps, before the
step whose check fails) would resume from a state the checks refused. A resume of a diverged
run is refused saying so."""

import json

import pytest
from test_explicit import TRANSIT, N, bar_model
from test_interrupts import CASE

from fibreshell.case import load_case
from fibreshell.cli import main
from fibreshell.run import run_case
from solvers import CentralDifference, DivergenceError
from solvers.output import load_checkpoint


def test_a_diverged_run_keeps_no_checkpoint_past_its_last_good_state(tmp_path):
    # The bar of tests/test_explicit.py at 1.01 x its critical step L_e / c: the error grows
    # slowly, the run passes its checks at step 10 and fails one later (measured: at step 30)
    # with a checkpoint written every 10 steps.
    checkpoint = tmp_path / "run.ckpt"
    solver = CentralDifference(duration=5 * TRANSIT, dt=1.01 * TRANSIT / N, progress=False)
    with pytest.raises(DivergenceError, match="diverged") as stop:
        solver.solve(bar_model(), checkpoint=checkpoint, checkpoint_interval=0.0)
    good_time = stop.value.result.frames[-1].time
    assert good_time > 0.0  # a good state past the start, so a checkpoint could be kept
    if checkpoint.exists():
        payload = load_checkpoint(checkpoint)
        assert payload is not None
        assert payload["run"].state.time <= good_time
    else:
        assert "was removed" in str(stop.value)


def test_fibreshell_run_of_a_diverged_case_names_no_checkpoint_and_refuses_to_resume(
    tmp_path, capsys
):
    # The falling cantilever of tests/test_interrupts.py at dt = 1.65e-5 s, 1.5 x the step
    # the solver would take (9.89e-6 s at safety 0.9, measured): it diverges at step 30
    # (measured), its last good state at step 20.
    case = tmp_path / "case.toml"
    case.write_text(
        CASE.replace("damping = 100.0", "damping = 100.0\ndt = 1.65e-5\ncheckpoint_interval = 0.0")
    )
    out = tmp_path / "out"
    ran = run_case(load_case(case), out, progress=False)
    assert ran.status == "stopped" and "diverged" in ran.error
    summary = json.loads((out / "summary.json").read_text())
    assert summary["checkpoint"] is None and ran.checkpoint is None
    assert not (out / "checkpoint.pkl").exists()
    capsys.readouterr()
    assert main(["run", str(case), "--out", str(out), "--resume", "--quiet"]) == 2
    said = capsys.readouterr().err
    assert "diverged" in said and "would diverge again" in said
