"""The worked example of relighting one's own photograph (docs/own-data.md's walkthrough): a folder as a user
would make it — the room's model (scene.yaml), a photograph of it and points picked on both — made by
the project, so every step from photograph to relit image runs from a fresh clone.

The photograph is path-traced by Mitsuba through a camera with its own intrinsics (principal point
12 px right and 8 px up of the centre) and radial distortion (k1 = −0.08, k2 = 0.01): a centred
pinhole image rendered larger and cropped so its optical centre falls at (c_x, c_y), then distorted
(scene.intrinsics.distort_image), denoised by Open Image Denoise when it is installed, and written
as an 8-bit sRGB PNG as a camera would. The points are corners of the model the camera sees,
projected through the true camera and moved by 0.3 px (seeded) as a user's clicks would be; the
true camera is written too (``true-camera.json``), to score the calibration against."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..core.images import atomic_output, write_image
from ..scene.camera import Camera, Pose, View
from ..scene.intrinsics import Intrinsics, distort_image

__all__ = ["EXAMPLE_SCENE", "true_camera", "pinhole_photograph", "project", "make_example"]

#: the model: a room with a table, a cabinet and a lamp under the ceiling (metres; y up)
EXAMPLE_SCENE = """\
name: my-room
nodes:
  - {name: floor, shape: plane, params: {size: [5, 4]}, material: {colour: [0.55, 0.5, 0.45]}}
  - {name: ceiling, shape: plane, params: {size: [5, 4]}, position: [0, 2.6, 0], rotation: [180, 0, 0],
     material: {colour: [0.75, 0.75, 0.75]}}
  - {name: back-wall, shape: plane, params: {size: [5, 2.6]}, position: [0, 1.3, -2], rotation: [90, 0, 0],
     material: {colour: [0.6, 0.62, 0.55]}}
  - {name: left-wall, shape: plane, params: {size: [2.6, 4]}, position: [-2.5, 1.3, 0], rotation: [0, 0, -90],
     material: {colour: [0.65, 0.55, 0.5]}}
  - {name: right-wall, shape: plane, params: {size: [2.6, 4]}, position: [2.5, 1.3, 0], rotation: [0, 0, 90],
     material: {colour: [0.5, 0.55, 0.65]}}
  - {name: front-wall, shape: plane, params: {size: [5, 2.6]}, position: [0, 1.3, 2], rotation: [-90, 0, 0],
     material: {colour: [0.6, 0.6, 0.6]}}
  - {name: table, shape: box, params: {size: [1.4, 0.75, 0.8]}, position: [-0.4, 0.375, -0.6],
     material: {colour: [0.45, 0.3, 0.2]}}
  - {name: cabinet, shape: box, params: {size: [0.6, 1.2, 0.5]}, position: [1.6, 0.6, -1.6],
     material: {colour: [0.3, 0.4, 0.55]}}
lights:
  - {name: lamp, type: area, centre: [0.2, 2.55, -0.3], edge_u: [0.6, 0, 0], edge_v: [0, 0, 0.6], radiance: 9}
  - {name: reading-lamp, type: area, centre: [-2.0, 1.8, -1.2], edge_u: [0, 0.3, 0], edge_v: [0, 0, 0.3],
     radiance: 14}
"""
_POSE = Pose((2.0, 1.7, 1.8), (-0.5, 0.75, -1.3))


def true_camera(size: tuple[int, int] = (320, 240)) -> tuple[View, Intrinsics]:
    """The camera the example's photograph is taken with, at ``size`` (its intrinsics scale with it)."""
    w, h = size
    f = 0.62 * w
    s = w / 320
    intrinsics = Intrinsics(
        w, h, f, f, (w - 1) / 2 + round(12 * s), (h - 1) / 2 - round(8 * s), "OPENCV", (-0.08, 0.01, 0.0, 0.0)
    )
    return View(_POSE, intrinsics.camera(0.05, 50.0)), intrinsics


def pinhole_photograph(polygons, intrinsics: Intrinsics, samples: int, seed: int) -> np.ndarray:
    """The pinhole image (H, W, 3) radiance of ``polygons`` through the example's camera with the
    principal point at (c_x, c_y) (``intrinsics``, distortion aside): a centred render, larger,
    cropped. What the undistorted photograph shows; with edited lamps, the truth of an edit."""
    from ..passes.denoise import denoiser_available
    from ..radiosity import render_mitsuba

    w, h = intrinsics.width, intrinsics.height
    dx, dy = round(intrinsics.cx - (w - 1) / 2), round(intrinsics.cy - (h - 1) / 2)
    big_w, big_h = w + 2 * abs(dx), h + 2 * abs(dy)
    fov = math.degrees(2 * math.atan(big_h / (2 * intrinsics.fy)))
    big = render_mitsuba(
        polygons, View(_POSE, Camera(fov, 0.05, 50.0)), (big_w, big_h), samples, seed, denoise=denoiser_available()
    )
    x0, y0 = abs(dx) - dx, abs(dy) - dy  # the big image's centre lands on (c_x, c_y) of the crop
    return big[y0 : y0 + h, x0 : x0 + w]


def _visible_corners(polygons, eye: np.ndarray) -> np.ndarray:
    """The model's corners the camera sees (a ray from the eye reaches them)."""
    from embreex import rtcore_scene
    from embreex.mesh_construction import TriangleMesh

    corners = np.unique(np.round(polygons.corners.reshape(-1, 3), 6), axis=0)
    vertices, faces = polygons.triangles()
    scene = rtcore_scene.EmbreeScene()
    TriangleMesh(scene, vertices[faces])
    d = corners - eye
    length = np.linalg.norm(d, axis=1)
    hit = scene.run(
        np.repeat(eye[None], len(d), 0).astype(np.float32), (d / length[:, None]).astype(np.float32), output=1
    )
    return corners[np.asarray(hit["tfar"]) >= length * (1 - 2e-3)]


def project(points: np.ndarray, view: View, intrinsics: Intrinsics) -> np.ndarray:
    """Pixels (n, 2) of world ``points`` through the distorted camera (OpenCV's model)."""
    m = np.diag([1.0, -1.0, -1.0, 1.0]) @ view.view_matrix().astype(np.float64)
    cam = np.c_[points, np.ones(len(points))] @ m.T
    x, y = cam[:, 0] / cam[:, 2], cam[:, 1] / cam[:, 2]
    r2 = x * x + y * y
    k1, k2, p1, p2 = intrinsics.distortion or (0.0, 0.0, 0.0, 0.0)
    radial = 1 + k1 * r2 + k2 * r2 * r2
    xd = x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x)
    yd = y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y
    return np.c_[intrinsics.fx * xd + intrinsics.cx, intrinsics.fy * yd + intrinsics.cy]


def make_example(
    folder, size: tuple[int, int] = (320, 240), samples: int = 64, seed: int = 0, points: int = 16
) -> dict[str, Path]:
    """Write the example folder (scene.yaml, photograph.png, points.txt, true-camera.json); returns
    the paths by name. ``points``: how many corners to pick (spread over the photograph)."""
    import json

    from ..radiosity import scene_polygons
    from ..scene import load_scene

    root = Path(folder)
    root.mkdir(parents=True, exist_ok=True)
    paths = {
        name: root / file
        for name, file in (
            ("scene", "scene.yaml"),
            ("photograph", "photograph.png"),
            ("points", "points.txt"),
            ("true camera", "true-camera.json"),
        )
    }
    with atomic_output(paths["scene"]) as tmp:
        Path(tmp).write_text(EXAMPLE_SCENE)
    polygons = scene_polygons(load_scene(paths["scene"]))
    view, intrinsics = true_camera(size)
    photo = distort_image(pinhole_photograph(polygons, intrinsics, samples, seed), intrinsics)
    write_image(paths["photograph"], np.clip(photo, 0, None))
    corners = _visible_corners(polygons, np.asarray(view.pose.position, np.float64))
    uv = project(corners, view, intrinsics)
    margin = 6
    inside = ((uv >= margin) & (uv <= np.array(size) - 1 - margin)).all(axis=1)
    corners, uv = corners[inside], uv[inside]
    # spread: farthest-point picks in the image, from the first
    chosen = [0]
    for _ in range(min(points, len(uv)) - 1):
        distance = np.min(np.linalg.norm(uv[:, None] - uv[chosen][None], axis=2), axis=1)
        chosen.append(int(np.argmax(distance)))
    rng = np.random.default_rng(seed)
    clicked = uv[chosen] + rng.normal(0, 0.3, (len(chosen), 2))
    lines = [
        "# u v x y z: a pixel of photograph.png (column, row; the top-left pixel is 0 0) and the model point",
        "# it shows (metres, scene.yaml's frame); picked as a user would, to a third of a pixel",
    ]
    lines += [f"{u:.2f} {v:.2f} {x:.4f} {y:.4f} {z:.4f}" for (u, v), (x, y, z) in zip(clicked, corners[chosen])]
    with atomic_output(paths["points"]) as tmp:
        Path(tmp).write_text("\n".join(lines) + "\n")
    doc = {
        "position": list(view.pose.position),
        "target": list(view.pose.target),
        "up": list(view.pose.up),
        "width": size[0],
        "height": size[1],
        "fx": intrinsics.fx,
        "fy": intrinsics.fy,
        "cx": intrinsics.cx,
        "cy": intrinsics.cy,
        "distortion": list(intrinsics.distortion),
    }
    with atomic_output(paths["true camera"]) as tmp:
        Path(tmp).write_text(json.dumps(doc, indent=2) + "\n")
    return paths
