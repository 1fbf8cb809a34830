"""Frame time of every viewer mode at 1280×720 (offscreen, the same frames a window shows), as a
ratio to the plain mode's in the same run."""

from __future__ import annotations

from illusio.core.context import Context
from illusio.viewer import MODES, Viewer

from .runner import Timing, time_case

SIZE = (1280, 720)


def run(ctx: Context, repeat: int, quick: bool = False) -> tuple[list[Timing], dict[str, float]]:
    size = (320, 180) if quick else SIZE
    timings: list[Timing] = []
    viewer = Viewer(ctx, "plain", size=size)
    for name, mode in MODES.items():
        for variant in mode.variants:
            viewer.set_mode(name, variant)
            viewer.key("d", True)  # a moving camera: nothing of the last frame is reused

            def frame():
                viewer.step(1 / 30)
                ctx.finish()

            timings.append(time_case(f"{name}/{variant}", frame, repeat, notes=f"{size[0]}x{size[1]}, camera moving"))
            viewer.key("d", False)
    viewer.release()
    plain = next(t.median_ms for t in timings if t.name.startswith("plain/"))
    ratios = {f"{t.name} / plain": t.median_ms / plain for t in timings if not t.name.startswith("plain/")}
    return timings, ratios
