"""The viewer showcase: each mode of ``illusio view`` played along a camera path offscreen, as an
MP4 beside the camera path that made it (``illusio view --path FILE -o OUT.mp4`` replays it)."""

from __future__ import annotations

from pathlib import Path

from ..core.context import Context
from ..viewer.offscreen import record
from ..viewer.path import CameraPath, Keyframe
from .html import Item, Section

__all__ = ["viewer_showcase", "SHOWCASE_PATHS"]

_TV = (0.0, 1.08, -2.2)
_WALL = (0.0, 1.35, -2.5)
#: (file stem, technique, source, view, caption, keyframes (t, eye, target))
SHOWCASE_PATHS = (
    (
        "plain-walk",
        "plain",
        "living-room",
        None,
        "plain: a walk through the living room",
        (
            (0.0, (2.5, 1.7, 2.4), (-0.4, 0.8, -1.4)),
            (1.5, (1.0, 1.6, 1.4), (-1.5, 1.0, -1.8)),
            (3.0, (-1.2, 1.5, 1.6), (0.0, 1.0, -2.2)),
        ),
    ),
    (
        "sis-tv",
        "sis",
        None,
        "tv",
        "sis: walking up to the TV, whose snow hides a torus knot (Figure 23)",
        ((0.0, (2.5, 1.7, 2.4), _TV), (1.5, (1.2, 1.4, 0.6), _TV), (3.0, (0.2, 1.15, -0.9), _TV)),
    ),
    (
        "sis-interactive",
        "sis",
        None,
        "interactive",
        "sis: around the wall in the interaction mode; the hidden knot turns (Figure 25)",
        ((0.0, (-2.0, 1.4, 1.5), _WALL), (1.5, (0.0, 1.4, 2.0), _WALL), (3.0, (2.0, 1.4, 1.5), _WALL)),
    ),
    (
        "lines-orbit",
        "lines",
        "torus-knot",
        None,
        "lines: orbiting the torus knot (apparent ridges + silhouettes)",
        (
            (0.0, (7.0, 3.0, 7.0), (0.0, 0.0, 0.0)),
            (1.5, (-7.0, 3.0, 7.0), (0.0, 0.0, 0.0)),
            (3.0, (-7.0, 3.0, -7.0), (0.0, 0.0, 0.0)),
        ),
    ),
)


def viewer_showcase(ctx: Context, out_dir: Path, size: tuple[int, int], fps: float = 12.0) -> Section:
    section = Section(
        "illusio view — camera paths",
        "Each mode of the live viewer, recorded offscreen along a camera path (the same frames the window "
        "shows). Replay one in a window with `illusio view --technique T --path FILE.json`.",
    )
    w, h = max(64, size[0] // 2), max(36, size[1] // 2)
    for stem, technique, source, view, caption, keys in SHOWCASE_PATHS:
        path = CameraPath([Keyframe(t, eye, target) for t, eye, target in keys])
        rel_path, rel_video = f"viewer/{stem}.json", f"viewer/{stem}.mp4"
        path.save(out_dir / rel_path)
        count = record(technique, source, view, (w, h), path, fps, out_dir / rel_video, ctx=ctx)
        source_arg = f" {source}" if source else ""
        view_arg = f" --view {view}" if view else ""
        section.items.append(
            Item(
                rel_video,
                caption,
                f"{count} frames at {fps:g} fps, {w}×{h}",
                files=(rel_path,),
                command=f"illusio view{source_arg} --technique {technique}{view_arg} --path {rel_path} "
                f"-o {Path(rel_video).name} --size {w}x{h}",
            )
        )
    return section
