"""The ply contact's tangent lists only the nodes each contact point acts on.

A point's fade past the lower ply's outline moves with the ends of the outline's edge nearest
it (elements/ply_fade.py), so the tangent's rows carry those two nodes; where the fade is 1
(off the outline's band, or no nearest edge computed) its gradient is 0 and the point does not
act on them. The outline's first edge stood in there, in the friction tangent's rows (a zero
block): on the model below (gauss rule) 15 of the 29 touching points tied to two far nodes,
the node graph's nonzeros 246 against 208 and its reverse Cuthill-McKee bandwidth 13 against
11; on a large ply those two nodes touched every frictional point and widened the band the
solver factorises.

Reference: the tangent's own blocks. A node a row lists carries a block that is not all zero
in that row (the node graph of the listed nodes is that of the nonzero blocks), exactly: the
blocks of a node a point acts on are products of the gap's and the fade's gradients and
shape functions that vanish only on sets of measure zero (the Gauss and centroid rules'
shape functions are all positive; the vertex rule's vanish by construction and is left out).
The model: tests/test_interaction_conformance.py's two jittered plies with friction, the upper
ply's points and the mirrored pass at the lower ply's nodes (whose outline points touch in the
fade).
"""

import numpy as np
import pytest

from tests.test_interaction_conformance import plies_with_friction


@pytest.mark.parametrize("rule", ["gauss", "centroid"])
@pytest.mark.parametrize("points", ["upper", "lower"])
def test_every_node_a_tangent_row_lists_carries_a_block(rule, points):
    block, state, history = plies_with_friction(rule=rule, points=points)
    parts = block.tangent(state, history)
    assert len(parts) >= 2  # the contact's and the friction's (and the fade's where it moves)
    for part in parts:
        acting = np.any(part.blocks != 0.0, axis=(1, 2, 4))  # (t, nodes): a nonzero column
        for row in range(len(part.nodes)):  # a check over the few rows of a test model
            listed = set(part.nodes[row].tolist())
            assert listed == set(part.nodes[row][acting[row]].tolist()), (
                f"row {row} of a part over {part.nodes.shape[1]} nodes lists "
                f"{sorted(listed - set(part.nodes[row][acting[row]].tolist()))} with zero blocks"
            )
