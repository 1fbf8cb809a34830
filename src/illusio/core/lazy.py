"""Packages that import their modules on first use (PEP 562), so ``illusio --help`` and reading a
technique's Params defaults do not load numba and the passes."""

from __future__ import annotations

import importlib
import sys
import types
from typing import Any

__all__ = ["lazy_exports", "load"]


def load(reference: str) -> Any:
    """The object a ``"package.module:attribute"`` string names, imported when asked for: how a
    lower layer reaches one above it without importing it (the registry's renderers, batch's app)."""
    module, _, attribute = reference.partition(":")
    if not module or not attribute:
        raise ValueError(f"a reference is 'module:attribute', got {reference!r}")
    return getattr(importlib.import_module(module), attribute)


class _Package(types.ModuleType):
    """A package whose export shares its name with the submodule defining it (``illusio.sis``'s
    ``stereogram``): importing the submodule sets the package's attribute to the module (Python's
    import system does), which would shadow the export — the one-shot ``stereogram()`` the docs
    show would be a module. The export is kept instead; the submodule stays in ``sys.modules``, and
    its names are imported from it by name (``from illusio.sis.stereogram import StereogramRenderer``;
    ``import illusio.sis.stereogram as m`` gives the export, as the package's attribute)."""

    def __setattr__(self, name: str, value) -> None:
        exports = self.__dict__.get("_lazy_exports", {})
        if (
            isinstance(value, types.ModuleType)
            and exports.get(name) == name
            and value.__name__ == f"{self.__name__}.{name}"
            and hasattr(value, name)
        ):
            value = getattr(value, name)
        super().__setattr__(name, value)


def lazy_exports(package: str, exports: dict[str, str]):
    """A module ``__getattr__`` (PEP 562) that imports ``package.MODULE`` on first use of a name
    listed in ``exports`` (name -> module), so a package's ``__init__`` loads nothing heavy. The
    package's ``dir()`` (tab completion, ``help()``) lists the exports, and an export named as its
    own submodule stays the export once that submodule is imported."""
    module = sys.modules[package]
    module._lazy_exports = dict(exports)
    module.__class__ = _Package

    def __getattr__(name: str):
        if name in exports:
            return getattr(importlib.import_module(f".{exports[name]}", package), name)
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    def __dir__():
        return sorted(set(module.__dict__) | set(exports))

    module.__dir__ = __dir__
    return __getattr__
