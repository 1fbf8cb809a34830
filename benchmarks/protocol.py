"""The Renderer protocol's array path and one-shot calls against the texture path, every renderer.

Goals (issue 12): ``render(frame, params)`` (array out) ≤ 1.3 × ``render_texture`` + ``finish``, and
a one-shot call (``stereogram(depth)``, ``multiscene``, ``line_drawing``, ``render_scene``) ≤ 1.5 × a
kept renderer's ``render``. Each pair is timed in the same run, so the ratios hold on any machine.
"""

from __future__ import annotations

from illusio.core.context import Context
from illusio.core.renderer import Frame
from illusio.lines.drawing import LineRenderer, line_drawing
from illusio.lines.params import LineParams
from illusio.passes.scene_renderer import RenderSettings, SceneRenderer, render_scene
from illusio.scene.builtin import builtin_scene, shapes
from illusio.sis.depth import hidden_scene
from illusio.sis.multiscene import MultiSceneParams, MultiSceneRenderer, MultiSceneSubject, multiscene
from illusio.sis.params import StereogramParams
from illusio.sis.stereogram import StereogramRenderer, stereogram

from .runner import Timing, time_case
from .sis import depth_map

SIZE = (1920, 1080)


def _cases(ctx: Context, size):
    """(label, renderer, subject, frame, params, one-shot call) for every renderer."""
    w, h = size
    room = builtin_scene("living-room")
    depth = depth_map(w, h)
    other = depth[:, ::-1].copy()
    depths = [0]
    knot = shapes.torus_knot()
    hidden = hidden_scene(knot)
    settings = RenderSettings(shadows=False, forward=True)
    sis = StereogramParams()
    multi = MultiSceneParams()
    lines = LineParams()
    line_size = (min(w, 1024), min(h, 1024))
    return [
        (
            "plain",
            SceneRenderer(ctx),
            room,
            Frame(room.camera("main"), size),
            settings,
            lambda: render_scene(room, room.camera("main"), size, ctx, settings),
        ),
        # two depth maps in turn: every one-shot call uploads a new subject (the usual script)
        (
            "sis",
            StereogramRenderer(ctx),
            depth,
            Frame(None, size),
            sis,
            lambda: stereogram(depths.__setitem__(0, 1 - depths[0]) or (depth if depths[0] else other), sis, ctx),
        ),
        (
            "multiscene",
            MultiSceneRenderer(ctx),
            MultiSceneSubject(room, hidden),
            Frame(room.camera("tv"), size),
            multi,
            lambda: multiscene(room, hidden, Frame(room.camera("tv"), size), multi, ctx),
        ),
        (
            "lines",
            LineRenderer(ctx),
            knot,
            Frame(None, line_size),
            lines,
            lambda: line_drawing(knot, lines, None, line_size, ctx),
        ),
    ]


def run(ctx: Context, repeat: int, quick: bool = False) -> tuple[list[Timing], dict[str, float]]:
    size = (480, 270) if quick else SIZE
    timings: list[Timing] = []
    ratios: dict[str, float] = {}
    for label, renderer, subject, frame, params, one_shot in _cases(ctx, size):
        renderer.prepare(subject)
        note = f"{frame.size[0]}x{frame.size[1]}"

        def texture():
            tex = renderer.render_texture(frame, params)
            ctx.finish()
            ctx.release(tex)

        t = time_case(f"{label}/render_texture + finish", texture, repeat, notes=note)
        a = time_case(f"{label}/render (array)", lambda: renderer.render(frame, params), repeat, notes=note)
        o = time_case(
            f"{label}/one-shot",
            one_shot,
            repeat,
            notes=note + ", the context's kept renderer, subject prepared each call",
        )
        timings += [t, a, o]
        ratios[f"{label}: array / texture (goal <= 1.3)"] = a.median_ms / t.median_ms
        ratios[f"{label}: one-shot / kept (goal <= 1.5)"] = o.median_ms / a.median_ms
        renderer.release()
    return timings, ratios
