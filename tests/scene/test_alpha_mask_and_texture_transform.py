"""glTF's alpha mask (alphaMode MASK, alphaCutoff, the base colour texture's alpha) and
KHR_texture_transform, in files written as trimesh and pygltflib write them: the mask cuts the surface
from the image and from the shadows, the transform moves the texture on the surface, and both survive
illusio's export."""

from __future__ import annotations

import math

import numpy as np
import pytest

from illusio.scene.scene_file import load_scene_file

trimesh = pytest.importorskip("trimesh")
pygltflib = pytest.importorskip("pygltflib")

SIZE = (96, 64)


def _quad(width=2.0, height=2.0):
    w, h = width / 2, height / 2
    vertices = np.array([[-w, -h, 0], [w, -h, 0], [w, h, 0], [-w, h, 0]], np.float64)
    uv = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], np.float64)  # trimesh's convention: v up
    return trimesh.Trimesh(vertices, [[0, 1, 2], [0, 2, 3]], process=False), uv


def _halves(left, right, n=16):
    """An n×n image, ``left`` (RGBA bytes) in its left half and ``right`` in its right half."""
    from PIL import Image

    image = np.zeros((n, n, 4), np.uint8)
    image[:, : n // 2] = left
    image[:, n // 2 :] = right
    return Image.fromarray(image, "RGBA")


def _scene_file(path, fence_material, with_wall=True, texture_transform=None):
    """A textured 2 m quad ("fence") at z = 0 facing +z, a white wall 1 m behind it, a point light and
    a camera 3 m in front; the quad's base colour texture info gets ``texture_transform``."""
    from trimesh.visual.material import PBRMaterial

    scene = trimesh.Scene()
    fence, uv = _quad()
    fence.visual = trimesh.visual.TextureVisuals(uv=uv, material=fence_material)
    scene.add_geometry(fence, node_name="fence", geom_name="fence")
    if with_wall:
        wall, _ = _quad(8, 8)
        wall.visual = trimesh.visual.TextureVisuals(
            material=PBRMaterial(name="wall-paint", baseColorFactor=[0.9, 0.9, 0.9, 1.0], metallicFactor=0.0)
        )
        scene.add_geometry(
            wall, node_name="wall", geom_name="wall", transform=trimesh.transformations.translation_matrix([0, 0, -1])
        )
    scene.export(str(path))
    gltf = pygltflib.GLTF2().load(str(path))
    gltf.extensionsUsed = ["KHR_lights_punctual"]
    gltf.extensions = {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 4000.0, "name": "bulb"}]}}
    gltf.cameras = [
        pygltflib.Camera(type="perspective", perspective=pygltflib.Perspective(yfov=0.9, znear=0.1, zfar=20.0))
    ]
    gltf.nodes.append(
        pygltflib.Node(name="lamp", translation=[0.0, 0.0, 2.5], extensions={"KHR_lights_punctual": {"light": 0}})
    )
    gltf.nodes.append(pygltflib.Node(name="front", camera=0, translation=[0.0, 0.0, 3.0]))
    gltf.scenes[0].nodes += [len(gltf.nodes) - 2, len(gltf.nodes) - 1]
    if texture_transform is not None:
        gltf.extensionsUsed.append("KHR_texture_transform")
        for material in gltf.materials:
            info = material.pbrMetallicRoughness.baseColorTexture
            if info is not None:
                info.extensions = {"KHR_texture_transform": texture_transform}
    gltf.save(str(path))
    return path


def _render(scene):
    from illusio.passes.scene_renderer import render_scene

    return render_scene(scene, scene.camera("front"), SIZE)


def _pixel(scene, point):
    pixels, _ = scene.camera("front").project(np.asarray([point], np.float64), SIZE)
    return int(pixels[0][1]), int(pixels[0][0])


def _masked_fence():
    from trimesh.visual.material import PBRMaterial

    # left half transparent (alpha 0), right half opaque red: the mask keeps the right half only
    return PBRMaterial(
        name="fence-paint",
        baseColorFactor=[1.0, 1.0, 1.0, 1.0],
        baseColorTexture=_halves((200, 20, 20, 0), (200, 20, 20, 255)),
        metallicFactor=0.0,
        alphaMode="MASK",
        alphaCutoff=0.5,
    )


def test_an_alpha_mask_cuts_the_surface_from_the_image_and_from_the_shadows(tmp_path, ctx):
    path = _scene_file(tmp_path / "fence.glb", _masked_fence())
    assert pygltflib.GLTF2().load(str(path)).materials[0].alphaMode == "MASK"  # the construct under test
    scene = load_scene_file(path)
    fence = scene.node("fence").material
    assert fence.opacity is not None and fence.alpha_cutoff == pytest.approx(0.5)
    image = _render(scene)
    cut, kept = _pixel(scene, (-0.5, 0, 0)), _pixel(scene, (0.5, 0, 0))
    # the wall seen through the cut half is the wall without the fence: lit, not shadowed by the cut texels
    scene.node("fence").visible = False
    no_fence = _render(scene)
    assert np.allclose(image[cut], no_fence[cut], atol=2 / 255), (image[cut], no_fence[cut])
    assert image[kept][0] > 3 * image[kept][1]  # the kept half: the red texture
    # and the kept half shadows the wall beside it, so the mask did not switch the shadow off
    behind = _pixel(scene, (0.9, 0, -1))  # seen past the fence's edge, in the shadow of its right half
    assert image[behind].mean() < 0.5 * no_fence[behind].mean()


def test_without_its_alpha_mode_the_same_texture_is_opaque(tmp_path, ctx):
    material = _masked_fence()
    material.alphaMode = None  # glTF's default OPAQUE: the alpha is ignored
    scene = load_scene_file(_scene_file(tmp_path / "opaque.glb", material))
    assert scene.node("fence").material.opacity is None
    image = _render(scene)
    cut = _pixel(scene, (-0.5, 0, 0))
    assert image[cut][0] > 3 * image[cut][1]  # red where the mask would have cut


def test_an_alpha_mask_survives_export(tmp_path, ctx):
    from illusio.scene.export import export_gltf

    scene = load_scene_file(_scene_file(tmp_path / "fence.glb", _masked_fence()))
    again = load_scene_file(export_gltf(scene, tmp_path / "again.glb"))
    a, b = scene.node("fence").material, again.node("fence").material
    assert b.alpha_cutoff == a.alpha_cutoff and np.array_equal(b.opacity >= b.alpha_cutoff, a.opacity >= a.alpha_cutoff)
    assert np.abs(_render(again) - _render(scene)).max() < 2 / 255


def _red_green_fence():
    from trimesh.visual.material import PBRMaterial

    return PBRMaterial(
        name="fence-paint",
        baseColorFactor=[1.0, 1.0, 1.0, 1.0],
        baseColorTexture=_halves((220, 10, 10, 255), (10, 220, 10, 255)),
        metallicFactor=0.0,
    )


def _colours_across(scene, image, xs):
    """'r' or 'g' at each x across the fence's middle."""
    out = ""
    for x in xs:
        p = image[_pixel(scene, (x, 0, 0))]
        out += "r" if p[0] > 3 * p[1] else "g" if p[1] > 3 * p[0] else "?"
    return out


@pytest.mark.parametrize(
    ("transform", "expected"),
    [
        (None, "rrgg"),
        ({"offset": [0.5, 0.0]}, "ggrr"),  # u' = u + ½: the right half of the texture first, then (wrapped) the left
        ({"scale": [2.0, 1.0]}, "rgrg"),  # u' = 2u: the texture twice across
        ({"rotation": math.pi, "offset": [1.0, 1.0]}, "ggrr"),  # u' = 1 − u: mirrored
    ],
)
def test_khr_texture_transform_moves_the_texture_on_the_surface(tmp_path, ctx, transform, expected):
    path = _scene_file(tmp_path / "fence.glb", _red_green_fence(), with_wall=False, texture_transform=transform)
    scene = load_scene_file(path)
    image = _render(scene)
    assert _colours_across(scene, image, (-0.75, -0.25, 0.25, 0.75)) == expected


def test_khr_texture_transform_is_the_extensions_matrix():
    """uv' = T · R · S · uv in glTF's convention (origin top left), as the extension's README writes
    it, checked on one vertex by hand: scale (2, 3), then rotation θ, then offset (0.1, 0.2)."""
    from illusio.scene.scene_file import _texture_transform, _transformed_uvs

    class Info:
        extensions = {"KHR_texture_transform": {"offset": [0.1, 0.2], "rotation": 0.3, "scale": [2.0, 3.0]}}

    class Pbr:
        baseColorTexture = Info()

    class Material:
        name = "m"
        pbrMetallicRoughness = Pbr()

    matrix = _texture_transform(Material())
    u, v = 0.25, 0.4  # glTF's v
    su, sv = 2 * u, 3 * v
    c, s = math.cos(0.3), math.sin(0.3)
    expected = (c * su + s * sv + 0.1, -s * su + c * sv + 0.2)
    (got,) = _transformed_uvs(np.array([[u, 1 - v]], np.float32), matrix)  # trimesh's v is 1 − glTF's
    assert np.allclose((got[0], 1 - got[1]), expected, atol=1e-6)
