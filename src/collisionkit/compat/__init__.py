"""Drop-in interfaces that match other packages' collision APIs (``collisionkit.compat.irfpy``)."""

from . import irfpy

__all__ = ["irfpy"]
