"""Element types that plug into the femcore model (protocol in elements.base)."""

from elements.annulus import RigidAnnulus
from elements.base import ElementBlock, ElementType
from elements.cable import Cable
from elements.contact import Contact
from elements.fibre_bending import FibreBending
from elements.fibrous import FibrousShell
from elements.grip import Grip
from elements.mindlin import MindlinShell
from elements.rigid_surface import RigidSurface
from elements.tools import RigidCylinder, RigidPlane, RigidSphere

__all__ = [
    "Cable", "Contact", "ElementBlock", "ElementType", "FibreBending", "FibrousShell", "Grip",
    "MindlinShell", "RigidAnnulus", "RigidCylinder", "RigidPlane", "RigidSphere", "RigidSurface",
]  # fmt: skip
