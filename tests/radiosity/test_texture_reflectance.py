"""An element's reflectance from the texture it covers (radiosity.texture_reflectance): the numba
kernel against its plain reference on random textures and elements, children that share out their
parent's mean, light reflected where the texture is bright, and the textured solution's image
against Mitsuba path-tracing the same texture."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from illusio.radiosity import RadiosityParams, RadiosityRenderer
from illusio.radiosity.hierarchy import Hierarchy
from illusio.radiosity.polygons import scene_polygons
from illusio.radiosity.texture_reflectance import TextureReflectance, reference_mean
from illusio.scene import builtin_scene
from tests.radiosity.against_mitsuba import radiosity_and_mitsuba


def _random_elements(rng, n):
    """n quads (and some triangles) in uv: squares of sides from 0.003 to 2 (past the image: it
    wraps), turned at random."""
    centre = rng.random((n, 2)) * 2 - 0.5
    side = 10 ** rng.uniform(-2.5, 0.3, n)
    turn = rng.random(n) * 2 * np.pi
    square = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]]) / 2
    rotation = np.stack([np.cos(turn), -np.sin(turn), np.sin(turn), np.cos(turn)], -1).reshape(n, 2, 2)
    uv = centre[:, None] + side[:, None, None] * np.einsum("nij,kj->nki", rotation, square)
    triangle = rng.random(n) < 0.3
    uv[triangle, 3] = uv[triangle, 2]
    return uv, triangle


@pytest.mark.parametrize("kind", ["smooth", "noise"])
def test_the_kernel_matches_its_reference_on_random_inputs(rng, kind):
    """Mean reflectance over random elements of a random 128×96 image (not a power of two: the
    pyramid resamples it) against reference_mean's 64² full-resolution samples: within 0.01 on a
    smooth image (a few sines; 0.0035 at most over 12 seeds), and on white noise — where the
    reference's own samples are a noisy mean — within 0.06, 95 % within 0.02 (0.035 and 0.011)."""
    h, w = 128, 96
    if kind == "noise":
        image = rng.random((h, w, 3)) * 0.9
    else:
        y, x = np.mgrid[0:h, 0:w] / np.array([h, w])[:, None, None]
        waves = np.round(rng.random((3, 3)) * np.array([3, 3, 6]))
        image = np.stack([0.5 + 0.4 * np.sin(2 * np.pi * (a * x + b * y) + c) for a, b, c in waves], axis=-1)
    uv, triangle = _random_elements(rng, 300)
    got = TextureReflectance({0: image})(np.zeros(len(uv), int), uv, triangle)
    reference = np.array([reference_mean(image, uv[i], triangle[i]) for i in range(len(uv))])
    error = np.abs(got - reference).max(axis=1)
    if kind == "smooth":
        assert error.max() < 0.01
    else:
        assert error.max() < 0.06 and np.percentile(error, 95) < 0.02


def _half_and_half(dark_left: bool, size: int = 64):
    """A floor texture: one half (u < ½) white, the other near black."""
    image = np.full((size, size, 3), 0.9, np.float32)
    image[:, : size // 2] = 0.02
    return image if dark_left else image[:, ::-1].copy()


def _box_with_floor_texture(texture):
    box = builtin_scene("cornell-box")
    floor = box.node("floor")
    u = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], np.float32)
    floor.mesh = dataclasses.replace(floor.mesh, uvs=u[: len(floor.mesh.vertices)])
    floor.material = dataclasses.replace(floor.material, colour=(1.0, 1.0, 1.0), texture=texture)
    return box


def test_children_share_out_their_parents_mean():
    """Three subdivisions of the textured floor: each element's ρ is the area-weighted mean of its
    children's within 0.01, and the halves' elements take their half's reflectance."""
    polygons = scene_polygons(_box_with_floor_texture(_half_and_half(True)))
    floor = polygons.names.index("floor")
    h = Hierarchy(polygons)
    parents = h.roots[polygons.group == floor]
    assert np.allclose(h.reflectance[parents], 0.46, atol=0.01)  # (0.02 + 0.9) / 2
    level = parents
    for _ in range(3):
        first = h.subdivide(level)
        children = (first[:, None] + np.arange(4)).reshape(-1)
        share = (h.area[children][:, None] * h.reflectance[children]).reshape(-1, 4, 3).sum(axis=1)
        assert np.allclose(share / h.area[level][:, None], h.reflectance[level], atol=0.01)
        level = children
    x = h.centre[level, 0]
    left = x < np.median(x)
    # which half is dark depends on the floor's uv direction; one half dark, the other light
    halves = sorted([h.reflectance[level][left].mean(), h.reflectance[level][~left].mean()])
    assert halves[0] < 0.1 and halves[1] > 0.8


def _ceiling_above(ctx, texture):
    """The ceiling's mean radiosity above the floor's bright half and above its dark half."""
    box = _box_with_floor_texture(texture)
    renderer = RadiosityRenderer(ctx)
    try:
        renderer.prepare(box)
        solution = renderer.solve(RadiosityParams())
    finally:
        renderer.release()
    h, polygons = solution.hierarchy, solution.polygons
    leaves = h.leaves()
    group = polygons.group[h.polygon[leaves]]
    floor = leaves[group == polygons.names.index("floor")]
    ceiling = leaves[group == polygons.names.index("ceiling")]
    rho = h.reflectance[floor].mean(axis=1)
    bright, dark = h.centre[floor[rho > 0.8]].mean(axis=0), h.centre[floor[rho < 0.1]].mean(axis=0)
    axis = int(np.argmax(np.abs(bright - dark)))  # the floor's halves lie along this axis
    side = (h.centre[ceiling, axis] - (bright[axis] + dark[axis]) / 2) * np.sign(bright[axis] - dark[axis])
    b = h.radiosity[ceiling].mean(axis=1)
    return b[side > 0].mean(), b[side < 0].mean()


def test_a_floor_lights_the_ceiling_above_its_bright_half(ctx):
    """The floor half white, half black, then mirrored: each half of the ceiling is brighter when
    the floor's white half lies under it than when its black half does (by 18 % on one side and
    2.5 % on the other, where the tall block covers most of the floor), a mean gain over 5 %. A
    per-node mean reflectance gives both floors one solution: no gain."""
    bright_first, dark_first = _ceiling_above(ctx, _half_and_half(True))  # sides A, B
    bright_second, dark_second = _ceiling_above(ctx, _half_and_half(False))  # sides B, A
    gain_a, gain_b = bright_first / dark_second - 1, bright_second / dark_first - 1
    assert gain_a > 0.01 and gain_b > 0.01 and (gain_a + gain_b) / 2 > 0.05, (gain_a, gain_b)


def test_a_textured_floor_against_mitsuba_of_the_same_texture(ctx):
    """The Cornell box with a coarse checker on its floor, solved with per-element reflectance and
    drawn modulated by the texture, against Mitsuba path-tracing the same reflectance image through
    the same uvs: within the radiosity goal (5 % over 4×4 blocks)."""
    from illusio.scene.builtin import textures

    box = _box_with_floor_texture(textures.checker(64, 4, (0.85, 0.85, 0.85), (0.1, 0.1, 0.1)))
    image, reference, lit = radiosity_and_mitsuba(ctx, box, (48, 48), 4, 128, seed=5)
    from illusio.radiosity.mitsuba import score

    s = score(image, reference, lit, block=4)
    print(f"textured floor against Mitsuba: {s.mean_relative_error:.4f}")
    assert s.mean_relative_error < 0.05
