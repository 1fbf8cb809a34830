"""Packages that import their modules on first use (PEP 562), so ``illusio --help`` and reading a
technique's Params defaults do not load numba and the passes."""

from __future__ import annotations

import importlib
from typing import Any

__all__ = ["lazy_exports", "load"]


def load(reference: str) -> Any:
    """The object a ``"package.module:attribute"`` string names, imported when asked for: how a
    lower layer reaches one above it without importing it (the registry's renderers, batch's app)."""
    module, _, attribute = reference.partition(":")
    if not module or not attribute:
        raise ValueError(f"a reference is 'module:attribute', got {reference!r}")
    return getattr(importlib.import_module(module), attribute)


def lazy_exports(package: str, exports: dict[str, str]):
    """A module ``__getattr__`` (PEP 562) that imports ``package.MODULE`` on first use of a name
    listed in ``exports`` (name -> module), so a package's ``__init__`` loads nothing heavy."""

    def __getattr__(name: str):
        if name in exports:
            return getattr(importlib.import_module(f".{exports[name]}", package), name)
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    return __getattr__
