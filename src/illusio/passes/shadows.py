"""Cube shadow maps for point emitters, packed in one atlas: a row per light, a column per cube
face (+x −x +y −y +z −z), each tile holding the distance from the light to the nearest surface."""

from __future__ import annotations

import moderngl
import numpy as np

from ..core.context import Context
from ..core.gl import set_uniform
from ..scene.transforms import frustum, look_at
from .gpu_scene import GpuScene

__all__ = ["ShadowPass", "cube_face_matrices"]

SHADER = "passes/shaders/shadow.glsl"
_FACES = (
    ((1, 0, 0), (0, -1, 0)),
    ((-1, 0, 0), (0, -1, 0)),
    ((0, 1, 0), (0, 0, 1)),
    ((0, -1, 0), (0, 0, -1)),
    ((0, 0, 1), (0, -1, 0)),
    ((0, 0, -1), (0, -1, 0)),
)


def cube_face_matrices(near: float, far: float) -> np.ndarray:
    """(6, 4, 4) projection·rotation of the six 90° cube faces for a light at the origin."""
    proj = frustum(-near, near, -near, near, near, far)
    return np.stack([proj @ look_at((0, 0, 0), d, up) for d, up in _FACES]).astype(np.float32)


class ShadowPass:
    """Renders the shadow atlas for a list of light positions."""

    def __init__(self, ctx: Context, tile_size: int = 512, **defines):
        self.ctx = ctx
        self.tile_size = int(tile_size)
        self.program = ctx.program(SHADER, **defines)
        self.masked_program = ctx.program(SHADER, ALPHA_MASK=1, **defines)

    def __call__(
        self, gpu_scene: GpuScene, positions: np.ndarray, near: float, far: float
    ) -> tuple[moderngl.Texture, np.ndarray]:
        """Atlas texture (pooled: release it) and the face matrices it was rendered with."""
        s = self.tile_size
        rows = max(1, len(positions))
        atlas = self.ctx.acquire((6 * s, rows * s), 1, "f4", filter="nearest")
        fbo = self.ctx.framebuffer([atlas], depth=True)
        gl = self.ctx.gl
        fbo.use()
        fbo.viewport = (0, 0, 6 * s, rows * s)
        fbo.clear(1e30, 1e30, 1e30, 1e30, depth=1.0)
        gl.enable(moderngl.DEPTH_TEST)
        matrices = cube_face_matrices(near, far)
        # nodes with an alpha mask cast shadows only where they are drawn (shadow.glsl's ALPHA_MASK)
        groups = gpu_scene.groups(lambda index, node: node.material.opacity is not None)
        for row, pos in enumerate(positions):
            for face in range(6):
                fbo.viewport = (face * s, row * s, s, s)
                for masked, indices in groups.items():
                    prog = self.masked_program if masked else self.program
                    set_uniform(prog, "light_position", np.asarray(pos, np.float32))
                    set_uniform(prog, "face_matrix", matrices[face])
                    gpu_scene.draw(
                        prog,
                        (lambda i, node, prog=prog: gpu_scene.bind_surface(prog, i, node))
                        if masked
                        else (lambda i, node, prog=prog: set_uniform(prog, "model_matrix", node.transform)),
                        only=indices if len(groups) > 1 else None,
                    )
        gl.disable(moderngl.DEPTH_TEST)
        return atlas, matrices
