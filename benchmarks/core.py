"""Core benchmark: G-buffer and shading of the office and of a 1M-triangle mesh at 1920×1080.

Baselines in the same run: the G-buffer alone (what shading adds), shading without shadow maps
(what the cube shadow maps cost), and the forward path against the deferred one (same image).
"""

from __future__ import annotations

from illusio.core import Context
from illusio.core.renderer import Frame
from illusio.passes import RenderSettings, SceneRenderer
from illusio.scene import builtin_scene, turntable
from illusio.scene.builtin import shapes

from .runner import Timing, time_case

SIZE = (1920, 1080)


def run(ctx: Context, repeat: int, quick: bool = False) -> tuple[list[Timing], dict[str, float]]:
    size = (480, 270) if quick else SIZE
    timings: list[Timing] = []
    renderer = SceneRenderer(ctx)
    big = turntable(shapes.sphere(1.0, 1000, 501))  # 2·1000·501 − 2·1000 (poles) = 1,000,000 triangles, +2 floor
    cases = [("office", builtin_scene("office")), ("mesh-1M", big)]
    for label, scene in cases:
        view = scene.camera()
        renderer.prepare(scene)
        tris = renderer.gpu_scene.triangle_count
        frame = Frame(view, size)

        def gbuffer_only():
            g = renderer.gbuffer(frame)
            ctx.finish()
            g.release()

        def shaded(shadows: bool, forward: bool = False):
            def go():
                tex = renderer.render_texture(frame, RenderSettings(shadows=shadows, forward=forward))
                ctx.finish()
                ctx.release(tex)

            return go

        note = f"{tris:,} triangles, {size[0]}x{size[1]}"
        timings.append(time_case(f"{label}/gbuffer", gbuffer_only, repeat, notes=note))
        timings.append(time_case(f"{label}/gbuffer+shading", shaded(False), repeat, notes=note))
        timings.append(time_case(f"{label}/gbuffer+shading+shadows", shaded(True), repeat, notes=note))
        timings.append(time_case(f"{label}/forward", shaded(False, True), repeat, notes=note))
        timings.append(time_case(f"{label}/forward+shadows", shaded(True, True), repeat, notes=note))
        renderer.release()
    by = {t.name: t.median_ms for t in timings}
    ratios = {}
    for label, _ in cases:
        ratios[f"{label}: full frame / gbuffer only"] = by[f"{label}/gbuffer+shading+shadows"] / by[f"{label}/gbuffer"]
        ratios[f"{label}: shadows on / off"] = by[f"{label}/gbuffer+shading+shadows"] / by[f"{label}/gbuffer+shading"]
        ratios[f"{label}: deferred / forward, no shadows"] = by[f"{label}/gbuffer+shading"] / by[f"{label}/forward"]
        ratios[f"{label}: deferred / forward, shadows"] = (
            by[f"{label}/gbuffer+shading+shadows"] / by[f"{label}/forward+shadows"]
        )
    return timings, ratios
