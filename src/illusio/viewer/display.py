"""Puts the mode's images on a target: the image (and its aside) side by side, stretched to the
viewport, as colour or as a depth map; sRGB-encoded for a window, linear for files."""

from __future__ import annotations

import moderngl

from ..core.context import Context
from ..core.gl import set_uniform

__all__ = ["DisplayPass"]


class DisplayPass:
    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.program = ctx.program("viewer/shaders/display.glsl")

    def __call__(
        self,
        target: moderngl.Framebuffer,
        size: tuple[int, int],
        image: moderngl.Texture,
        aside: tuple | None = None,
        encode_srgb: bool = False,
        origin: tuple[int, int] = (0, 0),
    ) -> None:
        """Draw ``image`` over the whole of ``size`` (the left half with an ``aside``) into ``target``,
        from pixel ``origin`` (x, y from the bottom left: the window's image beside its panel).
        ``aside``: (texture, "colour" | "depth") or (texture, "grey", scale)."""
        w, h = size
        ox, oy = origin
        target.use()
        self.ctx.gl.disable(moderngl.DEPTH_TEST)
        panes = [(image, "colour")] + ([aside] if aside is not None else [])
        pane_w = w // len(panes)
        for i, (texture, kind, *scale) in enumerate(panes):
            target.viewport = (ox + i * pane_w, oy, pane_w, h)
            texture.use(0)
            set_uniform(self.program, "image", 0)
            set_uniform(self.program, "as_depth", kind == "depth")
            set_uniform(self.program, "grey_scale", float(scale[0]) if kind == "grey" else 0.0)
            set_uniform(self.program, "encode_srgb", bool(encode_srgb))
            self.ctx.fullscreen.draw(self.program)
        target.viewport = (0, 0, ox + w, oy + h)
