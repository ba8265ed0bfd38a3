"""Validation cases: one module each, stating its source, geometry, parameters and checks.

Every module defines NAME, TITLE, SOURCE and ``run(resolution, out_dir) -> dict`` with the keys
converged, wall_time_s, steps, solver, parameters, checks, figures (file names in out_dir).
"""

from validation.cases import (
    bai_5_1,
    bai_6_1_1,
    bai_6_1_2,
    bai_6_2_1,
    bai_6_2_2,
    bai_sensitivity,
    bar_wave,
    catenary,
    elastic_catenary,
    fibrous_curvature,
    fibrous_heavy_cantilever,
    mindlin_elastica,
    mindlin_pinched_cylinder,
    mindlin_plate,
    mindlin_rollup,
    mindlin_scordelis_lo,
)

RESOLUTIONS = ("coarse", "default", "fine")
PAPER_CASES = (bai_5_1, bai_6_1_1, bai_6_1_2, bai_6_2_1, bai_6_2_2)
SENSITIVITY_CASES = (bai_sensitivity,)
VERIFICATION_CASES = (
    catenary,
    elastic_catenary,
    bar_wave,
    fibrous_curvature,
    fibrous_heavy_cantilever,
    mindlin_elastica,
    mindlin_rollup,
    mindlin_plate,
    mindlin_scordelis_lo,
    mindlin_pinched_cylinder,
)
CASES = {module.NAME: module for module in (*PAPER_CASES, *SENSITIVITY_CASES, *VERIFICATION_CASES)}

__all__ = ["CASES", "PAPER_CASES", "RESOLUTIONS", "VERIFICATION_CASES"]
