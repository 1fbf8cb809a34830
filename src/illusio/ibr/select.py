"""The second pass (shaders/select.glsl): one full-screen draw per reference view, the depth test
keeping per pixel the reference whose back-projected point is nearest ours — the text's multi-pass
algorithm, which takes any number of views (up to 16 here) — or the text's single pass, one draw
comparing every reference itself; then one draw fetching the chosen reference's attributes into a
G-buffer. NumPy reference: :func:`illusio.ibr.reference.select`."""

from __future__ import annotations

import moderngl
import numpy as np

from ..core.context import Context
from ..core.errors import InputError
from ..core.gl import set_uniform
from ..passes.gbuffer import LAYOUT, GBuffer
from ..passes.lights import Emitters
from ..passes.shading import MAX_EMITTERS, ShadingParams, bind_emitters
from ..scene.camera import View

__all__ = ["SelectPass", "ReferenceArrays", "projection_terms", "MAX_REFERENCES"]

MAX_REFERENCES = 16
HALF_MAX = float(np.finfo(np.float16).max)


def projection_terms(view: View, size) -> tuple[float, float, float, float]:
    """(p00, p02, p11, p12) of ``view``'s projection at ``size``: what unprojection needs."""
    p = view.projection_matrix(size[0] / size[1]).astype(np.float64)
    return float(p[0, 0]), float(p[0, 2]), float(p[1, 1]), float(p[1, 2])


class ReferenceArrays:
    """The reference views on the GPU, one texture array per attribute (a layer per view): albedo,
    normal, emission and recorded colour in half floats where their values fit (float32 where
    not), depth in float32."""

    def __init__(self, ctx: Context, views):
        # (a recorded colour array, "colour", when every view has one; else the emission array stands in)
        if not 1 <= len(views) <= MAX_REFERENCES:
            raise InputError(f"image-based rendering takes 1..{MAX_REFERENCES} reference views, got {len(views)}")
        self.views = [v.view for v in views]
        self.size = views[0].size
        w, h = self.size

        def array(name, components, filter=moderngl.LINEAR, precise=False):
            data = np.stack(
                [np.asarray(getattr(v, name), np.float32).reshape(h, w, -1)[::-1, :, :components] for v in views]
            )
            # attributes in half floats, as the G-buffer the rasteriser's captures come from holds
            # them (so nothing is lost there): half the texel reads' bytes. Depth, and values past
            # half's range (a Mitsuba capture's bright emitter), in float32
            dtype = "f4" if precise or np.abs(data).max(initial=0.0) > HALF_MAX else "f2"
            tex = ctx.gl.texture_array(
                (w, h, len(views)), components, np.ascontiguousarray(data, dtype).tobytes(), dtype=dtype
            )
            tex.filter = (filter, filter)  # linear: the resolve's one-sample bilinear attributes
            tex.repeat_x = tex.repeat_y = False  # as the reference's clamped texel indices
            return tex

        self.albedo, self.normal = array("albedo", 4), array("normal", 4)
        self.emission, self.depth = array("emission", 3), array("depth", 1, moderngl.NEAREST, precise=True)
        self.has_colour = all(v.colour is not None for v in views)
        #: any emitting texel in any view (none: the resolve compiles the emission's fetch out)
        self.emits = any(np.any(np.asarray(v.emission) > 0) for v in views)
        self.colour = array("colour", 3) if self.has_colour else self.emission

    def bind(self, program, first_unit: int = 1, photographic: bool = False) -> None:
        """The arrays on units ``first_unit``…, the cameras' uniforms; ``photographic``: the recorded
        colour in the emission's place."""
        for unit, (name, tex) in enumerate(
            (
                ("ref_albedo", self.albedo),
                ("ref_normal", self.normal),
                ("ref_emission", self.colour if photographic else self.emission),
                ("ref_depth", self.depth),
            ),
            start=first_unit,
        ):
            tex.use(unit)
            set_uniform(program, name, unit)
        count = len(self.views)
        inverse = np.stack([np.linalg.inv(v.view_matrix().astype(np.float64)).T for v in self.views]).astype(np.float32)
        set_uniform(program, "ref_inverse_view", np.pad(inverse, ((0, MAX_REFERENCES - count), (0, 0), (0, 0))))
        terms = np.array([projection_terms(v, self.size) for v in self.views], np.float32)
        set_uniform(program, "ref_projection", np.pad(terms, ((0, MAX_REFERENCES - count), (0, 0))))

    def release(self) -> None:
        for t in {self.albedo, self.normal, self.emission, self.depth, self.colour}:
            t.release()


class SelectPass:
    """``(reconstructed depth, new view, references, ...)`` → a G-buffer of the new view (pooled
    textures: release it); :meth:`shaded`: the same choice lit at once (radiance, source)."""

    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.fill_program = ctx.program("ibr/shaders/fill.glsl", HITS=1)
        self._marks: moderngl.Texture | None = None  # the single lit pass's pixels left for the fill

    def __call__(
        self,
        reconstructed: moderngl.Texture,
        view: View,
        references: ReferenceArrays,
        use_3d: bool = False,
        bilinear: bool = True,
        max_distance: float = 3.0,
        photographic: bool = False,
        single_pass: bool = False,
        fill: int = 0,
    ) -> GBuffer:
        """``photographic``: the G-buffer carries the references' recorded colour as emission (and no
        albedo), so shading shows it as it was recorded. ``single_pass``: one draw over every
        reference instead of a draw each (the same choice, ties to the first reference). ``fill``:
        disocclusions (depth but no reference) up to this many pixels from a hit take the farthest
        hit of the nearest ring around them (:meth:`fill_hits`); 0 leaves them holes."""
        hits = self.hits(
            reconstructed, view, references, use_3d, bilinear, max_distance, photographic, single_pass, fill
        )
        w, h = hits.size
        textures = {name: self.ctx.acquire((w, h), comps, dtype) for name, comps, dtype in LAYOUT}
        prog = self._program(references, photographic, RESOLVE=1)
        self._resolve(prog, hits, list(textures.values()), view, references, photographic)
        return GBuffer(self.ctx, textures, (w, h))

    def shaded(
        self,
        reconstructed: moderngl.Texture,
        view: View,
        references: ReferenceArrays,
        emitters: Emitters,
        shading: ShadingParams,
        use_3d: bool = False,
        bilinear: bool = True,
        max_distance: float = 3.0,
        photographic: bool = False,
        single_pass: bool = False,
        fill: int = 0,
    ) -> tuple[moderngl.Texture, moderngl.Texture]:
        """The same choice as ``__call__``, lit in the resolve draw itself by ``emitters`` seen from
        the new eye (what ShadingPass makes of the G-buffer, without writing and reading one):
        (radiance RGBA32F linear × exposure, background in holes; source R32F: reference index + 1,
        0 = hole), both pooled. ``single_pass``: the selection lights its choice in the same draw,
        and a second draw fills and lights only the disocclusions (select.glsl)."""
        if photographic and not references.has_colour:
            raise InputError("these references hold no recorded colour: relight them (IbrParams.relight)")
        if single_pass:
            return self._selected_and_lit(
                reconstructed, view, references, emitters, shading, use_3d, bilinear, max_distance, photographic, fill
            )
        hits = self.hits(
            reconstructed, view, references, use_3d, bilinear, max_distance, photographic, single_pass, fill
        )
        radiance, source = self.ctx.acquire(hits.size, 4, "f4"), self.ctx.acquire(hits.size, 1, "f4")
        prog = self._program(references, photographic, RESOLVE=1, SHADE=1)
        self._bind_lighting(prog, view, emitters, shading)
        self._resolve(prog, hits, [radiance, source], view, references, photographic)
        return radiance, source

    def _program(self, references: ReferenceArrays, photographic: bool, **defines):
        """select.glsl with ``defines``, lit (SHADE) with the emitters' array size, its emission
        fetch compiled out where it reads nothing (no reference emits and the output is not
        photographic)."""
        if defines.get("SHADE"):
            defines["MAX_EMITTERS"] = MAX_EMITTERS
        emission = photographic or references.emits
        return self.ctx.program("ibr/shaders/select.glsl", EMISSION=int(emission), **defines)

    def _bind_lighting(self, prog, view: View, emitters: Emitters, shading: ShadingParams) -> None:
        set_uniform(prog, "camera_position", np.asarray(view.pose.position, np.float32))
        set_uniform(prog, "background", tuple(shading.background))
        bind_emitters(prog, emitters, shading, None, None, 0, unit=0)  # (no shadow atlas: no unit taken)

    def _selected_and_lit(
        self,
        reconstructed: moderngl.Texture,
        view: View,
        references: ReferenceArrays,
        emitters: Emitters,
        shading: ShadingParams,
        use_3d: bool,
        bilinear: bool,
        max_distance: float,
        photographic: bool,
        fill: int,
    ) -> tuple[moderngl.Texture, moderngl.Texture]:
        """The single-pass selection lit in its own draw, which marks in a depth texture the pixels
        with reconstructed depth and no reference (1); then, with ``fill``, one draw with the depth
        test over those pixels only, filling each from the rings around it and lighting it."""
        ctx = self.ctx
        size = reconstructed.size
        radiance, source, hits = ctx.acquire(size, 4, "f4"), ctx.acquire(size, 1, "f4"), ctx.acquire(size, 4, "f4")
        unfilled = self._unfilled_marks(size)
        fbo = ctx.framebuffer([radiance, source, hits], depth=unfilled)
        fbo.use()
        fbo.viewport = (0, 0, *size)
        prog = self._program(
            references, photographic, SINGLE_PASS=1, SHADE=1, DISTANCE_3D=int(use_3d), BILINEAR=int(bilinear)
        )
        self._bind_selection(prog, reconstructed, view, references, max_distance, photographic)
        set_uniform(prog, "photographic", bool(photographic))
        self._bind_lighting(prog, view, emitters, shading)
        ctx.gl.enable(moderngl.DEPTH_TEST)
        try:
            ctx.gl.depth_func = "1"  # always: every pixel writes its mark
            ctx.fullscreen.draw(prog)
            if fill > 0:
                prog = self._program(references, photographic, RESOLVE=1, SHADE=1, FILL=1)
                set_uniform(prog, "radius", int(fill))
                self._bind_lighting(prog, view, emitters, shading)
                ctx.gl.depth_func = "<"  # the full-screen triangle's 0.5 passes the marked pixels' 1 only
                self._resolve(prog, hits, [radiance, source], view, references, photographic, depth=unfilled)
            else:
                ctx.release(hits)
        finally:
            ctx.gl.depth_func = "<"
            ctx.gl.disable(moderngl.DEPTH_TEST)
        return radiance, source

    def _unfilled_marks(self, size) -> moderngl.Texture:
        """The depth texture of the pixels left for the fill (kept, remade when the size changes)."""
        if self._marks is None or self._marks.size != tuple(size):
            self.release()
            self.ctx.make_current()
            self._marks = self.ctx.gl.depth_texture(tuple(size))
        return self._marks

    def release(self) -> None:
        """Drop the kept depth texture of the pixels left for the fill."""
        if self._marks is not None:
            self._marks.release()
            self._marks = None

    def hits(
        self,
        reconstructed: moderngl.Texture,
        view: View,
        references: ReferenceArrays,
        use_3d: bool,
        bilinear: bool,
        max_distance: float,
        photographic: bool,
        single_pass: bool,
        fill: int,
    ) -> moderngl.Texture:
        """The selection and the disocclusion fill: per pixel (uv in the chosen reference, its depth
        there, reference index + 1; 0 = none), pooled RGBA32F."""
        if photographic and not references.has_colour:
            raise InputError("these references hold no recorded colour: relight them (IbrParams.relight)")
        ctx = self.ctx
        w, h = reconstructed.size
        hits = ctx.acquire((w, h), 4, "f4")
        fbo = ctx.framebuffer([hits], depth=not single_pass)
        fbo.use()
        fbo.viewport = (0, 0, w, h)
        fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
        prog = self.ctx.program(
            "ibr/shaders/select.glsl", SINGLE_PASS=int(single_pass), DISTANCE_3D=int(use_3d), BILINEAR=int(bilinear)
        )
        self._bind_selection(prog, reconstructed, view, references, max_distance)
        count = len(references.views)
        if single_pass:
            ctx.fullscreen.draw(prog)
        else:
            ctx.gl.enable(moderngl.DEPTH_TEST)
            ctx.gl.depth_func = "<"
            try:
                for index in range(count):
                    set_uniform(prog, "layer", index)
                    ctx.fullscreen.draw(prog)
            finally:
                ctx.gl.disable(moderngl.DEPTH_TEST)
        return self.fill_hits(hits, reconstructed, fill)

    def _bind_selection(
        self,
        prog,
        reconstructed: moderngl.Texture,
        view: View,
        references: ReferenceArrays,
        max_distance: float,
        photographic: bool = False,
    ) -> None:
        """The selection's textures (the reconstructed depth on unit 0, the references after it, the
        recorded colour as emission where ``photographic``) and uniforms."""
        size = reconstructed.size
        reconstructed.use(0)
        set_uniform(prog, "reconstructed", 0)
        references.bind(prog, photographic=photographic)
        set_uniform(prog, "new_inverse_view", np.linalg.inv(view.view_matrix().astype(np.float64)).astype(np.float32))
        set_uniform(prog, "new_view_projection", view.view_projection(size))
        set_uniform(prog, "new_projection", projection_terms(view, size))
        set_uniform(prog, "new_eye", tuple(float(v) for v in view.pose.position))
        set_uniform(prog, "max_distance", float(max_distance))
        count = len(references.views)
        matrices = np.stack([v.view_projection(references.size).astype(np.float32).T for v in references.views])
        prog["ref_view_projection"].write(np.pad(matrices, ((0, MAX_REFERENCES - count), (0, 0), (0, 0))).tobytes())
        # each reference's eye in the new view's clip space (the seen points lie on the rays from them)
        eyes = np.c_[[v.pose.position for v in references.views], np.ones(count)] @ view.view_projection(size).T
        set_uniform(prog, "ref_eye_clip", np.pad(eyes.astype(np.float32), ((0, MAX_REFERENCES - count), (0, 0))))
        set_uniform(prog, "count", count)  # (the single pass's loop; the multi-pass draws set "layer")

    def _resolve(
        self,
        prog,
        hits: moderngl.Texture,
        targets: list,
        view: View,
        references: ReferenceArrays,
        photographic: bool,
        depth: moderngl.Texture | None = None,
    ) -> None:
        """The resolve draw of ``prog`` from ``hits`` (released) into ``targets``; ``depth``: a depth
        attachment for the depth test the caller set (the single lit pass's marks)."""
        out = self.ctx.framebuffer(targets, depth=depth if depth is not None else False)
        out.use()
        out.viewport = (0, 0, *hits.size)
        hits.use(0)  # (no shadow atlas: the emitters take no unit)
        set_uniform(prog, "hits", 0)
        references.bind(prog, first_unit=1, photographic=photographic)
        set_uniform(prog, "new_view", view.view_matrix())  # (the G-buffer's depth)
        set_uniform(prog, "photographic", bool(photographic))
        self.ctx.fullscreen.draw(prog)
        self.ctx.release(hits)

    def fill_hits(self, hits: moderngl.Texture, reconstructed: moderngl.Texture, radius: int) -> moderngl.Texture:
        """``hits`` (pooled RGBA32F: uv, reference depth, index + 1; released) with its holes where
        ``reconstructed`` has depth filled from up to ``radius`` pixels away: a new pooled
        texture. NumPy reference: renderer.fill_hits."""
        if radius <= 0:
            return hits
        filled = self.ctx.draw_fullscreen(
            self.fill_program, hits.size, textures={"hits": hits, "reconstructed": reconstructed}, radius=int(radius)
        )
        self.ctx.release(hits)
        return filled
