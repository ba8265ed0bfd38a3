"""Run one of Bai's specimens with three kinematics and collect what the paper's figures show.

A ``PaperCase`` names a specimen (validation.specimens), a fabric, the imposed displacement and
the resolution table. ``compute_paper_case`` builds three models on the same mesh (``KINEMATICS``:
the fibrous shell with the thickness along the director from the nodal normals, its default;
the fibrous shell with Bai's Eq. 15, each element's own normal; the Mindlin shell), solves each
with ``Static`` along the arc length of the path (load steps past a limit point), and
returns the report's ``Outcome``: per kinematics the solver, its iterations and time, and along
side 1 and side 2 the mid-surface, the director angle to the horizontal, the thickness along the
director, the mid-surface rotation from the clamp and the director's tilt from the normal; the
checks of the invariants; a paragraph on what the director angle and the thickness mean for each
kinematics, with the run's numbers. ``render_paper_case`` then draws the figures (side profiles
like Bai Fig. 10/12/14/16, a 3D view with the director segments drawn along the sides like the
lines on the specimens) and writes the VTU and XDMF files of the three runs.
``PaperCase.case`` binds the two into the ``Case`` record of the module.

Modules, one concern each:

- ``kinematics``: the three models' keys, elements, labels, colours and check names, and how
  the Mindlin shell's calibration is stated;
- ``case``: ``PaperCase``, ``corner_case``, ``solve``, ``compute_paper_case``,
  ``render_paper_case``;
- ``profiles``: the measurements along the sides (``side_data``, ``key_numbers``,
  ``slip_errors``, ``fibre_statistics``);
- ``invariants``: Bai's claims as checks (``invariant_checks``, ``slip_checks``);
- ``orders``: the observed orders of the reported quantities on three meshes
  (``order_quantities``, ``mesh_size``, ``observed_orders``, ``order_checks``);
- ``discussion``: the report's paragraph on the run;
- ``figures``: the side profiles, the side elevation, the fabric's laws and the 3D view.
"""

from validation.paper.case import (
    PaperCase,
    PaperRuns,
    compute_paper_case,
    corner_case,
    render_paper_case,
    solve,
)
from validation.paper.discussion import discussion
from validation.paper.figures import laws_figure, side_elevation, side_figure, view_3d
from validation.paper.invariants import EQ15_TOLERANCE_DEG, invariant_checks, slip_checks
from validation.paper.kinematics import (
    ARC_CHORDS,
    CHECK_NAMES,
    COLOURS,
    ELEMENT,
    FIBROUS_THICKNESS,
    INCREMENTS,
    KINEMATICS,
    LABELS,
    MARKERS,
    PAPER,
    Kinematics,
    calibration_parameters,
    calibration_title,
)
from validation.paper.orders import (
    ORDER_KINEMATICS,
    deflection_name,
    mesh_size,
    observed_orders,
    order_checks,
    order_kind,
    order_quantities,
    thickness_name,
)
from validation.paper.profiles import fibre_statistics, key_numbers, side_data, slip_errors

__all__ = [
    "ARC_CHORDS",
    "CHECK_NAMES",
    "COLOURS",
    "ELEMENT",
    "EQ15_TOLERANCE_DEG",
    "FIBROUS_THICKNESS",
    "INCREMENTS",
    "KINEMATICS",
    "LABELS",
    "MARKERS",
    "ORDER_KINEMATICS",
    "PAPER",
    "PaperCase",
    "PaperRuns",
    "Kinematics",
    "calibration_parameters",
    "calibration_title",
    "compute_paper_case",
    "corner_case",
    "deflection_name",
    "discussion",
    "fibre_statistics",
    "invariant_checks",
    "key_numbers",
    "laws_figure",
    "mesh_size",
    "observed_orders",
    "order_checks",
    "order_kind",
    "order_quantities",
    "render_paper_case",
    "side_data",
    "side_elevation",
    "side_figure",
    "slip_checks",
    "slip_errors",
    "solve",
    "thickness_name",
    "view_3d",
]
