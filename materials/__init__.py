"""Material laws, as pure functions over arrays: the fabric of the fibrous shell and its 1-D
tension, shear and bending laws; presets of the paper's materials in ``materials.presets``."""

from materials import presets
from materials.elastic import ElasticShell
from materials.fabric import Fabric
from materials.laws import BendingLaw, Law, ShearLaw, TensionLaw

__all__ = ["BendingLaw", "ElasticShell", "Fabric", "Law", "ShearLaw", "TensionLaw", "presets"]
