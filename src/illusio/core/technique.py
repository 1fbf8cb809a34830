"""A technique as the rest of illusio sees it, and the one registry of them.

Each technique package holds a ``technique.py`` with its ``TECHNIQUES`` (most have one; sis has
the stereogram and the multi-scene pipeline), re-exported by the package. Everything that lists
techniques — the viewer's modes, the gallery's sections, ``illusio list``, the benchmark suites,
the contract tests — loops over :func:`techniques`. A descriptor names its code as
``"module:attribute"`` strings imported on first use, so reading the registry loads no renderer,
numba kernel or GL code; the ``illusio`` commands are built from it too (``commands``).

Adding a technique: see docs/architecture.md, "Adding a technique"."""

from __future__ import annotations

import importlib
from collections.abc import Callable
from dataclasses import dataclass

from .errors import InputError, did_you_mean
from .lazy import load

__all__ = ["Technique", "techniques", "technique", "register", "load"]

#: the packages whose ``technique.py`` the registry reads, in the order techniques are listed
#: (the viewer's Tab order)
BUILTIN_PACKAGES = (
    "illusio.passes",
    "illusio.sis",
    "illusio.lines",
    "illusio.dof",
    "illusio.ibr",
    "illusio.radiosity",
    "illusio.relight",
)


@dataclass(frozen=True)
class Technique:
    """One technique.

    name: what ``illusio list``, the gallery's ``--only`` and the registry call it; title: one line
    with the paper; renderer, params: the Renderer subclass and its Params ("module:Class");
    subject: "module:function", ``function(source: str, size: (w, h), ctx) -> the renderer's subject``
    — how a source string (a built-in name or a file) becomes what ``prepare`` takes, at a frame
    size (a depth map, captured references and a photograph are made at it; ctx draws them);
    source_kind: what a source names ("scene", "mesh", "hidden shape"...); default_source: the one
    used when none is given; presets: the named setups the viewer offers as its views (sis's tv,
    wall, interactive, raw); viewer_mode: "module:Class" of its mode in ``illusio view``; showcase:
    "module:function" of its gallery section (None: shown in another technique's); benchmarks: its
    suites under benchmarks/; needs: the optional package it cannot work without (e.g. "mitsuba");
    commands: its ``illusio`` commands as "name=module:attribute", the attribute a command function or
    a ``typer.Typer`` (a command group, as ``ibr``); a name of two words ("relight prepare") is a
    subcommand of a one-word command that also runs on its own (``illusio relight SCENE``)."""

    name: str
    title: str
    renderer: str
    params: str
    subject: str
    source_kind: str
    default_source: str
    presets: tuple[str, ...] = ()
    viewer_mode: str | None = None
    showcase: str | None = None
    benchmarks: tuple[str, ...] = ()
    needs: str | None = None
    commands: tuple[str, ...] = ()

    def renderer_class(self) -> type:
        return load(self.renderer)

    def params_class(self) -> type:
        return load(self.params)

    def make_subject(self, source: str | None = None, size: tuple[int, int] = (320, 240), ctx=None):
        """The renderer's subject for ``source`` (default: ``default_source``) at a frame ``size``;
        ``ctx`` draws what needs drawing (default: the process's headless context)."""
        if ctx is None:
            from .context import default_context

            ctx = default_context()
        return load(self.subject)(self.default_source if source is None else source, tuple(size), ctx)

    def command_targets(self) -> dict[str, str]:
        """Command name -> "module:attribute" of what runs it (a function, or a typer.Typer group)."""
        return dict(c.split("=", 1) for c in self.commands)

    def mode_class(self) -> type | None:
        return load(self.viewer_mode) if self.viewer_mode else None

    def showcase_function(self) -> Callable | None:
        return load(self.showcase) if self.showcase else None


_registry: dict[str, Technique] = {}
_loaded = [False]


def register(technique: Technique) -> Technique:
    """Add ``technique`` (a package outside illusio registers its own this way); a name is taken once."""
    _load_builtin()
    if technique.name in _registry and _registry[technique.name] != technique:
        raise ValueError(f"a technique named {technique.name!r} is registered already")
    _registry[technique.name] = technique
    return technique


def _load_builtin() -> None:
    if _loaded[0]:
        return
    _loaded[0] = True
    for package in BUILTIN_PACKAGES:
        for t in importlib.import_module(f"{package}.technique").TECHNIQUES:
            _registry[t.name] = t


def techniques() -> dict[str, Technique]:
    """Every registered technique by name, built-in ones first in BUILTIN_PACKAGES order."""
    _load_builtin()
    return dict(_registry)


def technique(name: str) -> Technique:
    """The technique called ``name``; InputError naming the choices (and the closest) otherwise."""
    known = techniques()
    if name not in known:
        raise InputError(f"no technique {name!r}; choose one of {', '.join(known)}{did_you_mean(name, known)}")
    return known[name]
