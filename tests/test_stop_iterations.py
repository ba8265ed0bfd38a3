"""What a Static increment that ran out of Newton iterations says (solvers/stop_diagnosis.py
``iterations_spent``): its last residual ratio, the iterations and the tolerance it was judged
against, and what would help: a larger max_iterations where the ratio was still falling, a
looser tol where it stalled just above the tolerance (the round-off of the forces at a stiff
penalty: a fibrous strip on a table at penalty 10 stopped at 5.74e-7 against tol 1e-8 with
"residual ratio 5.74e-07 after 50 iterations", the tolerance unsaid)."""

import numpy as np

from solvers.stop_diagnosis import RECENT, iterations_spent


def test_the_message_gives_the_ratio_the_iterations_and_the_tolerance():
    said = iterations_spent([0.9, 0.5, 0.993], 1e-8, 50)
    assert said == "residual ratio 0.993 after 50 iterations (tol 1e-08)"


def test_a_ratio_still_falling_names_max_iterations():
    falling = list(np.geomspace(1.0, 1e-5, 50))
    said = iterations_spent(falling, 1e-8, 50)
    assert "still falling: raise max_iterations (it was 50)" in said


def test_a_ratio_stalled_just_above_the_tolerance_is_round_off():
    stalled = list(np.geomspace(1.0, 5.74e-7, 20)) + [5.74e-7] * 30
    said = iterations_spent(stalled, 1e-8, 50)
    assert "(tol 1e-08)" in said
    assert "round-off" in said and "a looser tol, e.g. 1e-06" in said


def test_a_ratio_stalled_far_above_the_tolerance_gets_no_remedy_here():
    # nor one ahead of the contacts' and the limit point's hints (stop_hint) that follow it
    stalled = [0.993] * (RECENT + 5)
    assert iterations_spent(stalled, 1e-8, 50).endswith("(tol 1e-08)")


def test_an_attempt_still_searching_its_contact_sets_names_max_iterations():
    # The table strip at the automatic penalty: three frozen sets found wrong, then the
    # unilateral law's lift-off front moving a node per iteration, the ratio near 1 when the
    # 50 iterations ran out (it converges at 61); cuts do not shorten the search.
    searching = [1.0, 1.4e-5, 1.0, 1.9e-7] + [0.99] * 46
    said = iterations_spent(searching, 1e-8, 50, searching=True)
    assert "unilateral contact law, whose sets may still have been changing" in said
    assert said.endswith("raise max_iterations (it was 50)")
    assert "unilateral" not in iterations_spent(searching, 1e-8, 50)


def test_a_short_attempt_still_falling_names_max_iterations():
    # three iterations from 1 to 0.00135 (the strip below): falling, however few
    said = iterations_spent([1.0, 0.2, 0.02, 0.00135], 1e-8, 3)
    assert said.endswith("still falling: raise max_iterations (it was 3)")


STRIP = """
title = "G1151 strip under its own weight"
[mesh]
rectangle = { lx = 200.0, ly = 60.0, nx = 8, ny = 2 }
[[part]]
element = "fibrous"
material = "g1151_laminate"
options = { clamped = "left" }
[[fix]]
nodes = "left"
[gravity]
acceleration = [0.0, 0.0, -9810.0]
[solver]
kind = "static"
increments = 2
max_iterations = 3
max_cuts = 1
"""


def test_a_static_stop_at_the_iteration_cap_names_it_not_a_limit_point(tmp_path, capsys):
    """The cantilevered strip converges in more than 3 iterations an increment: capped at 3,
    its ratio still falling, the stop names max_iterations and says the cap stopped it
    (before: "A limit point or buckling may be near: try path='arc_length'", which sends a
    user the wrong way)."""
    from fibreshell.cli import main

    case = tmp_path / "strip.toml"
    case.write_text(STRIP)
    assert main(["run", str(case), "--out", str(tmp_path / "out"), "--quiet"]) == 1
    said = capsys.readouterr().out
    assert "still falling: raise max_iterations (it was 3)" in said
    assert "The iteration cap stopped it, not a limit point" in said
    assert "may be near" not in said and "arc_length" not in said
