"""The Renderer protocol (docs/architecture.md, "A Renderer") over every registered technique
(core.technique): each is prepared with its default source at a small size and must give what the
protocol promises. The GL error flag is checked after each test by conftest's autouse fixture."""

import dataclasses
import re

import numpy as np
import pytest

from illusio.core.errors import InputError
from illusio.core.renderer import Frame
from illusio.core.technique import Technique, load, technique, techniques

SIZE = (176, 96)  # a stereogram holds one strip of its farthest separation (151 px by default)
ALL = list(techniques().values())


def _ranged_field(params_class):
    """A numeric field of ``params_class`` with a declared range, its (low, high)."""
    for f in dataclasses.fields(params_class):
        lo_hi = f.metadata.get("range")
        if lo_hi is not None and isinstance(f.default, (int, float)) and not isinstance(f.default, bool):
            return f, lo_hi
    return None, None


@pytest.fixture(scope="module")
def subjects():
    return {}


def _prepared(t: Technique, ctx, subjects):
    if t.needs:
        pytest.importorskip(t.needs, reason=f"{t.name} needs {t.needs}")
    if t.name not in subjects:
        subjects[t.name] = t.make_subject(None, SIZE, ctx)
    renderer = t.renderer_class()(ctx)
    return renderer, subjects[t.name]


def test_the_registry_holds_every_technique_once():
    names = [t.name for t in ALL]
    assert names[:1] == ["plain"] and len(names) == len(set(names)) == 8
    assert {"sis", "sis-scene", "lines", "dof", "ibr", "radiosity", "relight"} <= set(names)
    for t in ALL:  # every reference resolves to what it says
        assert t.renderer_class().Params is t.params_class()
        assert t.mode_class() is not None and t.mode_class().name in names + ["sis"]
        assert all(callable(load(ref)) for ref in (t.subject,) + ((t.showcase,) if t.showcase else ()))
    with pytest.raises(InputError, match="did you mean lines"):
        technique("line")


@pytest.mark.parametrize("t", ALL, ids=lambda t: t.name)
def test_prepare_render_and_render_texture_agree(t, ctx, subjects):
    """prepare → True, again with the same subject by value → False; render gives float32 (H, W, C)
    of the frame's size, finite, in [0, 1], not blank; render equals the readback of render_texture."""
    renderer, subject = _prepared(t, ctx, subjects)
    try:
        assert renderer.prepare(subject) is True
        assert renderer.prepare(subject) is False
        params = t.params_class()()
        image = renderer.render(Frame(None, SIZE), params)
        assert image.dtype == np.float32 and image.shape == (SIZE[1], SIZE[0], renderer.channels)
        assert np.isfinite(image).all() and image.min() >= 0 and image.max() <= 1
        assert image.std() > 1e-3, "a blank frame"
        texture = renderer.render_texture(Frame(None, SIZE), params)
        try:
            assert texture.size == SIZE
            again = ctx.readback_image(texture, renderer.channels)
        finally:
            ctx.release(texture)
        assert np.abs(again - image).max() <= 1 / 255 + 1e-6
    finally:
        renderer.release()


@pytest.mark.parametrize("t", ALL, ids=lambda t: t.name)
def test_maps_stay_valid_until_the_next_frame_and_release_returns_every_texture(t, ctx, subjects):
    renderer, subject = _prepared(t, ctx, subjects)
    held = ctx.textures.in_use
    renderer.prepare(subject)
    params = t.params_class()()
    image = renderer.render(Frame(None, SIZE), params)
    maps = renderer.maps()
    for name, texture in maps.items():  # readable, and not handed back to the pool
        assert ctx.readback(texture).size > 0, name
    renderer.render(Frame(None, SIZE), params)  # the next frame: the same maps again, no growth
    assert set(renderer.maps()) == set(maps)
    renderer.release()
    assert renderer.maps() == {}
    assert ctx.textures.in_use == held, "release left textures acquired"
    assert image.shape[:2] == (SIZE[1], SIZE[0])


@pytest.mark.parametrize("t", ALL, ids=lambda t: t.name)
def test_out_of_range_params_are_refused_by_name(t):
    params_class = t.params_class()
    f, (lo, hi) = _ranged_field(params_class)
    assert f is not None, f"{params_class.__name__} declares no ranged field"
    name = f.metadata.get("label") or f.name.replace("_", " ")
    with pytest.raises(InputError, match=re.escape(name)):
        params_class(**{f.name: hi + max(1.0, abs(hi))})


@pytest.mark.parametrize("t", ALL, ids=lambda t: t.name)
def test_a_frame_of_another_size_is_that_size(t, ctx, subjects):
    """Every renderer honours frame.size (relighting resamples its photograph's image)."""
    renderer, subject = _prepared(t, ctx, subjects)
    try:
        renderer.prepare(subject)
        other = (SIZE[0] + 16, SIZE[1] + 8)
        assert renderer.render(Frame(None, other), t.params_class()()).shape[:2] == (other[1], other[0])
    finally:
        renderer.release()


def _field_changes(params, prefix=""):
    """(dotted path, [other values to try]) for every declared field of ``params`` a generic change
    can reach: a switch flipped, another choice, a set with one member more or less, a number
    doubled, halved, or at an end of its range. Text (paths, names) and "other" fields aside."""
    from illusio.core.params import describe

    seen = {}
    for audience in ("panel", "cli"):
        for info in describe(params, audience):
            seen.setdefault(info.name, info)
    for info in seen.values():
        path = prefix + info.name
        if info.kind == "params":
            yield from _field_changes(info.value, path + ".")
        elif info.kind == "bool":
            yield path, [not info.value]
        elif info.kind == "choice":
            yield path, [c for c in info.choices if c != info.value]
        elif info.kind == "multi":
            more = [(*info.value, c) for c in info.choices if c not in info.value]
            fewer = [tuple(v for v in info.value if v != drop) for drop in info.value]
            yield path, [v for v in fewer + more if v]
        elif info.kind in ("int", "float"):
            lo, hi = info.range if info.range is not None else (-np.inf, np.inf)
            value = info.value
            tries = [value * 2 if value else 1, value / 2, hi, lo, (lo + hi) / 2]
            cast = (lambda v: int(round(v))) if info.kind == "int" else float
            values = []
            for v in tries:
                if np.isfinite(v) and lo <= v <= hi and cast(v) != value and cast(v) not in values:
                    values.append(cast(v))
            yield path, values


@pytest.mark.parametrize("t", ALL, ids=lambda t: t.name)
def test_changing_each_declared_field_changes_the_image_or_is_documented_as_not_visible(t, ctx, subjects):
    """Over every technique: each declared field, changed within its range, changes the default
    view's image (some pixel by more than 2/255), or its Params documents why it does not in
    ``NOT_VISIBLE_BY_DEFAULT`` (a field that only matters with another setting, for another
    subject or for speed). A documented field that does change the image is reported too, so the
    list stays true."""
    from illusio.core.params import with_values

    params_class = t.params_class()
    documented = dict(getattr(params_class, "NOT_VISIBLE_BY_DEFAULT", {}))
    renderer, subject = _prepared(t, ctx, subjects)
    try:
        renderer.prepare(subject)
        base = renderer.render(Frame(None, SIZE), params_class())
        unseen, stale = {}, []
        for path, values in _field_changes(params_class()):
            # each field from the default state: a renderer that keeps work between frames (radiosity's
            # solution) would otherwise show the field before's leftovers as this field's change
            renderer.render(Frame(None, SIZE), params_class())
            outcome = "refused"
            for value in values:
                try:
                    changed = with_values(params_class(), **{path: value})
                    image = renderer.render(Frame(None, SIZE), changed)
                except InputError:  # refused with this subject or size: the next value
                    continue
                difference = float(np.abs(image - base).max())
                outcome = f"{value!r}: largest change {difference * 255:.2f}/255"
                if difference > 2 / 255:
                    outcome = "changed"
                    break
            if outcome != "changed" and path not in documented:
                unseen[path] = outcome
            if outcome == "changed" and path in documented:
                stale.append(path)
        assert not unseen, f"{t.name}: fields that change nothing, undocumented: {unseen}"
        assert not stale, f"{t.name}: documented as not visible but they change the image: {stale}"
    finally:
        renderer.release()
