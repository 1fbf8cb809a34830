"""A Params class seen as command-line options: one option per declared field, in both directions.

:func:`option_specs` lists the options a command offers for a Params class (the command line builds
its typer options from them); :func:`params_from_options` makes the Params back from parsed option
values; :func:`option_words` writes the words that make a given Params instance (the gallery's
captions). All three read the same field metadata, so a caption, a command and a batch job cannot
disagree about a field's name. No typer here: the core does not depend on the command line.
"""

from __future__ import annotations

import dataclasses
import functools
from dataclasses import dataclass
from typing import Any

from .params import ParamInfo, check_value, describe, with_values

__all__ = ["OptionSpec", "field_value", "option_specs", "option_words", "params_from_options"]


@dataclass(frozen=True)
class OptionSpec:
    """One option. path: the dotted field path in the Params ("hierarchy.epsilon");
    flag: "--epsilon" (a switch: "--x/--no-x"); name: the Python parameter's name; kind: as
    ParamInfo.kind; info: the field's description."""

    path: str
    flag: str
    name: str
    kind: str
    default: Any
    info: ParamInfo
    meta: Any

    @property
    def long(self) -> str:
        """The option's first name ("--epsilon"), as batch jobs and error messages use it."""
        return self.flag.split("/")[0]


def option_specs(params_class, exclude: tuple[str, ...] = ()) -> list[OptionSpec]:
    """The options a command gets for ``params_class`` (its default instance's values as defaults),
    ``exclude`` naming dotted field paths the command sets itself."""
    out: list[OptionSpec] = []
    _walk(params_class(), "", set(exclude), out)
    seen: dict[str, str] = {}
    for spec in out:
        if spec.long in seen:
            raise TypeError(
                f"{params_class.__name__}: {spec.path} and {seen[spec.long]} both make {spec.long}; "
                f"give one a flag= in its param()"
            )
        seen[spec.long] = spec.path
    return out


def _walk(instance, prefix: str, exclude: set[str], out: list[OptionSpec], group: str = "") -> None:
    metas = {f.name: f.metadata for f in dataclasses.fields(instance)}
    for info in describe(instance, "cli", group):
        path = prefix + info.name
        if path in exclude:
            continue
        if info.kind == "params":
            _walk(info.value, path + ".", exclude, out, info.group)
            continue
        if info.kind == "other":
            continue  # nothing a command line can spell (colour tables, poses)
        flag = info.flag or info.name.replace("_", "-")
        if info.kind == "bool" and "/" not in flag:
            flag = f"{flag}/no-{flag}"
        flag = "/".join("--" + part for part in flag.split("/"))
        out.append(
            OptionSpec(path, flag, "param__" + path.replace(".", "__"), info.kind, info.value, info, metas[info.name])
        )


def field_value(params, path: str):
    """The value of dotted field ``path`` ("hierarchy.epsilon") in ``params``."""
    return functools.reduce(getattr, path.split("."), params)


def params_from_options(params_class, specs: list[OptionSpec], values: dict[str, Any]):
    """The ``params_class`` instance that parsed option values make: ``values`` maps each spec's
    ``name`` to what the command line gave (a multi as one comma-separated string). A value that is
    not its field's default is checked against the field's metadata and refused by its flag."""
    changed = {}
    for spec in specs:
        raw = values[spec.name]
        value = tuple(v.strip() for v in str(raw).split(",") if v.strip()) if spec.kind == "multi" else raw
        if value != spec.default:
            check_value(spec.meta, value, spec.long)
            changed[spec.path] = value
    return with_values(params_class(), **changed)  # its own checks across fields


def option_words(params, exclude: tuple[str, ...] = ()) -> list[str]:
    """The command-line words that make ``params`` from its class's defaults: one option for each
    field that differs (``--x`` / ``--no-x`` for a switch, a multi comma-separated, a number in the
    shortest form that reads back to the same value); ``exclude``: paths the command sets itself."""
    words: list[str] = []
    for spec in option_specs(type(params), exclude):
        value = field_value(params, spec.path)
        if value == spec.default:
            continue
        on, _, off = spec.flag.partition("/")
        if spec.kind == "bool":
            words.append(on if value else off)
        elif spec.kind == "multi":
            words += [on, ",".join(map(str, value))]
        elif isinstance(value, float):
            words += [on, f"{value:g}" if float(f"{value:g}") == value else repr(value)]
        else:
            words += [on, str(value)]
    return words
