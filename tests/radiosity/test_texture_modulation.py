"""Textures on the displayed radiosity (radiosity.texture_modulation): the GPU pass against its NumPy
reference on random inputs, and a textured floor drawn with its pattern under the solved light."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from illusio.core.renderer import Frame
from illusio.radiosity import RadiosityParams, RadiosityRenderer
from illusio.radiosity.texture_modulation import flat_albedo, modulate
from illusio.scene import builtin_scene
from illusio.scene.builtin import textures


def test_the_pass_matches_its_reference_on_random_inputs(ctx, rng):
    """The shader's modulation against modulate(), on random radiance, albedo and object ids
    (flat albedo 0 for one node: left unchanged), within float32 rounding."""
    from illusio.radiosity.texture_modulation import SHADER

    h, w, nodes = 23, 37, 5
    radiance = rng.random((h, w, 4)).astype(np.float32) * 3
    albedo = rng.random((h, w, 4)).astype(np.float32)
    ids = rng.integers(0, nodes + 1, (h, w))
    flat = rng.random((nodes + 1, 3)).astype(np.float32) * 0.9 + 0.05
    flat[2] = 0.0
    tex = {
        "radiance": ctx.upload(radiance),
        "albedo": ctx.upload(albedo),
        "object_id": ctx.upload(ids.astype(np.float32)[..., None]),
        "flat_albedo": ctx.upload(flat[None]),
    }
    try:
        out = ctx.draw_fullscreen(ctx.program(SHADER), (w, h), 4, "f4", textures=tex)
        gpu = ctx.readback(out)
        ctx.release(out)
    finally:
        ctx.release(*tex.values())
    assert np.allclose(gpu, modulate(radiance, albedo, ids, flat), rtol=1e-5, atol=1e-6)


def test_a_textured_floor_shows_its_pattern_under_the_solved_light(ctx):
    """The Cornell box with a fine checker on its floor (16 cells across, finer than its elements):
    the floor's pixels keep the checker's contrast (light cells / dark cells as the texture's against
    the untextured image), and the floor's mean radiance is the untextured one's (the texture shows
    once: in the modulation, not again in the elements' reflectance)."""
    box = builtin_scene("cornell-box")
    floor = box.node("floor")
    u = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], np.float32)
    floor.mesh = dataclasses.replace(floor.mesh, uvs=u[: len(floor.mesh.vertices)])
    floor.material = dataclasses.replace(
        floor.material, colour=(1.0, 1.0, 1.0), texture=textures.checker(64, 4, (0.8, 0.8, 0.8), (0.2, 0.2, 0.2))
    )
    assert np.allclose(flat_albedo(box)[1], 0.5, atol=1e-3)
    renderer = RadiosityRenderer(ctx)
    try:
        renderer.prepare(box)
        frame = Frame(box.camera("main"), (96, 96))
        textured, _ = renderer.radiance(frame, RadiosityParams())  # unclipped
        plain, _ = renderer.radiance(frame, RadiosityParams(textures=False))
        element = ctx.readback_image(renderer.maps()["element"], 1, clip=False)[..., 0]
        from illusio.passes.gbuffer import GBufferPass
        from illusio.passes.gpu_scene import GpuScene

        gpu_scene = GpuScene(ctx, box)
        gbuffer = GBufferPass(ctx)(gpu_scene, frame.view, frame.size)
        g = gbuffer.read()
        gbuffer.release()
        gpu_scene.release()
    finally:
        renderer.release()
    on_floor = (element >= 0) & (np.abs(textured - plain).max(axis=-1) > 1e-4)
    assert on_floor.mean() > 0.1, "the floor is seen and changed"
    assert textured[on_floor].mean() == pytest.approx(plain[on_floor].mean(), rel=0.03)
    ratio = textured[..., 1] / np.maximum(plain[..., 1], 1e-6)
    floor_pixels = g.object_id == box.nodes.index(floor) + 1
    # the checker's two cells (pixels whose filtered albedo is one cell's, not a blend of both):
    # 0.8 / 0.5 and 0.2 / 0.5 of the untextured radiance
    for albedo, expected in ((0.8, 1.6), (0.2, 0.4)):
        cell = floor_pixels & (np.abs(g.colour[..., 1] - albedo) < 0.05)
        assert cell.sum() > 100
        assert np.median(ratio[cell]) == pytest.approx(expected, abs=0.03)
