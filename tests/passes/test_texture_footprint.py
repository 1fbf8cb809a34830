"""The footprint ratio that decides anisotropic filtering per node (passes/texture_footprint.py)."""

import math

import numpy as np
import pytest

from illusio.core.renderer import Frame
from illusio.passes import SceneRenderer
from illusio.passes import gpu_scene as gpu_scene_module
from illusio.passes.scene_renderer import RenderSettings
from illusio.passes.texture_footprint import footprint_anisotropy
from illusio.scene import Camera, Material, Node, Pose, Scene, View
from illusio.scene.builtin import shapes, textures
from illusio.scene.transforms import compose, rotate_euler, translate

ONE = np.array([[0, 1, 2]])
SIZE = (640, 480)


def _random_view(rng) -> View:
    eye = rng.normal(size=3) * 3 + np.array([0.0, 0.0, 8.0])
    return View(Pose(tuple(eye), tuple(rng.normal(size=3))), Camera(float(rng.uniform(25, 80)), 0.05, 100.0))


def _at(point, uv, triangle, texels, scale=1e-4):
    """A tiny triangle at ``point`` with the same plane and texture map: its ratio is the point's."""
    d1, d2 = (triangle[1] - triangle[0]) * scale, (triangle[2] - triangle[0]) * scale
    t1, t2 = (texels[1] - texels[0]) * scale, (texels[2] - texels[0]) * scale
    return np.array([point, point + d1, point + d2]), np.array([uv, uv + t1, uv + t2])


def _ray(view: View, pixel) -> tuple[np.ndarray, np.ndarray]:
    """Eye and direction through ``pixel`` (x right, y down), by inverting the view-projection."""
    inverse = np.linalg.inv(view.view_projection(SIZE).astype(np.float64))
    ndc = np.array([pixel[0] / SIZE[0] * 2 - 1, 1 - pixel[1] / SIZE[1] * 2])
    near, far = (inverse @ np.array([*ndc, z, 1.0]) for z in (-1.0, 1.0))
    near, far = near[:3] / near[3], far[:3] / far[3]
    return near, far - near


def test_footprint_on_a_plane_parallel_to_the_image_is_round_everywhere(rng):
    view = View(Pose((0.3, -0.2, 5.0), (0.3, -0.2, 0.0)), Camera(60.0, 0.05, 100.0))
    for _ in range(5):  # anywhere in the frame, off the axis too
        triangle = np.c_[rng.uniform(-3, 3, (3, 2)), np.full(3, rng.uniform(-2, 2))]
        texels = triangle[:, :2] * 100.0
        assert footprint_anisotropy(triangle, ONE, texels, view, SIZE) == pytest.approx(
            1.0, abs=1e-6
        )  # closed-form singular values: ~sqrt(eps) near round


@pytest.mark.parametrize("tilt", [10.0, 30.0, 60.0])
def test_footprint_on_the_view_axis_of_a_plane_tilted_theta_is_one_over_cos_theta(tilt):
    view = View(Pose((0.0, 0.0, 4.0), (0.0, 0.0, 0.0)), Camera(50.0, 0.05, 100.0))
    a = math.radians(tilt)
    triangle = np.array([[0.0, 0.0, 0.0], [1e-3, 0.0, 0.0], [0.0, 1e-3 * math.cos(a), 1e-3 * math.sin(a)]])
    texels = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])  # one texel per millimetre along the plane
    assert footprint_anisotropy(triangle, ONE, texels, view, SIZE) == pytest.approx(1.0 / math.cos(a), rel=1e-5)


def test_footprint_matches_finite_differences_of_rays_through_neighbouring_pixels(rng):
    checked = 0
    while checked < 10:
        view = _random_view(rng)
        triangle, texels = rng.normal(size=(3, 3)) * 2, rng.normal(size=(3, 2)) * 50
        b = rng.dirichlet([1.0, 1.0, 1.0])
        point, uv = b @ triangle, b @ texels
        (pixel,), (depth,) = view.project(point[None], SIZE)
        normal = np.cross(triangle[1] - triangle[0], triangle[2] - triangle[0])
        if depth < 0.5 or not (0 < pixel[0] < SIZE[0] and 0 < pixel[1] < SIZE[1]):
            continue
        eye, direction = _ray(view, pixel)
        if abs(normal @ direction) < 0.2 * np.linalg.norm(normal) * np.linalg.norm(direction):
            continue  # nearly edge-on: finite differences are poorly conditioned there
        # texel coordinates where the rays through pixel ± 1/2 meet the plane (barycentric solve)
        to_texels = np.linalg.lstsq(np.c_[triangle[1] - triangle[0], triangle[2] - triangle[0]], np.eye(3), rcond=None)[
            0
        ]

        def texel_at(px):
            e, d = _ray(view, px)
            hit = e + d * (normal @ (triangle[0] - e)) / (normal @ d)
            return texels[0] + (to_texels @ (hit - triangle[0])) @ np.array(
                [texels[1] - texels[0], texels[2] - texels[0]]
            )

        step = 1e-3
        jac = np.column_stack(
            [
                (texel_at(pixel + o) - texel_at(pixel - o)) / (2 * step)
                for o in (np.array([step, 0.0]), np.array([0.0, step]))
            ]
        )
        s = np.linalg.svd(jac, compute_uv=False)
        tiny, tiny_texels = _at(point, uv, triangle, texels)
        assert footprint_anisotropy(tiny, ONE, tiny_texels, view, SIZE) == pytest.approx(s[0] / s[1], rel=2e-3)
        checked += 1


def test_footprint_ratio_over_a_triangle_is_largest_at_its_corners(rng):
    for _ in range(40):
        view = _random_view(rng)
        triangle, texels = rng.normal(size=(3, 3)) * 2, rng.normal(size=(3, 2)) * 50
        corners = footprint_anisotropy(triangle, ONE, texels, view, SIZE)
        if not math.isfinite(corners):
            continue
        for b in rng.dirichlet([1.0, 1.0, 1.0], size=30):
            tiny, tiny_texels = _at(b @ triangle, b @ texels, triangle, texels)
            assert footprint_anisotropy(tiny, ONE, tiny_texels, view, SIZE) <= corners * (1 + 1e-6)


def test_triangles_across_the_near_plane_are_unbounded_and_those_behind_it_are_skipped():
    view = View(Pose((0.0, 0.0, 0.0), (0.0, 0.0, -1.0)), Camera(50.0, 0.1, 100.0))
    texels = np.array([[0.0, 0.0], [10.0, 0.0], [0.0, 10.0]])
    across = np.array([[0.0, -1.0, -2.0], [1.0, -1.0, 1.0], [-1.0, -1.0, 1.0]])
    behind = across + np.array([0.0, 0.0, 5.0])
    assert footprint_anisotropy(across, ONE, texels, view, SIZE) == math.inf
    assert footprint_anisotropy(behind, ONE, texels, view, SIZE) == 1.0


def _two_planes(texture) -> tuple[Scene, View]:
    """A wall facing the camera and a floor seen at a grazing angle, one texture shared by both."""
    scene = Scene("footprint", ambient=(1.0, 1.0, 1.0), background=(0.0, 0.0, 0.0))
    material = Material(texture=texture, colour=(1.0, 1.0, 1.0))
    scene.add(
        Node(
            "wall",
            shapes.plane((4.0, 1.5), uv_scale=0.05),
            compose(translate((0.0, 0.75, -3.0)), rotate_euler((90, 0, 0))),
            material,
        )
    )
    scene.add(Node("floor", shapes.plane((4.0, 6.0), uv_scale=0.05), translate((0.0, -0.5, 0.0)), material))
    return scene, View(Pose((0.0, 0.6, 2.0), (0.0, 0.6, -3.0)), Camera(50.0, 0.05, 50.0))


def test_each_node_gets_the_filtering_its_footprint_needs_from_a_shared_texture(ctx, monkeypatch):
    texture = np.repeat(textures.value_noise(128, 32, 2, 3)[..., None], 3, axis=2).astype(np.float32)
    scene, view = _two_planes(texture)
    renderer = SceneRenderer(ctx)
    settings = RenderSettings(shadows=False, forward=True)
    renderer.prepare(scene)
    gpu = renderer.gpu_scene
    size = (320, 240)
    wall, floor = scene.nodes
    assert gpu.anisotropy(wall, view, size) == 1.0
    assert gpu.anisotropy(floor, view, size) == gpu_scene_module.MAX_ANISOTROPY
    chosen = renderer.render(Frame(view, size), settings)
    forced = {}
    for name, value in (("trilinear", 1.0), ("anisotropic", gpu_scene_module.MAX_ANISOTROPY)):
        monkeypatch.setattr(gpu_scene_module.GpuScene, "anisotropy", lambda self, node, view, size, value=value: value)
        forced[name] = renderer.render(Frame(view, size), settings)
    monkeypatch.undo()
    floor.visible = False
    renderer.prepare(scene)  # an in-place edit: prepared again (compared by value)
    on_wall = renderer.render(Frame(view, size), settings).max(axis=-1) > 0
    on_floor = (chosen.max(axis=-1) > 0) & ~on_wall
    assert on_wall.sum() > 5000 and on_floor.sum() > 5000
    assert np.abs(forced["trilinear"] - forced["anisotropic"])[on_floor].max() > 0.01  # the choice shows
    np.testing.assert_array_equal(chosen[on_wall], forced["trilinear"][on_wall])
    np.testing.assert_array_equal(chosen[on_floor], forced["anisotropic"][on_floor])


def test_trilinear_filtering_of_a_round_footprint_is_as_accurate_as_anisotropic(ctx, monkeypatch):
    """Why round footprints get trilinear filtering: against a 4×4 supersampled image, its error on
    a wall facing the camera is no larger than the anisotropic filter's (smaller on llvmpipe)."""
    texture = np.repeat(textures.value_noise(256, 32, 5, 3)[..., None], 3, axis=2).astype(np.float32)
    scene, view = _two_planes(texture)
    scene.nodes[1].visible = False
    renderer = SceneRenderer(ctx)
    renderer.prepare(scene)
    settings = RenderSettings(shadows=False, forward=True)
    w, h, k = 240, 160, 4
    monkeypatch.setattr(gpu_scene_module.GpuScene, "anisotropy", lambda self, node, view, size: 16.0)
    reference = renderer.render(Frame(view, (w * k, h * k)), settings).reshape(h, k, w, k, 3).mean(axis=(1, 3))
    errors = {}
    for value in (1.0, gpu_scene_module.MAX_ANISOTROPY):
        monkeypatch.setattr(gpu_scene_module.GpuScene, "anisotropy", lambda self, node, view, size, value=value: value)
        errors[value] = np.abs(renderer.render(Frame(view, (w, h)), settings) - reference).mean()
    assert errors[1.0] <= 1.05 * errors[gpu_scene_module.MAX_ANISOTROPY]
