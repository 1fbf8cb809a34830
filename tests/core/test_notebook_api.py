"""The Python API in a notebook (issue 43): every exported name is the function or class, never a
module; a trimesh mesh goes wherever a mesh does; images show inline."""

from __future__ import annotations

import importlib
import io
import pkgutil
import types

import numpy as np
import pytest

import illusio
from illusio.core.images import linear_to_srgb

trimesh = pytest.importorskip("trimesh")

PACKAGES = sorted(name for _, name, is_package in pkgutil.walk_packages(illusio.__path__, "illusio.") if is_package) + [
    "illusio"
]


@pytest.mark.parametrize("package", PACKAGES)
def test_every_exported_name_is_a_function_class_or_value_not_a_module(package):
    module = importlib.import_module(package)
    for name in getattr(module, "__all__", ()):
        value = getattr(module, name)
        assert not isinstance(value, types.ModuleType), f"{package}.{name} is a module"
        assert name in dir(module), f"dir({package}) lacks {name}"


def test_a_trimesh_mesh_goes_wherever_a_mesh_does(ctx):
    from illusio.lines import estimate_curvature, line_drawing
    from illusio.scene import Mesh, as_mesh
    from illusio.scene.builtin.scenes import turntable
    from illusio.scene.scene import Node
    from illusio.sis.depth import hidden_scene

    ball = trimesh.creation.icosphere(3)
    drawing = line_drawing(ball, size=(96, 96), ctx=ctx)
    assert (drawing < 0.5).any() and (drawing > 0.9).mean() > 0.5  # an outline on white paper
    curvature = estimate_curvature(ball, cache=False)
    assert np.allclose(curvature.k_min, 1, atol=0.05) and np.allclose(curvature.k_max, 1, atol=0.05)
    for made in (hidden_scene(ball).nodes[0].mesh, Node("ball", ball).mesh, turntable(ball).nodes[-1].mesh):
        assert isinstance(made, Mesh)
    textured = ball.copy()
    textured.visual = trimesh.visual.TextureVisuals(uv=np.random.default_rng(1).random((len(ball.vertices), 2)))
    mesh = Mesh.from_trimesh(textured, name="ball")
    assert mesh.name == "ball" and np.allclose(mesh.uvs, textured.visual.uv, atol=1e-6)
    assert len(as_mesh(trimesh.Scene([ball, trimesh.creation.box()])).faces) == len(ball.faces) + 12
    from illusio.core.errors import InputError

    with pytest.raises(InputError, match="expected a mesh"):
        line_drawing("ball.obj", ctx=ctx)


def test_show_draws_images_inline_as_srgb_png(rng):
    from PIL import Image

    a, b = rng.random((20, 30, 3)).astype(np.float32), rng.random((12, 10)).astype(np.float32)
    picture = illusio.show(a, b, gap=4)
    png = np.asarray(Image.open(io.BytesIO(picture._repr_png_())), np.float32) / 255
    assert png.shape == (20, 30 + 4 + 10, 3)
    assert np.abs(png[:, :30] - linear_to_srgb(a)).max() <= 1 / 255 + 1e-6
    assert np.abs(png[:12, 34:, 0] - linear_to_srgb(b)).max() <= 1 / 255 + 1e-6
    assert np.all(png[12:, 34:] == 1)  # white below the shorter image
