"""The Renderer protocol: frames, subjects compared by value, self-describing params, the array path."""

import dataclasses

import numpy as np
import pytest

from illusio.core.errors import InputError
from illusio.core.params import ParamInfo, check_ranges, describe, param, with_values
from illusio.core.renderer import DEFAULT_SIZE, Frame, Renderer, fingerprint
from illusio.lines.drawing import LineRenderer
from illusio.lines.params import CurvatureParams, LineParams
from illusio.passes.scene_renderer import RenderSettings, SceneRenderer
from illusio.scene.builtin import builtin_scene, shape
from illusio.sis.multiscene import MultiSceneParams, MultiSceneRenderer
from illusio.sis.params import StereogramParams
from illusio.sis.stereogram import StereogramRenderer

ALL_PARAMS = (RenderSettings, StereogramParams, MultiSceneParams, LineParams, CurvatureParams)
ALL_RENDERERS = (SceneRenderer, StereogramRenderer, MultiSceneRenderer, LineRenderer)


def test_frame_checks_its_size_and_time():
    assert Frame().size == DEFAULT_SIZE
    assert Frame(size=(640.0, 480)).size == (640, 480)
    for bad in ((0, 10), (10, 9000), ("a", 3)):
        with pytest.raises(InputError, match="size"):
            Frame(size=bad)
    with pytest.raises(InputError, match="finite"):
        Frame(time=float("nan"))
    assert hash(Frame(index=3)) == hash(Frame(index=3))


def test_fingerprint_is_by_value(rng):
    a = rng.random((7, 5)).astype(np.float32)
    mesh = shape("blob")
    assert fingerprint(a) == fingerprint(a.copy())
    b = a.copy()
    b[3, 2] = np.nextafter(b[3, 2], 2)  # one ulp of one element
    assert fingerprint(a) != fingerprint(b)
    assert fingerprint(a) != fingerprint(a.astype(np.float64))  # the same numbers, another dtype
    assert fingerprint(a) != fingerprint(a.reshape(5, 7))
    assert fingerprint(mesh) == fingerprint(shape("blob"))
    edited = shape("blob")
    edited.vertices[0, 0] += 1e-3
    assert fingerprint(mesh) != fingerprint(edited)
    scene = builtin_scene("living-room")
    other = builtin_scene("living-room")
    assert fingerprint(scene) == fingerprint(other)
    other.nodes[4].transform[0, 3] += 0.01
    assert fingerprint(scene) != fingerprint(other)


def test_prepare_loads_only_a_subject_that_differs_by_value(ctx, rng):
    renderer = StereogramRenderer(ctx)
    depth = rng.random((20, 30)).astype(np.float32)
    assert renderer.prepare(depth) is True
    assert renderer.prepare(depth.copy()) is False
    depth[0, 0] = 0.5 if depth[0, 0] != 0.5 else 0.25  # in place: seen
    assert renderer.prepare(depth) is True
    with pytest.raises(InputError, match="prepare"):
        StereogramRenderer(ctx).render(Frame(size=(30, 20)))
    # a bad subject is refused and leaves nothing held; the good one loads again after it
    with pytest.raises(InputError):
        renderer.prepare(np.full((20, 30), np.nan, np.float32))
    with pytest.raises(InputError, match="prepare"):
        renderer.render(Frame(size=(30, 20)))
    assert renderer.prepare(depth) is True
    renderer.release()


@pytest.mark.parametrize("cls", ALL_PARAMS)
def test_every_params_is_frozen_hashable_and_describes_its_fields(cls):
    p = cls()
    assert dataclasses.is_dataclass(p) and hash(p) == hash(cls())
    with pytest.raises(dataclasses.FrozenInstanceError):
        setattr(p, dataclasses.fields(p)[0].name, None)
    infos = describe(p)
    assert infos

    def walk(items):
        for info in items:
            assert isinstance(info, ParamInfo) and info.kind != "other", (cls.__name__, info.name)
            if info.kind in ("float", "int"):
                assert info.range is not None, (cls.__name__, info.name)
                lo, hi = info.range
                assert lo <= info.value <= hi
            if info.kind in ("choice", "multi"):
                assert info.choices
            walk(info.children)

    walk(infos)


def test_check_ranges_refuses_values_outside_their_declaration():
    @dataclasses.dataclass(frozen=True)
    class Knobs:
        radius: float = param(1.0, range=(0.0, 2.0), unit="px")
        kind: str = param("a", choices=("a", "b"))
        kinds: tuple = param(("a",), choices=("a", "b"), multiple=True)
        __post_init__ = check_ranges

    Knobs(2.0, "b", ("a", "b"))
    with pytest.raises(InputError, match=r"radius = 3 px is out of range \[0, 2\]"):
        Knobs(3.0)
    with pytest.raises(InputError, match="finite"):
        Knobs(float("inf"))
    with pytest.raises(InputError, match="'c' is not one of"):
        Knobs(kind="c")
    with pytest.raises(InputError, match="'c' is not one of"):
        Knobs(kinds=("a", "c"))
    nested = with_values(MultiSceneParams(), **{"stereogram.strip_width": 80.0, "emission": 0.0})
    assert nested.stereogram.strip_width == 80.0 and nested.emission == 0.0
    with pytest.raises(InputError):
        with_values(LineParams(), **{"curvature.rings": 99})


def test_every_renderer_follows_the_protocol():
    for cls in ALL_RENDERERS:
        assert issubclass(cls, Renderer)
        assert cls.Params in ALL_PARAMS
        for name in ("prepare", "render_texture", "render", "maps", "release"):
            assert callable(getattr(cls, name))


def test_texture_write_and_one_pass_readback_match_the_plain_path(ctx, rng):
    """Context.acquire_upload (pooled) and readback_image (GL drops channels, one NumPy pass) give
    what upload + readback give, for float and 8-bit textures."""
    img = rng.random((13, 17, 4)).astype(np.float32) * 1.4 - 0.2
    tex = ctx.acquire_upload(img)
    np.testing.assert_array_equal(ctx.readback(tex), img)
    np.testing.assert_array_equal(ctx.readback_image(tex, 3), np.clip(img[..., :3], 0, 1))
    np.testing.assert_array_equal(ctx.readback_image(tex, 3, clip=False), img[..., :3])
    ctx.release(tex)
    u8 = (rng.random((9, 11, 4)) * 255).astype(np.uint8)
    tex = ctx.acquire_upload(u8)
    np.testing.assert_array_equal(ctx.readback_image(tex, 3), ctx.readback(tex, 3))
    ctx.release(tex)
    with pytest.raises(InputError, match="cannot write"):
        ctx.upload_into(ctx.acquire((4, 4), 1, "f4"), np.zeros((4, 5), np.float32))


def test_frames_at_new_sizes_keep_the_pool_consistent(ctx, rng):
    """A renderer whose kept subject texture is replaced (a new frame size) neither leaks pooled
    textures nor releases one twice; the map shows the new size."""
    renderer = StereogramRenderer(ctx)
    renderer.prepare(rng.random((30, 40)).astype(np.float32))
    sizes = [(40, 30), (64, 48), (40, 30), (64, 48)]
    counts = []
    for size in sizes:
        image = renderer.render(Frame(size=size), StereogramParams(strip_width=10, depth_factor=5))
        assert image.shape[:2] == (size[1], size[0])
        assert renderer.maps()["depth"].size == size
        counts.append(ctx.textures.in_use)
    assert counts[2] == counts[0] and counts[3] == counts[1]
    renderer.release()
    lines = LineRenderer(ctx)
    lines.prepare(shape("blob"))
    for size in ((48, 32), (32, 48), (48, 32)):
        lines.render(Frame(size=size))
        assert lines.maps()["depth"].size == size
    lines.release()
