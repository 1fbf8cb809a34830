"""Steps (2) and (4) of Figure 22 as one pass: the host surface drawn in screen space, textured with
the hidden scene's depth image D and with the pattern through its uvs. NumPy reference:
:func:`illusio.sis.reference.host_projection` (a planar host)."""

from __future__ import annotations

import moderngl

from ..core.context import Context
from ..core.errors import InputError
from ..core.gl import set_uniform
from ..passes.gpu_scene import GpuScene
from ..scene.camera import View

__all__ = ["HostProjectionPass"]


class HostProjectionPass:
    """``(gpu_scene, hosts, view, size, hidden_depth, pattern, pattern_repeat)`` → (D in screen space,
    R32F, −1 off the host; the pattern in screen space, RGBA8), both pooled. The nearest host surface
    is drawn over its whole extent, whatever stands in front of it (an occluder must not cut the
    stereogram's rows). ``hidden_depth`` is sampled bilinearly, the pattern by nearest texel, repeated
    ``pattern_repeat`` times across the host's uv square. ``depth_box`` (x0, y0, x1, y1, pixels, row 0
    at the top): read D across that rectangle of the screen instead of through the uvs (the
    "viewer" layout; 1 = far outside it)."""

    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.program = ctx.program("sis/shaders/host_projection.glsl")

    def __call__(
        self,
        gpu_scene: GpuScene,
        hosts,
        view: View,
        size: tuple[int, int],
        hidden_depth: moderngl.Texture,
        pattern: moderngl.Texture,
        pattern_repeat=(1.0, 1.0),
        depth_box: tuple[float, float, float, float] | None = None,
    ) -> tuple[moderngl.Texture, moderngl.Texture]:
        ctx = self.ctx
        w, h = size
        hidden_depth.filter = (moderngl.LINEAR, moderngl.LINEAR)
        pattern.repeat_x = pattern.repeat_y = True
        pattern.filter = (moderngl.NEAREST, moderngl.NEAREST)
        depth_screen = ctx.acquire((w, h), 1, "f4")
        pattern_screen = ctx.acquire((w, h), 4, "f1")
        fbo = ctx.framebuffer([depth_screen, pattern_screen], depth=True)
        fbo.use()
        fbo.viewport = (0, 0, w, h)
        fbo.clear(-1.0, 0.0, 0.0, 0.0, depth=1.0)
        ctx.gl.enable(moderngl.DEPTH_TEST)
        ctx.gl.disable(moderngl.CULL_FACE)
        prog = self.program
        set_uniform(prog, "view_matrix", view.view_matrix())
        set_uniform(prog, "projection_matrix", view.projection_matrix(w / h))
        hidden_depth.use(0)
        pattern.use(1)
        for name, value in (
            ("hidden_depth", 0),
            ("pattern", 1),
            ("pattern_repeat", tuple(float(v) for v in pattern_repeat)),
        ):
            set_uniform(prog, name, value)
        set_uniform(prog, "viewer_layout", 0 if depth_box is None else 1)
        if depth_box is not None:  # to GL window rows (origin at the bottom)
            x0, y0, x1, y1 = (float(v) for v in depth_box)
            set_uniform(prog, "depth_box", (x0, h - y1, x1, h - y0))
        for _, node in hosts:
            if node.mesh.uvs is None:
                with_uvs = [n.name for n in gpu_scene.scene.nodes if n.visible and n.mesh.uvs is not None]
                raise InputError(
                    f"host {node.name!r} has no texture coordinates to carry a stereogram: unwrap it (uvs) in the "
                    f"tool that made it, or choose a node that has them: {', '.join(with_uvs) or 'none has'}"
                )
            set_uniform(prog, "uv_min", tuple(float(v) for v in node.mesh.uvs.min(axis=0)))
            set_uniform(prog, "uv_max", tuple(float(v) for v in node.mesh.uvs.max(axis=0)))
            set_uniform(prog, "model_matrix", node.transform)
            gpu_scene.vao(prog, node).render(moderngl.TRIANGLES)
        ctx.gl.disable(moderngl.DEPTH_TEST)
        return depth_screen, pattern_screen
