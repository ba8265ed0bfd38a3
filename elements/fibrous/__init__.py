"""FibrousShell: the 3-node continuum-based shell for fibrous reinforcements of Bai, Colmars,
Naouar and Boisse, Composites Part A 139 (2020) 106135 (equation numbers below are Bai's;
section numbers refer to docs/theory.md).

Kinematics (§1): x(xi, eta, zeta) = sum N_k x_k + zeta/2 sum N_k h_m^k V_k (Eq. 5), directors V
free to rotate (fibre slip), thickness along the director h_m = h / (V . n) so that the
thickness along the normal is conserved (Eq. 10, 14). The normal n at node k is the
angle-weighted nodal normal of the block (default, ``thickness="nodal"``, §1.4: one h_m per
node, so a director that stays put while the surface bends stretches the fibres, and the
directors tilt by atan(theta) as a deck of cards does) or, as Bai Eq. 15 writes, the normal of
each element (``thickness="element"``: parallel directors are then strain-free at any
curvature). Warp runs along local edge 1-2 and weft along 1-3 (Eq. 9). The virtual work has
three parts:

* tension (Eq. 19, 24-29, §2): fibres at ``levels`` positions zeta_f through the thickness, log
  strain, T(eps) per unit width, delta W = A0 sum_f w_f sum_alpha T delta eps;
* in-plane shear (Eq. 21, 30-33, §3): the warp-weft angle change gamma at each level,
  delta W = A0 sum_f w_f M_s(gamma) delta gamma;
* rotation-free bending (Eq. 20, 34-37, §4): warp and weft curvatures of each element from the
  fold angles with its three neighbours, delta W = A0 sum_alpha M_alpha delta chi_alpha.

Everything is vectorised over the cells of a block; the reference geometry, the neighbour
tables and the fibre orientation of each triangle are computed once, at ``bind``.
Local nodes 1, 2, 3 of the paper are columns 0, 1, 2 here.

The package, one concern per module:

* element.py: the FibrousShell type (fabric, options, ``bind``) and ``lobatto_levels``;
* block.py: FibrousShellBlock, the tables fixed at bind and the element protocol;
* fibres.py: the fibre frame of each cell (Eq. 9) and the shear sign;
* fibre_kernels.py: the same frame and signs by compiled loops, for the build of large blocks;
* geometry.py: normals, nodal normals, thickness along the directors (Eq. 10, 14, 15), the
  fibre vectors of the levels (Eq. 5, 8);
* membrane.py: tension and in-plane shear at the levels (Eq. 19, 21, 24-33);
* bending.py: rotation-free bending from the neighbouring elements (Eq. 20, 34-37) and its
  stiffness;
* fold_branch.py: each side's fold angle followed through a flat fold (whole turns, §4.2);
* supports.py: clamped sides, held cells and wall normals (docs/theory.md §4.5);
* symmetry.py: symmetry planes, sides that bend against their cells' mirror images (§4.5);
* tangent.py: the analytic tangent of tension and shear, the membrane Hessian included;
* tangent_pieces.py: the same tangent a run of rows at a time, for the explicit solver's bound;
* row_product.py: rows of the membrane's J^T H J and the bending patches added to them;
* tangent_kernels.py: the tangent's normal pulls, bending shares and J^T H J, compiled;
* hessian_kernels.py: the cells' tension + shear Hessians, compiled;
* kernels.py: the forces, energy and strains by compiled passes over cells and nodes (numba);
* geometry_kernels.py: those passes' geometry (normals, nodal sums, folds), compiled;
* cell_terms.py: the scalar pieces of a cell (edges, levers, a level's strains, folds) the
  compiled loops share;
* level_lanes.py: the fibre levels of a chunk of cells as vectorised loops across the cells;
* packed_laws.py: the material laws as arrays the compiled loops evaluate;
* level_jacobian.py: the exact derivatives of the levels' strains and shear angles (numpy),
  for the static solver's level projection;
* level_kernels.py: the same derivatives, compiled;
* stable_steps.py: the cells' critical time steps in one compiled pass;
* diagnostics.py: model-level views of the block tables (``thickness_along_directors``,
  ``side_tables``).
"""

from elements.fibrous.block import FibrousShellBlock
from elements.fibrous.diagnostics import side_tables, thickness_along_directors
from elements.fibrous.element import FibrousShell, lobatto_levels

__all__ = [
    "FibrousShell",
    "FibrousShellBlock",
    "lobatto_levels",
    "side_tables",
    "thickness_along_directors",
]
