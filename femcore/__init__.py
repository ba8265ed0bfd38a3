"""Generic finite-element core: mesh, topology, DOFs, assembly, model, state, results.

femcore knows nothing of fabrics or of any particular element; element types plug in through
the element protocol (femcore.element, gathered for element writers in elements.base), and
what acts between bodies and tools through the interaction protocol (femcore.interaction).
"""

from femcore.dofs import DOF_NAMES, DofManager
from femcore.interaction import Body, Interaction, InteractionBlock
from femcore.mesh import Mesh
from femcore.model import CompiledModel, Model
from femcore.results import Frame, Result
from femcore.state import State

__all__ = [
    "DOF_NAMES", "Body", "CompiledModel", "DofManager", "Frame", "Interaction",
    "InteractionBlock", "Mesh", "Model", "Result", "State",
]  # fmt: skip
