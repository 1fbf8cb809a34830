"""Autostereogram benchmark at 1920×1080, all in one run: the paper's strip pipeline (Algorithm 1, one
render pass per strip, ≈20 passes), the fast formulation (one dispatch, depth in), the sequential
and chain GPU layouts, the symmetric algorithm, the numba sequential reference, and the full
multi-scene frame of the living-room TV.

Goals (issue 3): fast ≥ 3× faster than strip; the multi-scene frame ≥ 10 frames per second.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from illusio.core import Context
from illusio.core.renderer import Frame
from illusio.scene import Pose, View, builtin_scene
from illusio.scene.builtin import shapes
from illusio.sis import reference
from illusio.sis.depth import hidden_scene
from illusio.sis.multiscene import MultiSceneParams, MultiSceneRenderer, MultiSceneSubject
from illusio.sis.params import StereogramParams
from illusio.sis.patterns import random_dots
from illusio.sis.stereogram import StereogramRenderer, quantise

from .runner import Timing, time_case

SIZE = (1920, 1080)


def depth_map(w: int, h: int) -> np.ndarray:
    ys, xs = np.mgrid[0:h, 0:w]
    r2 = ((xs - w / 2) ** 2 + (ys - h / 2) ** 2) / (0.3 * h) ** 2
    return np.clip(r2, 0, 1).astype(np.float32)  # a sphere-like bump, D = 0 at its top


def run(ctx: Context, repeat: int, quick: bool = False) -> tuple[list[Timing], dict[str, float]]:
    w, h = (480, 270) if quick else SIZE
    depth = depth_map(w, h)
    renderer = StereogramRenderer(ctx)
    renderer.prepare(depth)
    frame = Frame(None, (w, h))
    tex = renderer.depth_texture((w, h))
    timings: list[Timing] = []
    note = f"{w}x{h}, W_s = 100, beta = 50"

    def gpu(algorithm):
        params = StereogramParams(algorithm=algorithm)

        def go():
            out = renderer.render_texture(frame, params)
            ctx.finish()
            ctx.release(out)

        return go

    for algorithm in ("strip", "fast", "sequential", "symmetric"):
        timings.append(
            time_case(
                f"gpu/{algorithm}", gpu(algorithm), repeat, notes=note + ", depth texture in, stereogram texture out"
            )
        )
    chain_params = StereogramParams()
    sep = renderer.separation_pass(tex, chain_params)
    pattern, _ = renderer.pattern_texture(chain_params, (w, h))

    def chain():
        out = renderer.compute(sep, pattern, chain_params, algorithm="chain")
        ctx.finish()
        ctx.release(out)

    timings.append(time_case("gpu/chain (separation map given)", chain, repeat, notes=note))
    sep_cpu = reference.separation(depth, 100, 50)
    pat_cpu = quantise(random_dots(w, h, 0))
    reference.sequential(sep_cpu[:4, :300], pat_cpu[:4, :300], 100, 150)  # numba compile outside the timing
    timings.append(
        time_case(
            "cpu/sequential (numba)",
            lambda: reference.sequential(sep_cpu, pat_cpu, 100, 150),
            max(3, repeat // 3),
            notes=note,
        )
    )
    ctx.release(sep)
    renderer.release()

    scene = builtin_scene("living-room")
    hidden = hidden_scene(shapes.torus_knot())
    multi = MultiSceneRenderer(ctx)
    multi.prepare(MultiSceneSubject(scene, hidden))
    frame = [0]
    tv = scene.camera("tv")

    def multiscene(moving: bool):
        def go():
            frame[0] += 1
            # a moving viewer: the camera turns a little every frame, so nothing of the last frame is
            # reused; a still one: only the TV is shaded again (MultiSceneParams.reuse_static)
            view = _turned(tv, 0.2 * (frame[0] % 20) - 2.0) if moving else tv
            out = multi.render_texture(Frame(view, (w, h), index=frame[0]), MultiSceneParams())
            ctx.finish()
            ctx.release(out)

        return go

    def scene_only():
        out = multi.scene_renderer.render_texture(Frame(tv, (w, h)), replace(MultiSceneParams().settings, forward=True))
        ctx.finish()
        ctx.release(out)

    timings.append(
        time_case(
            "multiscene/tv frame",
            multiscene(True),
            repeat,
            notes=f"{w}x{h}, snow, fast, living-room 'tv' camera turning 0.2 degrees a frame",
        )
    )
    timings.append(
        time_case(
            "multiscene/tv frame, still camera",
            multiscene(False),
            repeat,
            notes="the same with the camera still: the static layer is reused",
        )
    )
    timings.append(
        time_case("multiscene/main scene alone", scene_only, repeat, notes="the same forward pass, no stereogram")
    )
    by = {t.name: t.median_ms for t in timings}
    ratios = {
        "strip / fast (goal >= 3)": by["gpu/strip"] / by["gpu/fast"],
        "strip / sequential": by["gpu/strip"] / by["gpu/sequential"],
        "numba sequential / fast": by["cpu/sequential (numba)"] / by["gpu/fast"],
        "multi-scene frames per second (goal >= 10)": 1000.0 / by["multiscene/tv frame"],
        "multi-scene frames per second, still camera": 1000.0 / by["multiscene/tv frame, still camera"],
        "multi-scene frame / main scene alone": by["multiscene/tv frame"] / by["multiscene/main scene alone"],
    }
    return timings, ratios


def _turned(view: View, degrees: float) -> View:
    """``view`` with its eye turned about the vertical axis through its target."""
    target = np.asarray(view.pose.target, np.float64)
    offset = np.asarray(view.pose.position, np.float64) - target
    a = np.radians(degrees)
    turned = np.array(
        [offset[0] * np.cos(a) + offset[2] * np.sin(a), offset[1], -offset[0] * np.sin(a) + offset[2] * np.cos(a)]
    )
    return View(Pose(tuple(target + turned), tuple(target), view.pose.up), view.camera)
