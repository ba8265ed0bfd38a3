"""Generic finite-element core: mesh, topology, DOFs, assembly, model, state, results.

femcore knows nothing of fabrics or of any particular element; element types plug in through
the protocol of elements.base.
"""

from femcore.dofs import DOF_NAMES, DofManager
from femcore.mesh import Mesh
from femcore.model import CompiledModel, Model
from femcore.results import Frame, Result
from femcore.state import State

__all__ = ["DOF_NAMES", "CompiledModel", "DofManager", "Frame", "Mesh", "Model", "Result", "State"]
