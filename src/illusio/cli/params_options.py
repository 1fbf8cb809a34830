"""Command-line options made from a Params class's declared fields.

A technique's parameters are stated once, in its Params (default, range, choices, unit, help; see
:func:`illusio.core.params.param`). A command asks for them by keyword and gets one instance::

    @params_options(params=DofParams)
    def dof(scene: str = typer.Argument(...), output: Path = ..., *, params: DofParams) -> None:
        ...

Every field a command shows (``cli`` metadata, by default the panel's) becomes an option: its
name with ``-`` for ``_`` unless its ``flag`` says otherwise, nested Params flattened (their fields'
own names; a clash between two fields is an error at import, caught by the tests); switches as
``--x/--no-x``; a tuple of choices as one comma-separated value. The help says the unit, range
and choices; --help lists them in panels by the fields' groups (core.params.GROUPS: the method,
the paper's parameters, the output, advanced), after the command's own options. A value is
checked against its field's metadata and refused by its flag (``--aperture = 600 mm is out of
range [0, 500]``) before the Params is made, so batch jobs (which run commands by their options)
and the panel (which reads the same metadata) see the same fields.
"""

from __future__ import annotations

import functools
import inspect
import re
import typing
from collections.abc import Callable

import typer

from ..core.options import OptionSpec, option_specs, params_from_options
from ..core.params import GROUPS

__all__ = ["OptionSpec", "option_specs", "params_options"]


_TYPES = {"float": float, "int": int, "bool": bool, "choice": str, "multi": str, "text": str}


def _help(spec: OptionSpec) -> str:
    info = spec.info
    text = info.help or info.label or info.name.replace("_", " ")
    if info.label and info.help and info.label not in info.help:
        text = f"{info.label}: {info.help}"
    extra = []
    if info.unit:
        extra.append(info.unit)
    if info.range is not None and spec.kind in ("int", "float"):
        extra.append(f"{_number(info.range[0])} to {_number(info.range[1])}")
    if info.choices:
        extra.append(
            ("comma-separated, of: " if spec.kind == "multi" else "one of ") + ", ".join(map(str, info.choices))
        )
    return text + (f" ({'; '.join(extra)})" if extra else "")


def _number(value: float) -> str:
    return str(int(value)) if float(value).is_integer() and abs(value) >= 1e5 else f"{value:g}"


def help_panel(params_class, group: str) -> str:
    """The --help panel an option is listed under: the Params' own title (its ``PANEL``, else its
    class name) and the field's group (core.params.GROUPS): "Radiosity: the paper's parameters"."""
    title = getattr(params_class, "PANEL", None) or re.sub(r"(?<!^)(?=[A-Z])", " ", params_class.__name__).removesuffix(
        " Params"
    )
    return f"{title}: {GROUPS[group]}"


def _option(spec: OptionSpec, panel: str | None = None) -> inspect.Parameter:
    default = ",".join(spec.default) if spec.kind == "multi" else spec.default
    # choices of numbers (a jet degree) keep their type
    numeric_choice = spec.kind == "choice" and not isinstance(default, str)
    default_type = type(default) if numeric_choice else _TYPES[spec.kind]
    option = typer.Option(
        default,
        *spec.flag.split("/") if spec.kind != "bool" else (spec.flag,),
        help=_help(spec),
        show_default=True,
        rich_help_panel=panel,
    )
    return inspect.Parameter(spec.name, inspect.Parameter.KEYWORD_ONLY, default=option, annotation=default_type)


def params_options(exclude: tuple[str, ...] = (), **classes) -> Callable:
    """Decorator: the command's keyword ``K`` (for each ``K=ParamsClass``) is made from generated
    options. ``exclude``: dotted paths ("params.stereogram.screen") the command sets itself."""

    def decorate(fn):
        hints = typing.get_type_hints(fn)
        signature = inspect.signature(fn)
        kept = [
            p.replace(annotation=hints.get(p.name, p.annotation))
            for p in signature.parameters.values()
            if p.name not in classes
        ]
        specs = {}
        for key, cls in classes.items():
            own = tuple(e.partition(".")[2] for e in exclude if e.partition(".")[0] == key)
            specs[key] = option_specs(cls, own)
        # each Params' options by group, most used first (typer shows panels in order of appearance)
        generated = [
            _option(s, help_panel(classes[key], s.info.group))
            for key, group in specs.items()
            for s in sorted(group, key=lambda s: list(GROUPS).index(s.info.group))
        ]
        names = [p.name for p in kept]
        clash = {f for s in generated for f in s.default.param_decls} & {
            f for p in kept if isinstance(p.default, typer.models.OptionInfo) for f in p.default.param_decls or ()
        }
        if clash:
            raise TypeError(
                f"{fn.__name__}: options {', '.join(sorted(clash))} are both the command's and a Params field's"
            )
        assert not set(names) & {p.name for p in generated}

        @functools.wraps(fn)
        def command(**kwargs):
            for key, group in specs.items():
                values = {spec.name: kwargs.pop(spec.name) for spec in group}
                kwargs[key] = params_from_options(classes[key], group, values)
            return fn(**kwargs)

        parameters = kept + generated
        order = [p for p in parameters if p.kind != inspect.Parameter.KEYWORD_ONLY] + [
            p for p in parameters if p.kind == inspect.Parameter.KEYWORD_ONLY
        ]
        command.__signature__ = inspect.Signature(
            [p.replace(kind=inspect.Parameter.KEYWORD_ONLY) for p in order], return_annotation=None
        )
        command.__annotations__ = {p.name: p.annotation for p in order}
        command.option_specs = specs
        command.params_classes = dict(classes)
        del command.__wrapped__  # typer must read our signature, not the wrapped function's
        return command

    return decorate
