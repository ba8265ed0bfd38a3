"""A ply contact whose plies never face each other at the start is said when the model is
compiled (elements/ply_start.py ``_say_none_faces``): its contact would act only if the plies
came to face each other, which a ply laid beside the other by a typo never does."""

from __future__ import annotations

import warnings

import pytest

from elements.layup import Layup
from materials import Fabric

PLY = Fabric(thickness=0.3, areal_density=2.85e-10, tension=60.0, shear=0.2, bending=0.375)


def _shifted(shift):
    layup = Layup(PLY, (0.0, 90.0), 40.0, cells=2)
    moved = layup.mesh.points.copy()
    moved[layup.ply_nodes[1]] += shift
    layup.mesh = layup.mesh.with_points(moved)
    return layup.model()


def test_a_top_ply_laid_beside_the_bottom_one_is_said():
    with pytest.warns(UserWarning, match="no contact point of the upper ply faces the lower"):
        _shifted((100.0, 0.0, 0.0)).compile()


@pytest.mark.parametrize("shift", [(0.0, 0.0, 0.0), (30.0, 0.0, 0.0), (0.0, 0.0, 5.0)],
                         ids=["laid-on", "overhanging-by-three-quarters", "above"])  # fmt: skip
def test_plies_that_face_each_other_somewhere_start_silently(shift):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _shifted(shift).compile()
