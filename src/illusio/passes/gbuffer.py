"""G-buffer pass: colour, linear depth, normal, world position, object id and emission of a scene
seen through a view. Reference: :func:`illusio.passes.reference.gbuffer`."""

from __future__ import annotations

from dataclasses import dataclass

import moderngl
import numpy as np

from ..core.context import Context
from ..core.gl import set_uniform
from ..scene.camera import View
from .gpu_scene import GpuScene

__all__ = ["GBufferPass", "GBuffer", "GBufferImages"]

SHADER = "passes/shaders/gbuffer.glsl"
# name, components, dtype of each attachment, in shader location order
LAYOUT = (
    ("colour", 4, "f2"),
    ("depth", 1, "f4"),
    ("normal", 4, "f2"),
    ("position", 4, "f4"),
    ("object_id", 1, "f4"),
    ("emission", 4, "f2"),
)


@dataclass
class GBufferImages:
    """G-buffer read back to arrays (row 0 on top). depth: metres along the view axis, +inf where
    nothing was hit; object_id: int32, node index + 1, 0 = background; normal: world, unit."""

    colour: np.ndarray
    specular: np.ndarray
    depth: np.ndarray
    normal: np.ndarray
    shininess: np.ndarray
    position: np.ndarray
    object_id: np.ndarray
    emission: np.ndarray

    @property
    def mask(self) -> np.ndarray:
        return self.object_id > 0


@dataclass
class GBuffer:
    """The G-buffer textures (pooled: call :meth:`release` when done)."""

    ctx: Context
    textures: dict[str, moderngl.Texture]
    size: tuple[int, int]

    def __getitem__(self, name: str) -> moderngl.Texture:
        return self.textures[name]

    def read(self) -> GBufferImages:
        r = {k: self.ctx.readback(t) for k, t in self.textures.items()}
        hit = r["object_id"][..., 0] > 0.5
        depth = np.where(hit, r["depth"][..., 0], np.inf).astype(np.float32)
        return GBufferImages(
            colour=r["colour"][..., :3],
            specular=r["colour"][..., 3],
            depth=depth,
            normal=r["normal"][..., :3],
            shininess=r["normal"][..., 3],
            position=r["position"][..., :3],
            object_id=np.rint(r["object_id"][..., 0]).astype(np.int32),
            emission=r["emission"][..., :3],
        )

    def release(self) -> None:
        self.ctx.release(*self.textures.values())
        self.textures = {}


class GBufferPass:
    """Rasterises a :class:`GpuScene` into the G-buffer attachments."""

    def __init__(self, ctx: Context, **defines):
        self.ctx = ctx
        self.programs = {textured: ctx.program(SHADER, TEXTURED=int(textured), **defines) for textured in (False, True)}

    def __call__(self, gpu_scene: GpuScene, view: View, size: tuple[int, int]) -> GBuffer:
        w, h = int(size[0]), int(size[1])
        textures = {name: self.ctx.acquire((w, h), comps, dtype) for name, comps, dtype in LAYOUT}
        fbo = self.ctx.framebuffer(list(textures.values()), depth=True)
        gl = self.ctx.gl
        fbo.use()
        fbo.viewport = (0, 0, w, h)
        fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
        gl.enable(moderngl.DEPTH_TEST)
        gl.disable(moderngl.CULL_FACE)
        cull = view.view_projection((w, h))
        # textured and untextured nodes each with their own variant (surface.glsl's TEXTURED)
        for textured, indices in gpu_scene.groups(lambda index, node: node.material.texture is not None).items():
            prog = self.programs[textured]
            set_uniform(prog, "view_matrix", view.view_matrix())
            set_uniform(prog, "projection_matrix", view.projection_matrix(w / h))
            set_uniform(prog, "camera_position", np.asarray(view.pose.position, np.float32))
            gpu_scene.draw(
                prog,
                lambda index, node, prog=prog: gpu_scene.bind_surface(prog, index, node, view=view, size=(w, h)),
                only=indices,
                cull_to=cull,
            )
        gl.disable(moderngl.DEPTH_TEST)
        return GBuffer(self.ctx, textures, (w, h))
