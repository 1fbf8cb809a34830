"""The relighting technique (Loscos 1999, ch. 4): a real scene relit from one photograph."""

from __future__ import annotations

from pathlib import Path

from ..core.technique import Technique

#: paths a pixel of the built-in photograph made at a frame's size
PHOTOGRAPH_SAMPLES = 64


def real_scene_subject(source: str, size: tuple[int, int], ctx=None):
    """A real scene folder (scene.yaml, a photograph, camera.json), or a built-in scene photographed
    by Mitsuba at ``size``."""
    from .photograph import builtin_real_scene, load_real_scene

    if Path(source).is_dir():
        return load_real_scene(source)
    return builtin_real_scene(source, size, PHOTOGRAPH_SAMPLES)


TECHNIQUES = (
    Technique(
        name="relight",
        title="Relighting a real scene from one photograph (Loscos 1999, ch. 4)",
        renderer="illusio.relight.renderer:RelightRenderer",
        params="illusio.relight.params:RelightParams",
        subject="illusio.relight.technique:real_scene_subject",
        source_kind="real scene folder or built-in scene",
        default_source="office",
        presets=("per-pixel", "loscos", "baseline"),
        viewer_mode="illusio.viewer.modes.relight:RelightMode",
        commands=(
            "relight=illusio.cli.relight:relight",
            "relight prepare=illusio.cli.relight:relight_prepare",
            "relight calibrate=illusio.cli.relight:relight_calibrate",
            "relight example=illusio.cli.relight:relight_example",
        ),
        showcase="illusio.gallery.relight:relight_showcase",
        benchmarks=("relight",),
        needs="mitsuba",
    ),
)
