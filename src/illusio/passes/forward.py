"""Forward shading: the scene lit in the pass that rasterises it, with the deferred path's equations
(``shaders/emitters.glsl``) and no G-buffer. On a CPU rasteriser it is the faster path where big
surfaces fill a high-resolution frame (writing and reading six G-buffer targets then costs more
than the lighting), the slower one for dense meshes (the quads of tiny triangles are shaded several
times): benchmarks/core.py measures both. Reference: :func:`illusio.passes.reference.shading`
(tested on the deferred path's G-buffer of the same view).
"""

from __future__ import annotations

from dataclasses import dataclass

import moderngl
import numpy as np

from ..core.context import Context
from ..core.gl import set_uniform
from ..scene.camera import View
from .gpu_scene import GpuScene
from .lights import Emitters
from .shading import MAX_EMITTERS, ShadingParams, bind_emitters

__all__ = ["ForwardPass", "ScreenMaterial"]

SHADER = "passes/shaders/forward.glsl"


@dataclass(frozen=True)
class ScreenMaterial:
    """Nodes that take their colour from a screen-space texture instead of their material: albedo =
    texture × ``tint`` and emission = texture × ``emission``, the texture sampled at the pixel's
    screen position (it may have any resolution; linear filtering as the texture is set).
    ``nodes``: indices into the scene's node list."""

    texture: moderngl.Texture
    nodes: frozenset[int]
    tint: tuple[float, float, float] = (1.0, 1.0, 1.0)
    emission: float = 0.0
    shadows: bool = True  # False: these nodes are lit as if nothing stood between them and the lights


class ForwardPass:
    """GpuScene + emitters (+ shadow atlas) -> linear radiance, RGBA float32 (pooled), and on request
    the object ids (R32F, node index + 1, 0 = background) from the same pass.

    ``depth_prepass``: draw the depth first and shade where it is equal, so each pixel is lit once
    whatever the overdraw (nodes are also drawn front to back). For frame after frame with only the
    screen-material nodes changing, :meth:`static_layer` + :meth:`dynamic_layer` split the work."""

    def __init__(self, ctx: Context, depth_prepass: bool = True):
        self.ctx = ctx
        self.depth_prepass = depth_prepass
        self.depth_program = ctx.program("passes/shaders/depth_only.glsl")
        self.masked_depth_program = ctx.program("passes/shaders/depth_only.glsl", ALPHA_MASK=1)

    def __call__(
        self,
        gpu_scene: GpuScene,
        view: View,
        size: tuple[int, int],
        emitters: Emitters,
        params: ShadingParams = ShadingParams(),
        shadow_atlas: moderngl.Texture | None = None,
        shadow_matrices: np.ndarray | None = None,
        shadow_tile_size: int = 512,
        screen_material: ScreenMaterial | None = None,
        object_ids: bool = False,
    ) -> tuple[moderngl.Texture, moderngl.Texture | None]:
        w, h = int(size[0]), int(size[1])
        out = self.ctx.acquire((w, h), 4, "f4")
        ids = self.ctx.acquire((w, h), 1, "f4") if object_ids else None
        fbo = self._target([out, ids] if ids is not None else [out], True, params)
        if ids is not None:  # the background's id is 0, not the background colour
            fbo.color_attachments[1].write(np.zeros((h, w), np.float32).tobytes())
        if self.depth_prepass:
            self._depth(fbo, gpu_scene, view, (w, h))
        self._shade(
            fbo,
            gpu_scene,
            view,
            (w, h),
            emitters,
            params,
            shadow_atlas,
            shadow_matrices,
            shadow_tile_size,
            screen_material,
            equal_depth=self.depth_prepass,
        )
        return out, ids

    def static_layer(
        self,
        gpu_scene: GpuScene,
        view: View,
        size: tuple[int, int],
        emitters: Emitters,
        params: ShadingParams,
        shadow_atlas,
        shadow_matrices,
        shadow_tile_size: int,
        dynamic: frozenset[int],
    ) -> tuple[moderngl.Texture, moderngl.Texture]:
        """Every node but the ``dynamic`` ones shaded (RGBA32F, pooled), and the depth of every node
        (a depth texture the caller owns and releases): what :meth:`dynamic_layer` completes."""
        w, h = int(size[0]), int(size[1])
        base = self.ctx.acquire((w, h), 4, "f4")
        depth = self.ctx.gl.depth_texture((w, h))
        fbo = self._target([base], depth, params)
        self._depth(fbo, gpu_scene, view, (w, h))
        others = [i for i in range(len(gpu_scene.scene.nodes)) if i not in dynamic]
        self._shade(
            fbo,
            gpu_scene,
            view,
            (w, h),
            emitters,
            params,
            shadow_atlas,
            shadow_matrices,
            shadow_tile_size,
            None,
            equal_depth=True,
            only=others,
        )
        return base, depth

    def dynamic_layer(
        self,
        base: moderngl.Texture,
        depth: moderngl.Texture,
        gpu_scene: GpuScene,
        view: View,
        emitters: Emitters,
        params: ShadingParams,
        shadow_atlas,
        shadow_matrices,
        shadow_tile_size: int,
        screen_material: ScreenMaterial,
    ) -> moderngl.Texture:
        """A copy of ``base`` with the screen-material nodes shaded where ``depth`` shows them
        (RGBA32F, pooled): the same image as one forward pass of the whole scene."""
        out = self.ctx.acquire(base.size, 4, "f4")
        self.ctx.gl.copy_framebuffer(self.ctx.framebuffer([out]), self.ctx.framebuffer([base]))
        fbo = self.ctx.framebuffer([out], depth=depth)
        fbo.use()
        fbo.viewport = (0, 0, *base.size)
        self._shade(
            fbo,
            gpu_scene,
            view,
            base.size,
            emitters,
            params,
            shadow_atlas,
            shadow_matrices,
            shadow_tile_size,
            screen_material,
            equal_depth=True,
            only=screen_material.nodes,
        )
        return out

    def _target(self, colour, depth, params: ShadingParams) -> moderngl.Framebuffer:
        fbo = self.ctx.framebuffer(colour, depth=depth)
        fbo.use()
        fbo.viewport = (0, 0, *colour[0].size)
        fbo.clear(*params.background, 1.0, depth=1.0)
        return fbo

    def _depth(self, fbo: moderngl.Framebuffer, gpu_scene: GpuScene, view: View, size) -> None:
        """Depth pre-pass into ``fbo`` (bound; colour untouched)."""
        gl = self.ctx.gl
        gl.enable(moderngl.DEPTH_TEST)
        gl.disable(moderngl.CULL_FACE)
        attachments = len(fbo.color_attachments)  # one mask per attachment when there are several
        fbo.color_mask = (False,) * 4 if attachments == 1 else ((False,) * 4,) * attachments
        # nodes with an alpha mask cut their depth where the shading pass cuts their colour
        groups = gpu_scene.groups(lambda index, node: node.material.opacity is not None)
        for masked, indices in groups.items():
            pre = self.masked_depth_program if masked else self.depth_program
            set_uniform(pre, "view_matrix", view.view_matrix())
            set_uniform(pre, "projection_matrix", view.projection_matrix(size[0] / size[1]))
            gpu_scene.draw(
                pre,
                (lambda index, node, pre=pre: gpu_scene.bind_surface(pre, index, node))
                if masked
                else (lambda index, node, pre=pre: set_uniform(pre, "model_matrix", node.transform)),
                view.pose.position,
                cull_to=view.view_projection(size),
                only=indices if len(groups) > 1 else None,
            )
        fbo.color_mask = (True,) * 4 if attachments == 1 else ((True,) * 4,) * attachments
        gl.disable(moderngl.DEPTH_TEST)

    def _shade(
        self,
        fbo: moderngl.Framebuffer,
        gpu_scene: GpuScene,
        view: View,
        size,
        emitters: Emitters,
        params: ShadingParams,
        shadow_atlas,
        shadow_matrices,
        shadow_tile_size: int,
        screen_material: ScreenMaterial | None,
        equal_depth: bool,
        only=None,
    ) -> None:
        """Lit nodes into ``fbo`` (bound); ``equal_depth``: against a finished depth buffer
        (no depth writes, pass where equal)."""
        w, h = int(size[0]), int(size[1])
        gl = self.ctx.gl
        gl.enable(moderngl.DEPTH_TEST)
        gl.disable(moderngl.CULL_FACE)
        if equal_depth:
            fbo.depth_mask = False
            gl.depth_func = "<="
        flagged = screen_material.nodes if screen_material is not None else frozenset()
        eye, cull = view.pose.position, view.view_projection((w, h))

        def variant(index, node):  # the shader knobs this node needs (a variant each: see surface.glsl)
            m = node.material
            screen = index in flagged  # its own texture is replaced: no fetch
            return (m.texture is not None and not screen, m.specular > 0.0, screen)

        # one program per kind of surface; the order between groups does not change the image (the
        # depth test decides), within a group front to back
        for (textured, glossy, screen), indices in gpu_scene.groups(variant, only).items():
            shadowed = shadow_atlas is not None and not (screen and not screen_material.shadows)
            prog = self.ctx.program(
                SHADER,
                MAX_EMITTERS=MAX_EMITTERS,
                SHADOW_MAPS=int(shadowed),
                TEXTURED=int(textured),
                GLOSSY=int(glossy),
                SCREEN_MATERIAL=int(screen),
            )
            set_uniform(prog, "view_matrix", view.view_matrix())
            set_uniform(prog, "projection_matrix", view.projection_matrix(w / h))
            set_uniform(prog, "camera_position", np.asarray(eye, np.float32))
            bind_emitters(prog, emitters, params, shadow_atlas, shadow_matrices, shadow_tile_size, unit=1)
            if screen:
                screen_material.texture.use(2)
                set_uniform(prog, "screen_albedo", 2)
                set_uniform(prog, "screen_size", (float(w), float(h)))
                set_uniform(prog, "screen_tint", tuple(float(c) for c in screen_material.tint))
                set_uniform(prog, "screen_emission", float(screen_material.emission))

            def set_node(index, node, prog=prog):
                gpu_scene.bind_surface(prog, index, node, texture_unit=0, view=view, size=(w, h))

            gpu_scene.draw(prog, set_node, eye, indices, cull_to=cull)
        gl.depth_func = "<"
        fbo.depth_mask = True
        gl.disable(moderngl.DEPTH_TEST)
