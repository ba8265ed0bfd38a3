"""Static at a trial state where an element cannot be evaluated (a node's normal sum
vanishes): the trial is rejected, the run goes on.

The bias specimen of tests/test_bias_extension.py pulled by a force of 20 N on its free end
instead of a displacement: a chord correction's trial (solvers/newton.py
``chord_corrections``) has a node whose normal sum S vanishes: the fibrous shell's nodal
normal S / |S| is not defined there. That trial's energy is inf (StaticRun.energy), so the
chord is not taken; a Newton iterate there fails its increment (IncrementFailed), which is
cut as any other."""

from __future__ import annotations

import numpy as np
from test_bias_extension import LENGTH, LINEAR, bias_specimen

from solvers import Static

FORCE = 20.0  # N


def test_a_trial_with_a_vanished_normal_is_rejected_and_the_pull_converges():
    mesh, model = bias_specimen(LINEAR, pull=None)
    right = np.asarray(mesh.node_sets["right"])
    model.force("right", (FORCE / len(right), 0.0, 0.0))
    result = Static(increments=4, seek_stable=False, progress=False).solve(model)
    assert result.converged
    # the pulled end moves along the pull (a ZeroDivisionError from the fibrous kernels before)
    assert result.positions[right, 0].mean() > LENGTH
