"""The image-based rendering showcase: a camera path through the office drawn only from three
reference views (captured at twice the output's size, as photographs would be), beside the ground
truth and the source view of every pixel (Figure 4.5)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..core.context import Context
from ..core.images import VideoWriter, write_image
from ..core.renderer import Frame
from ..ibr.params import IbrParams
from ..ibr.reference_views import capture, orbit_views, rig_placement
from ..ibr.renderer import IbrRenderer
from ..passes.scene_renderer import RenderSettings, SceneRenderer
from ..scene.builtin import builtin_scene
from ..viewer.path import CameraPath, Keyframe
from .html import Item, Section

__all__ = ["ibr_showcase", "showcase_path"]


def showcase_path(scene, baseline: float = 1.6) -> CameraPath:
    """A walk across the references' baseline (the rig of ``orbit_views(scene, n, baseline)``, where
    ``rig_placement`` puts it), a little forward of it, looking at the main target."""
    base = scene.camera()
    right, _, _ = base.pose.axes()
    eye, width = rig_placement(scene, baseline)
    forward = np.asarray(base.pose.target, np.float64) - eye
    forward /= np.linalg.norm(forward)
    target = tuple(float(v) for v in base.pose.target)
    side = 0.4375 * width  # 0.7 m of a 1.6 m rig: inside the outer references
    points = [eye - right * side + forward * 0.3, eye + forward * 0.6, eye + right * side + forward * 0.3]
    return CameraPath([Keyframe(2.0 * k, tuple(float(v) for v in p), target) for k, p in enumerate(points)])


def ibr_showcase(ctx: Context, out_dir: Path, size: tuple[int, int], fps: float = 8.0) -> Section:
    section = Section(
        "Image-based rendering (Porquet 2005)",
        "New views of the office drawn only from three reference views (colour, depth, normals), each "
        "pixel from the reference that sees its point best; left the reconstruction, middle the "
        "ground truth rendered from the scene, right the source view of each pixel (magenta: holes).",
    )
    scene = builtin_scene("office")
    small = (max(64, size[0] // 2), max(48, size[1] // 2))
    refs = capture(
        scene, orbit_views(scene, 3, 1.6), (small[0] * 2, small[1] * 2), ctx
    )  # references at 2× (photographs)
    renderer = IbrRenderer(ctx)
    renderer.prepare(refs)
    truth = SceneRenderer(ctx)
    truth.prepare(scene)
    path = showcase_path(scene)
    count = int(path.duration * fps) + 1
    scores = []
    with VideoWriter(out_dir / "ibr/office-walk.mp4", fps) as video:
        for i in range(count):
            frame = Frame(path.view(i / fps, scene.camera().camera), small, i / fps, i)
            image = renderer.render(frame)
            sources = renderer.render(frame, IbrParams(show_sources=True))
            gt = truth.render(frame, RenderSettings(shadows=False))
            scores.append(10 * np.log10(1 / max(float(np.mean((image - gt) ** 2)), 1e-12)))
            triple = np.concatenate([image, gt, sources], axis=1)
            video.append(triple)
            if i == count // 2:
                write_image(out_dir / "ibr/office-middle.png", triple)
    renderer.release()
    truth.release()
    section.items.append(
        Item(
            "ibr/office-walk.mp4",
            "a walk through the office from 3 reference views",
            f"{count} frames; PSNR against the ground truth {min(scores):.1f}–{max(scores):.1f} dB",
            figure="Porquet 2005",
            command="illusio ibr capture office --views 3 -o refs && "
            "illusio ibr render refs --camera between:0,1 -o between.png",
        )
    )
    section.items.append(
        Item(
            "ibr/office-middle.png",
            "the walk's middle frame: reconstruction, ground truth, source views",
            f"PSNR {scores[count // 2]:.1f} dB",
            figure="Porquet 2005, Figure 4.5 (source views)",
            command="illusio ibr render refs --camera between:0,1 -o sources.png",
            params=IbrParams(show_sources=True),
        )
    )
    return section
