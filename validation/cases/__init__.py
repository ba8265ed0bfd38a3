"""Validation cases: one module each, stating its source, geometry, parameters and checks.

Every module defines NAME, TITLE, SOURCE and ``run(resolution, out_dir) -> dict`` with the keys
converged, wall_time_s, steps, solver, parameters, checks, figures (file names in out_dir).
"""

from validation.cases import bar_wave, catenary, elastic_catenary

RESOLUTIONS = ("coarse", "default", "fine")
CASES = {module.NAME: module for module in (catenary, elastic_catenary, bar_wave)}

__all__ = ["CASES", "RESOLUTIONS"]
