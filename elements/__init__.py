"""Element types that plug into the femcore model (protocol in elements.base)."""

from elements.base import ElementBlock, ElementType
from elements.cable import Cable
from elements.fibrous import FibrousShell
from elements.mindlin import MindlinShell

__all__ = ["Cable", "ElementBlock", "ElementType", "FibrousShell", "MindlinShell"]
