"""Depth maps for stereograms: checks on user input, files (white = near), and renders of a 3D scene.

D is float32 (H, W) in [0, 1] with 0 = near and 1 = far (the paper's D); files and the CLI use the
opposite, brightness convention (white = near), as depth maps are usually drawn.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import moderngl
import numpy as np

from ..core.context import Context
from ..core.errors import InputError
from ..core.files import load_npy
from ..core.gl import set_uniform
from ..core.images import read_image
from ..passes.gpu_scene import GpuScene
from ..scene.camera import Camera, Pose, View
from ..scene.mesh import Mesh
from ..scene.scene import Scene

__all__ = ["check_depth", "read_depth", "HiddenDepthPass", "OBJECT_RANGE", "hidden_scene", "depth_from_scene"]

#: the share of [0, 1] a rendered object spans in front of the far background
OBJECT_RANGE = 0.8


def check_depth(depth, name: str = "depth map") -> np.ndarray:
    """D as float32 (H, W) in [0, 1]; a clear error for anything else, a warning if it is flat."""
    d = np.asarray(depth)
    if d.ndim == 3 and d.shape[2] in (1, 3, 4):
        d = d[..., 0]
    if d.ndim != 2 or d.size == 0:
        raise InputError(f"{name} must be a non-empty 2-D array, got shape {np.shape(depth)}")
    if d.dtype.kind not in "fiub":
        raise InputError(f"{name} must be numeric, got {d.dtype}")
    d = d.astype(np.float32)
    if not np.isfinite(d).all():
        raise InputError(f"{name} has NaN or infinite values")
    if d.min() < 0 or d.max() > 1:
        raise InputError(f"{name} values must lie in [0, 1], got [{d.min():g}, {d.max():g}]")
    if d.max() == d.min():
        warnings.warn(
            f"{name} is all one value ({float(d.min()):g}): the stereogram will show a flat plane", stacklevel=2
        )
    return d


def read_depth(path: str | Path) -> np.ndarray:
    """A depth file as D (0 = near): a grey image (8 or 16-bit; white = near) or a .npy array of the
    same convention (values outside [0, 1] are rescaled from their min..max)."""
    p = Path(path)
    if p.suffix.lower() == ".npy":
        a = np.asarray(load_npy(p, "depth array"), np.float64)
        if a.ndim == 3 and a.shape[2] == 1:
            a = a[..., 0]
        if a.ndim != 2 or a.size == 0:
            raise InputError(f"depth array {p} must be 2-D and non-empty, got shape {a.shape}")
        if not np.isfinite(a).all():
            raise InputError(f"depth array {p} has NaN or infinite values")
        if a.min() < 0 or a.max() > 1:
            span = a.max() - a.min()
            a = (a - a.min()) / span if span > 0 else np.zeros_like(a)
        height = a
    else:
        img = read_image(p, srgb=False)  # depth is data, not colour: no sRGB decoding
        if img.shape[2] >= 3 and np.ptp(img[..., :3], axis=2).max() > 1e-6:
            import warnings

            warnings.warn(
                f"{p.name} is a colour image: its luminance is taken as the depth (white = near)", stacklevel=2
            )
            height = img[..., :3] @ np.array([0.2126, 0.7152, 0.0722], np.float32)
        else:
            height = img[..., 0]
    return check_depth(1.0 - np.asarray(height, np.float32), f"depth map {p.name}")


class HiddenDepthPass:
    """A scene drawn straight to D (R32F texture, pooled): the nearest point of the scene's bounding
    sphere at 0, its farthest at :data:`OBJECT_RANGE`, the background at 1."""

    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.program = ctx.program("sis/shaders/hidden_depth.glsl")

    def __call__(self, gpu_scene: GpuScene, view: View, size: tuple[int, int]) -> moderngl.Texture:
        lo, hi = gpu_scene.scene.bounds()
        centre = (np.asarray(lo) + np.asarray(hi)) / 2
        radius = float(np.linalg.norm(np.asarray(hi) - np.asarray(lo))) / 2
        distance = float(-(view.view_matrix() @ np.append(centre, 1.0))[2])
        out = self.ctx.acquire(size, 1, "f4")
        fbo = self.ctx.framebuffer([out], depth=True)
        fbo.use()
        fbo.viewport = (0, 0, *size)
        fbo.clear(1.0, 1.0, 1.0, 1.0, depth=1.0)
        gl = self.ctx.gl
        gl.enable(moderngl.DEPTH_TEST)
        gl.disable(moderngl.CULL_FACE)
        prog = self.program
        for name, value in (
            ("view_matrix", view.view_matrix()),
            ("projection_matrix", view.projection_matrix(size[0] / size[1])),
            ("front", max(distance - radius, 1e-4)),
            ("back", distance + radius),
            ("object_range", OBJECT_RANGE),
        ):
            set_uniform(prog, name, value)
        gpu_scene.draw(prog, lambda index, node: set_uniform(prog, "model_matrix", node.transform))
        gl.disable(moderngl.DEPTH_TEST)
        return out


def hidden_scene(mesh: Mesh, azimuth: float = 0.0, elevation: float = 10.0, distance: float = 2.6) -> Scene:
    """A scene holding only ``mesh`` (normalised to 1 m), with a ``main`` camera in front of it: what a
    stereogram hides."""
    from ..scene.mesh import as_mesh
    from ..scene.scene import Node

    mesh = as_mesh(mesh)
    m = mesh.normalised(1.0)
    lo, hi = m.bounds
    centre = tuple((np.asarray(lo) + np.asarray(hi)) / 2)
    return Scene(
        name=f"hidden-{mesh.name or 'mesh'}",
        nodes=[Node("subject", m, tags=("subject",))],
        cameras={"main": View(Pose.orbit(centre, distance, azimuth, elevation), Camera(30.0, 0.05, 30.0))},
    )


def depth_from_scene(ctx: Context, scene: Scene, size: tuple[int, int], view: View | None = None) -> np.ndarray:
    """D (0 = near) of a scene rendered through ``view`` (its main camera by default)."""
    gpu = GpuScene(ctx, scene)
    try:
        tex = HiddenDepthPass(ctx)(gpu, view or scene.camera(), size)
        d = ctx.readback(tex)[..., 0]
        ctx.release(tex)
    finally:
        gpu.release()
    return np.clip(d, 0, 1).astype(np.float32)
