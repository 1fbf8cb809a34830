"""Where the focus goes: a fixed distance, a named object of the scene (the distance along the view
axis to its bounding box's centre), or an interactive policy of section 4.2 computed from what the
frame shows (object ids and depths of the G-buffer) or from the viewer (speed, position)."""

from __future__ import annotations

import numpy as np

from ..core.errors import InputError
from ..scene.camera import View
from ..scene.scene import Scene
from ..scene.transforms import transform_points

__all__ = ["object_distance", "POLICIES", "gaze_focus", "largest_focus", "speed_focus", "nearest_exhibit_focus"]


def object_distance(scene: Scene, name: str, view: View) -> float:
    """Metres along ``view``'s axis to the centre of the node named (or tagged) ``name``; at least
    the camera's near plane."""
    nodes = [n for n in scene.nodes if n.name == name or name in n.tags]
    if not nodes:
        raise InputError(
            f"scene {scene.name!r} has no object named {name!r}; objects: " + ", ".join(n.name for n in scene.nodes)
        )
    lo, hi = nodes[0].mesh.bounds
    centre = transform_points(nodes[0].transform, ((np.asarray(lo, np.float64) + hi) / 2)[None])[0]
    eye_space = view.view_matrix().astype(np.float64) @ np.append(centre, 1.0)
    return max(float(-eye_space[2]), view.camera.near)


#: how the focus is chosen each frame (section 4.2): "none" keeps DofParams.focus_distance; "gaze":
#: the object in the view direction (the most seen in a small window at the screen's centre);
#: "largest": the object covering the most of the screen; "speed": a distance ahead that grows with
#: the viewer's speed; "nearest-exhibit": the exhibit nearest the viewer (the museum of Figure 12)
POLICIES = ("none", "gaze", "largest", "speed", "nearest-exhibit")


def _object_depth(object_id: np.ndarray, depth: np.ndarray, chosen: int) -> float:
    """The median view depth of the pixels of object ``chosen`` (ids are node index + 1)."""
    return float(np.median(depth[(object_id == chosen) & (depth > 0)]))


def gaze_focus(object_id: np.ndarray, depth: np.ndarray, window: float = 0.06) -> float | None:
    """The object seen most in a square window ``window`` × the image height at the centre, and the
    median depth of its pixels there (a small window, not one texel: a thin gap does not throw the
    focus to the far wall). None where nothing is there."""
    h, w = depth.shape
    r = max(1, int(round(window * h / 2)))
    ys, xs = slice(h // 2 - r, h // 2 + r), slice(w // 2 - r, w // 2 + r)
    ids, d = object_id[ys, xs], depth[ys, xs]
    seen = ids[(ids > 0) & (d > 0)]
    if seen.size == 0:
        return None
    return _object_depth(ids, d, int(np.bincount(seen).argmax()))


def largest_focus(object_id: np.ndarray, depth: np.ndarray, candidates=None) -> float | None:
    """The object covering the most pixels (among ``candidates``, node index + 1; all by default)
    and the median depth of its pixels."""
    ids = object_id[(object_id > 0) & (depth > 0)]
    if candidates is not None:
        ids = ids[np.isin(ids, np.asarray(sorted(candidates)))]
    if ids.size == 0:
        return None
    return _object_depth(object_id, depth, int(np.bincount(ids).argmax()))


def speed_focus(speed: float, base: float = 2.0, lookahead: float = 1.5) -> float:
    """Metres ahead: ``base`` standing still, plus ``lookahead`` seconds of walking at ``speed``
    (m/s): a moving viewer looks farther ahead (section 4)."""
    return base + lookahead * max(float(speed), 0.0)


def nearest_exhibit_focus(scene: Scene, view: View, tag: str = "exhibit") -> float | None:
    """The distance along the view axis to the exhibit (nodes tagged ``tag``) nearest the viewer
    among those in sight — in front of the eye, within a cone of the vertical field of view around
    the view direction (an exhibit behind the visitor would blur all that is seen). None if none."""
    eye = np.asarray(view.pose.position, np.float64)
    forward = np.asarray(view.pose.target, np.float64) - eye
    forward /= np.linalg.norm(forward)
    cos_limit = np.cos(np.radians(view.camera.fov_y))
    best = None
    for node in scene.nodes:
        if tag not in node.tags or not node.visible:
            continue
        lo, hi = node.mesh.bounds
        centre = transform_points(node.transform, ((np.asarray(lo, np.float64) + hi) / 2)[None])[0]
        offset = centre - eye
        distance = float(np.linalg.norm(offset))
        if distance <= 0 or offset @ forward / distance < cos_limit:
            continue  # out of sight
        if best is None or distance < best[0]:
            best = (distance, node.name)
    return None if best is None else object_distance(scene, best[1], view)
