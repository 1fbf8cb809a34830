"""Params fields that describe themselves: range, unit, choices and a label in field metadata.

Every technique's Params is a frozen, hashable dataclass. Its fields are declared with
:func:`param`, so a window can build its panel from the class alone (:func:`describe`) and every
value is checked against its declared range in one place (:func:`check_ranges`)::

    @dataclass(frozen=True)
    class BlurParams:
        radius: float = param(4.0, range=(0.0, 32.0), unit="px", help="blur radius")
        __post_init__ = check_ranges

A field's ``group`` (:data:`GROUPS`) files it with its kind in a command's --help and a window's
panel: the method first, then the paper's parameters, then what the output shows, then the
advanced settings most users leave alone.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any

from .errors import InputError, did_you_mean

__all__ = ["GROUPS", "param", "ParamInfo", "describe", "is_params", "check_ranges", "check_value", "with_values"]


#: a field's group → its panel's title, in the order panels are shown (most used first)
GROUPS = {
    "method": "method",
    "paper": "the paper's parameters",
    "output": "output",
    "advanced": "advanced",
}


def param(
    default: Any = dataclasses.MISSING,
    *,
    range: tuple[float, float] | None = None,
    unit: str = "",
    choices: tuple | None = None,
    multiple: bool = False,
    step: float | None = None,
    label: str = "",
    help: str = "",
    panel: bool = True,
    log: bool = False,
    default_factory: Any = dataclasses.MISSING,
    flag: str = "",
    cli: bool | None = None,
    group: str = "",
):
    """A dataclass field with its description in metadata.

    range: inclusive (low, high) for numbers; unit: "px", "cm", "s", "1/units"…; choices: the
    allowed values of a string (a combo box) or, with ``multiple``, of each element of a tuple
    (check boxes); step: the panel's increment for integers; log: a slider in log scale;
    panel: False for fields a panel should not show (paths, nested colour tables);
    flag: the command-line name where it is not the field's (``aperture_mm`` → ``"aperture"``; a
    switch may name its off side: ``"relative/raw"``); cli: whether commands offer it as an option
    (default: as ``panel``); group: one of :data:`GROUPS` (default: the group of the field that
    nests this Params, else "paper"; a nested Params' field gives its fields their default)."""
    if group and group not in GROUPS:
        raise ValueError(f"group {group!r} is not one of {', '.join(GROUPS)}")
    meta = {
        "range": range,
        "unit": unit,
        "choices": choices,
        "multiple": multiple,
        "step": step,
        "label": label,
        "help": help,
        "panel": panel,
        "log": log,
        "flag": flag,
        "cli": panel if cli is None else cli,
        "group": group,
    }
    if default_factory is not dataclasses.MISSING:
        return field(default_factory=default_factory, metadata=meta)
    return field(default=default, metadata=meta)


@dataclass(frozen=True)
class ParamInfo:
    """One field as a panel sees it. kind: "float", "int", "bool", "choice", "multi", "text" (a free
    string: a name or a path), "params" (a nested Params: see ``children``) or "other" (shown
    read-only)."""

    name: str
    kind: str
    value: Any
    range: tuple[float, float] | None = None
    unit: str = ""
    choices: tuple = ()
    step: float | None = None
    label: str = ""
    help: str = ""
    log: bool = False
    children: tuple[ParamInfo, ...] = ()
    flag: str = ""
    group: str = "paper"

    @property
    def title(self) -> str:
        text = self.label or self.name.replace("_", " ")
        return f"{text} ({self.unit})" if self.unit else text


def is_params(value) -> bool:
    """Whether ``value`` is a Params instance: a dataclass whose fields are declared by :func:`param`."""
    return (
        dataclasses.is_dataclass(value)
        and not isinstance(value, type)
        and any("panel" in f.metadata for f in dataclasses.fields(value))
    )


def describe(params, audience: str = "panel", group: str = "") -> tuple[ParamInfo, ...]:
    """One ParamInfo per field ``audience`` ("panel": a window's panel; "cli": a command's options)
    is shown, in declaration order; nested Params as kind "params" with their own fields. ``group``:
    the default group of the fields (that of the field nesting ``params``; else "paper")."""
    out = []
    for f in dataclasses.fields(params):
        meta = f.metadata
        if not meta.get(audience, meta.get("panel", True)):
            continue
        value = getattr(params, f.name)
        common = dict(
            range=meta.get("range"),
            unit=meta.get("unit", ""),
            step=meta.get("step"),
            label=meta.get("label", ""),
            help=meta.get("help", ""),
            log=meta.get("log", False),
            flag=meta.get("flag", ""),
            group=meta.get("group") or group or "paper",
        )
        if meta.get("choices") is not None:
            kind = "multi" if meta.get("multiple") else "choice"
            out.append(ParamInfo(f.name, kind, value, choices=tuple(meta["choices"]), **common))
        elif is_params(value):
            out.append(
                ParamInfo(f.name, "params", value, children=describe(value, audience, common["group"]), **common)
            )
        elif isinstance(value, bool):
            out.append(ParamInfo(f.name, "bool", value, **common))
        elif isinstance(value, int) and f.type not in ("float", float):
            out.append(ParamInfo(f.name, "int", value, **common))
        elif isinstance(value, float) or (isinstance(value, int) and f.type in ("float", float)):
            out.append(ParamInfo(f.name, "float", float(value), **common))
        elif isinstance(value, str):
            out.append(ParamInfo(f.name, "text", value, **common))
        else:
            out.append(ParamInfo(f.name, "other", value, **common))
    return tuple(out)


def check_ranges(params) -> None:
    """Raise InputError for a number outside its declared range, a non-finite number, or a value not
    among its choices. Usable as ``__post_init__`` or called from one."""
    for f in dataclasses.fields(params):
        check_value(f.metadata, getattr(params, f.name), f.metadata.get("label") or f.name.replace("_", " "))


def check_value(meta, value, name: str) -> None:
    """InputError naming ``name`` unless ``value`` keeps the choices and range in field metadata ``meta``."""
    choices = meta.get("choices")
    if choices is not None:
        values = value if meta.get("multiple") else (value,)
        bad = [v for v in values if v not in choices]
        if bad:
            raise InputError(
                f"{name}: {', '.join(map(repr, bad))} is not one of {', '.join(map(str, choices))}"
                f"{did_you_mean(bad[0], choices)}"
            )
        return
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        if not math.isfinite(value):
            raise InputError(f"{name} must be a finite number, got {value}")
        lo_hi = meta.get("range")
        if lo_hi is not None and not lo_hi[0] <= value <= lo_hi[1]:
            unit = f" {meta.get('unit')}" if meta.get("unit") else ""
            raise InputError(f"{name} = {value:g}{unit} is out of range [{lo_hi[0]:g}, {lo_hi[1]:g}]")


def with_values(params, **changes):
    """``dataclasses.replace`` that also accepts dotted names for nested Params
    (``with_values(p, **{"stereogram.strip_width": 80})``)."""
    nested: dict[str, dict] = {}
    flat = {}
    for key, value in changes.items():
        head, _, rest = key.partition(".")
        if rest:
            nested.setdefault(head, {})[rest] = value
        else:
            flat[key] = value
    for head, sub in nested.items():
        flat[head] = with_values(getattr(params, head), **sub)
    return dataclasses.replace(params, **flat)
