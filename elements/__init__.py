"""Element types that plug into the femcore model (protocol in elements.base)."""

from elements.base import ElementBlock, ElementType
from elements.cable import Cable

__all__ = ["Cable", "ElementBlock", "ElementType"]
