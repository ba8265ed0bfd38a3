"""A dynamic relaxation killed between increments resumes from its checkpoint to the same final
state, bit for bit, as a run never interrupted."""

import textwrap

import numpy as np
import pytest
from kill_helpers import kill_when

from solvers import DynamicRelaxation
from solvers.output import load_checkpoint

# A short thick Mindlin strip (length 10 thicknesses) rolled into a quarter circle by an end
# moment, in four increments of 400-650 iterations each (a second or two).
STRIP = textwrap.dedent(
    """
    import math
    from validation import specimens

    def rolled_strip():
        mesh, model = specimens.mindlin_strip(40.0, 8.0, 4.0, 70e3, cells=4)
        moment = 0.5 * math.pi * 70e3 * (8.0 * 4.0**3 / 12) / 40.0
        tip = mesh.nodes("right")
        model.moment(tip, (0.0, -moment / len(tip), 0.0), amplitude="linear")
        return model
    """
)
namespace: dict = {}
exec(STRIP, namespace)
rolled_strip = namespace["rolled_strip"]


@pytest.mark.slow
def test_a_relaxation_killed_halfway_resumes_to_the_same_state_bit_for_bit(tmp_path):
    checkpoint = tmp_path / "relax.ckpt"
    script = tmp_path / "run.py"
    script.write_text(
        STRIP
        + textwrap.dedent(
            f"""
            from solvers import DynamicRelaxation
            DynamicRelaxation(increments=4, progress=False).solve(
                rolled_strip(), checkpoint={str(checkpoint)!r}
            )
            """
        )
    )
    kill_when(script, checkpoint, lambda payload: payload["increment"] >= 2, 300.0)
    assert load_checkpoint(checkpoint)["increment"] < 4, "killed too late to resume anything"

    resumed = DynamicRelaxation(increments=4, progress=False).solve(
        rolled_strip(), checkpoint=checkpoint
    )
    reference = DynamicRelaxation(increments=4, progress=False).solve(rolled_strip())
    assert resumed.converged
    np.testing.assert_array_equal(resumed.positions, reference.positions)
    np.testing.assert_array_equal(resumed.directors, reference.directors)
    assert resumed.info["iterations_per_increment"] == reference.info["iterations_per_increment"]
    assert len(resumed.frames) == len(reference.frames) == 5


def test_a_relaxation_checkpoint_without_a_fingerprint_is_refused(tmp_path):
    from solvers.output import save_checkpoint

    checkpoint = tmp_path / "relax.ckpt"
    save_checkpoint(checkpoint, {"signature": ("something else",)})
    with pytest.raises(ValueError, match="another version .* fingerprint of its model"):
        DynamicRelaxation(increments=4, progress=False).solve(rolled_strip(), checkpoint=checkpoint)
