"""Autostereogram quality, not speed (issue 20): the left-to-right bias of each algorithm.

For a hidden torus knot, each algorithm's stereogram is decoded back: the fraction of checked pixels
within 1 px of the expected separation in the left half and in the right half (and how many pixels
each half could check: left-anchored algorithms cannot check their first strip), and how far the
near part of the hidden scene is seen from where the depth map draws it (geometry: a fused pair is
seen at its middle).
Then lighting on the host (section 6): the final frame of the living room, decoded where the host is
seen, with no shadows, with shadows falling on the host, and with the room shadowed but the host lit
unshadowed (`host_shadows=False`). Written as "ratios" (the numbers of the JSON), with no timings.
"""

from __future__ import annotations

import numpy as np

from illusio.core import Context
from illusio.core.renderer import Frame
from illusio.passes.scene_renderer import RenderSettings
from illusio.scene import load_scene
from illusio.scene.builtin import shape
from illusio.scene.camera import Camera, Pose, View
from illusio.scene.scene import Scene
from illusio.sis import reference
from illusio.sis.decode import check
from illusio.sis.depth import depth_from_scene, hidden_scene
from illusio.sis.multiscene import MultiSceneRenderer, MultiSceneSubject
from illusio.sis.params import HOST_LAYOUTS, MultiSceneParams, StereogramParams
from illusio.sis.stereogram import StereogramRenderer

ALGORITHMS = ("sequential", "fast", "strip", "symmetric")


def run(ctx: Context, repeat: int, quick: bool = False):
    w, h = (480, 270) if quick else (960, 540)
    strip_width, depth_factor = 100.0 * w / 1920 * 2, 50.0 * w / 1920 * 2
    depth = depth_from_scene(ctx, hidden_scene(shape("torus-knot")), (w, h))
    renderer = StereogramRenderer(ctx)
    renderer.prepare(depth)
    sep = reference.separation(depth, strip_width, depth_factor)
    results: dict[str, float] = {}
    for algorithm in ALGORITHMS:
        params = StereogramParams(algorithm=algorithm, strip_width=strip_width, depth_factor=depth_factor, seed=3)
        image = renderer.render(Frame(size=(w, h)), params)
        anchor = "centre" if algorithm == "symmetric" else "left"
        first = 0 if algorithm == "symmetric" else int(strip_width)
        for half, columns in (("left", (0, w // 2)), ("right", (w // 2, w))):
            report = check(image, sep, first, anchor, columns=columns)
            results[f"{algorithm} {half} half decoded"] = round(report.matched, 4)
            results[f"{algorithm} {half} half checked px"] = report.checked
        # where a point is seen (the middle of its fused pair) less where the depth map drew it:
        # left-anchored algorithms link depth pixel x to x − s, the symmetric one x − s/2 to x + s/2
        near = sep < strip_width + depth_factor / 2
        results[f"{algorithm} near part seen shifted px"] = (
            0.0 if anchor == "centre" else round(-float(sep[near].mean()) / 2, 1)
        )
    results["mean separation px"] = round(float(sep.mean()), 1)
    renderer.release()
    results.update(host_lighting(ctx, (w, h)))
    results.update(oblique_hosts(ctx, (w, h)))
    return [], results


ANGLES = (0, 15, 30, 45, 60)
DISTANCES = (2.0, 4.0)


def oblique_scene(angle: float) -> Scene:
    """A 1.6 × 0.9 m glowing panel (the host) standing at the origin, turned by ``angle`` degrees
    about the vertical."""
    from illusio.scene.builtin import shapes
    from illusio.scene.scene import Material, Node
    from illusio.scene.transforms import compose, rotate

    panel = Node(
        "panel",
        shapes.plane((1.6, 0.9)),
        compose(rotate((0, 1, 0), angle), rotate((1, 0, 0), 90)),
        Material((0.8, 0.8, 0.8)),
        tags=("host",),
    )
    return Scene(name=f"panel-{angle}", nodes=[panel])


def hidden_aspect(depth: np.ndarray) -> float:
    """Width / height on the screen of the hidden sphere (the host's pixels nearer than the far
    background), 1 when it is seen round."""
    near = (depth >= 0) & (depth < 0.999)
    rows, cols = np.nonzero(near)
    return float(np.ptp(cols) + 1) / float(np.ptp(rows) + 1) if len(rows) else float("nan")


def oblique_hosts(ctx: Context, size) -> dict[str, float]:
    """Hosts seen at an angle (the paper's Figure 27 and main future work): the panel turned by 0–60°,
    seen head-on from 2 and 4 m, a hidden sphere; per layout, the decoded fraction of the final frame
    and the sphere's aspect on the screen (1 = undistorted)."""
    out = {}
    renderer = MultiSceneRenderer(ctx)
    renderer.object_ids = True
    for angle in ANGLES:
        renderer.prepare(MultiSceneSubject(oblique_scene(angle), hidden_scene(shape("sphere"))))
        for distance in DISTANCES:
            view = View(Pose((0.0, 0.0, distance), (0.0, 0.0, 0.0)), Camera(45.0, 0.1, 20.0))
            for layout in HOST_LAYOUTS:
                params = MultiSceneParams(host="host", emission=0.9, host_layout=layout)
                image = renderer.render(Frame(view, size, index=3), params)
                report, depth = renderer.decode_frame(image, params)
                key = f"oblique {angle} deg at {distance:g} m, {layout}"
                out[f"{key}: decoded"] = round(report.matched, 4)
                out[f"{key}: checked px"] = report.checked
                out[f"{key}: hidden aspect"] = round(hidden_aspect(depth), 3)
    renderer.release()
    return out


def host_lighting(ctx: Context, size) -> dict[str, float]:
    """Fraction decoded and pixels checked on the seen host of the final frame, per lighting."""
    scene = load_scene("living-room")
    renderer = MultiSceneRenderer(ctx)
    renderer.object_ids = True
    renderer.prepare(MultiSceneSubject(scene, hidden_scene(shape("torus-knot"))))
    out = {}
    for host, camera, emission in (("tv-screen", "tv", 0.9), ("back-wall", "main", 0.0)):
        for label, shadows, host_shadows in (
            ("no shadows", False, False),
            ("shadows on the host", True, True),
            ("room shadowed, host not", True, False),
        ):
            params = MultiSceneParams(
                host=host, emission=emission, settings=RenderSettings(shadows=shadows), host_shadows=host_shadows
            )
            image = renderer.render(Frame(scene.camera(camera), size, index=3), params)
            report, _ = renderer.decode_frame(image, params)
            out[f"{host} {label} decoded"] = round(report.matched, 4)
            out[f"{host} {label} checked px"] = report.checked
    renderer.release()
    return out
