"""A Params instance written as options (the gallery's captions) reads back as the same Params
through each technique's real command."""

from __future__ import annotations

import dataclasses

import pytest

from illusio.core.options import field_value, option_specs, option_words, params_from_options
from illusio.core.params import with_values
from tests.cli.test_params_options import _technique_commands


def _changed(spec):
    """A value other than the default within the field's declared range or choices."""
    info = spec.info
    if spec.kind == "bool":
        return not spec.default
    if spec.kind == "choice":
        return next(c for c in info.choices if c != spec.default)
    if spec.kind == "multi":
        return tuple(c for c in info.choices if c not in spec.default)[:1] or spec.default[1:]
    if spec.kind in ("int", "float"):
        lo, hi = info.range if info.range is not None else (-1e9, 1e9)
        for candidate in (spec.default * 2 + 1, spec.default / 2, lo, hi, (lo + hi) / 2):
            value = int(candidate) if spec.kind == "int" else float(candidate)
            if lo <= value <= hi and value != spec.default:
                return value
    return None  # text: a path or a name the command checks itself


def _commands_with_params():
    for name, click_command, callback in _technique_commands():
        for key, cls in (getattr(callback, "params_classes", None) or {}).items():
            yield pytest.param(name, click_command, callback.option_specs[key], cls, id=f"{name}:{key}")


@pytest.mark.parametrize("name, click_command, specs, cls", list(_commands_with_params()))
def test_option_words_read_back_as_the_same_params(name, click_command, specs, cls):
    arguments = [p for p in click_command.params if p.param_type_name == "argument" and p.required]
    positional = ["x"] * len(arguments)
    # required options other than the Params' (the output) get a value
    for p in click_command.params:
        if p.param_type_name == "option" and p.required:
            positional += [p.opts[0], "x"]
    checked = 0
    for spec in specs:
        value = _changed(spec)
        if value is None:
            continue
        try:
            params = with_values(cls(), **{spec.path: value})
        except Exception:  # a change the class refuses across fields (checked by its own tests)
            continue
        words = option_words(params)
        assert set(spec.flag.split("/")) & set(words), (spec.path, words)
        ctx = click_command.make_context(name, positional + words)
        parsed = params_from_options(cls, specs, ctx.params)
        assert field_value(parsed, spec.path) == field_value(params, spec.path), spec.path
        assert dataclasses.asdict(parsed) == dataclasses.asdict(params), spec.path
        checked += 1
    assert checked >= len(specs) // 2, (name, checked, len(specs))


def test_option_words_write_nothing_for_the_defaults_and_skip_what_the_command_sets():
    from illusio.dof.params import DofParams

    assert option_words(DofParams()) == []
    changed = DofParams(focus_distance=3.25, aperture_mm=120.0)
    assert option_words(changed) == ["--focus-distance", "3.25", "--aperture", "120"]
    assert option_words(changed, ("focus_distance",)) == ["--aperture", "120"]
    assert {s.path for s in option_specs(DofParams)} >= {"focus_distance", "aperture_mm"}
