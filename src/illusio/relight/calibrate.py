"""The photograph's camera from points the user picked: 2D–3D correspondences → intrinsics (f_x, f_y,
c_x, c_y, radial k1, k2) and pose, by OpenCV's calibrateCamera on the one view (its pose from
solvePnP first), and the ``camera.json`` a real-scene folder keeps them in.

POINTS file — one correspondence a line, ``u v x y z`` separated by spaces, tabs or commas; ``#``
starts a comment; a first line of names (``u v x y z``) is allowed:

- ``u, v``: the pixel's column and row as an image editor shows them (the top-left pixel is 0, 0;
  OpenCV's convention, fractions allowed);
- ``x, y, z``: the same point in the model's coordinates (metres, the scene.yaml's frame).

At least 6 points, not all on one plane. What is estimated grows with the points: with fewer than
10, one focal length (f_x = f_y), the principal point at the image centre and k1; from 10, f_x, f_y,
c_x, c_y, k1 and k2. Tangential distortion and k3 are kept at 0.

camera.json — ``{"position", "target", "up"}`` (metres, the camera looking from position to
target), ``width``, ``height`` (pixels), ``fx, fy, cx, cy`` (pixels, OpenCV's convention) and
``distortion`` ``[k1, k2, p1, p2]``; or, written by hand, ``fov`` (vertical, degrees) instead of
the intrinsics.
"""

from __future__ import annotations

import json
import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..core.errors import InputError
from ..core.files import read_text
from ..core.images import atomic_output
from ..scene.camera import Camera, Pose, View
from ..scene.intrinsics import Intrinsics

__all__ = [
    "Calibration",
    "read_points",
    "calibrate",
    "write_camera",
    "read_camera",
    "MIN_POINTS",
    "MAX_REPROJECTION_ERROR",
]

MIN_POINTS = 6
#: the most f_y / f_x (or f_x / f_y) a fit may give: beyond it the points are not one camera's view
MAX_PIXEL_ASPECT = 2.0
#: the reprojection error (RMS, pixels) above which a calibration is refused
MAX_REPROJECTION_ERROR = 2.0
#: GL camera axes (y up, looking down −z) ↔ OpenCV's (y down, z forward)
_FLIP = np.diag([1.0, -1.0, -1.0])


@dataclass(frozen=True)
class Calibration:
    """intrinsics (OPENCV, (k1, k2, 0, 0)); view: the camera as illusio's View; errors: each point's
    reprojection error (pixels); rms: their root mean square."""

    intrinsics: Intrinsics
    view: View
    errors: np.ndarray
    rms: float


def read_points(path) -> tuple[np.ndarray, np.ndarray]:
    """(uv (n, 2), xyz (n, 3)) float64 from a POINTS file (the module docstring); a malformed line
    is an InputError naming file, line and column."""
    path = Path(path)
    uv, xyz = [], []
    for number, raw in enumerate(read_text(path, "calibration points (u v x y z per line)").splitlines(), 1):
        line = raw.split("#", 1)[0]
        fields = [(m.group(), m.start() + 1) for m in re.finditer(r"[^\s,]+", line)]
        if not fields:
            continue
        if not uv and [f.lower() for f, _ in fields] == ["u", "v", "x", "y", "z"]:
            continue
        if len(fields) != 5:
            raise InputError(f"{path}:{number}:{fields[0][1]}: a point is 'u v x y z', got {len(fields)} values")
        values = []
        for text, column in fields:
            try:
                value = float(text)
            except ValueError:
                value = math.nan
            if not math.isfinite(value):
                raise InputError(f"{path}:{number}:{column}: {text!r} is not a finite number")
            values.append(value)
        uv.append(values[:2])
        xyz.append(values[2:])
    if len(uv) < MIN_POINTS:
        raise InputError(f"{path}: {len(uv)} points; the camera needs at least {MIN_POINTS}")
    return np.array(uv, np.float64), np.array(xyz, np.float64)


def _cv2():
    try:
        import cv2
    except ImportError:
        raise InputError("calibration needs OpenCV: pip install 'illusio[photo]' (opencv-python-headless)") from None
    return cv2


def calibrate(uv: np.ndarray, xyz: np.ndarray, size: tuple[int, int]) -> Calibration:
    """The camera of an image of ``size`` = (width, height) from correspondences ``uv`` (n, 2)
    pixels ↔ ``xyz`` (n, 3) model coordinates (the module docstring). Started from several focal
    lengths (fields of view 20°–100°), the fit with the least reprojection error kept."""
    cv2 = _cv2()
    uv, xyz = np.asarray(uv, np.float64).reshape(-1, 2), np.asarray(xyz, np.float64).reshape(-1, 3)
    if len(uv) != len(xyz) or len(uv) < MIN_POINTS:
        raise InputError(f"calibration needs at least {MIN_POINTS} pairs of points, got {len(uv)} and {len(xyz)}")
    centred = xyz - xyz.mean(axis=0)
    if np.linalg.svd(centred, compute_uv=False)[-1] < 1e-6 * max(np.abs(centred).max(), 1e-12):
        raise InputError("the calibration points all lie on one plane (or a line): pick points at different depths")
    w, h = size
    few = len(uv) < 10
    flags = cv2.CALIB_USE_INTRINSIC_GUESS | cv2.CALIB_ZERO_TANGENT_DIST | cv2.CALIB_FIX_K3
    if few:
        flags |= cv2.CALIB_FIX_PRINCIPAL_POINT | cv2.CALIB_FIX_ASPECT_RATIO | cv2.CALIB_FIX_K2
    obj, img = [xyz.astype(np.float32)], [uv.astype(np.float32)]
    best = None
    for fov in (20, 35, 50, 65, 80, 100):
        f = (h / 2) / math.tan(math.radians(fov) / 2)
        k = np.array([[f, 0, (w - 1) / 2], [0, f, (h - 1) / 2], [0, 0, 1]])
        try:
            rms, k, dist, rvecs, tvecs = cv2.calibrateCamera(obj, img, (w, h), k, np.zeros(5), flags=flags)
        except cv2.error:
            continue
        if np.isfinite(rms) and k[0, 0] > 0 and k[1, 1] > 0 and (best is None or rms < best[0]):
            best = (rms, k, dist.reshape(-1), rvecs[0], tvecs[0])
    if best is None:
        raise InputError("calibration failed: OpenCV found no camera for these points (are u, v and x, y, z paired?)")
    _, k, dist, rvec, tvec = best
    aspect = float(k[1, 1] / k[0, 0])
    if not 1 / MAX_PIXEL_ASPECT <= aspect <= MAX_PIXEL_ASPECT:  # a camera's pixels are near square
        raise InputError(
            f"calibration found no plausible lens (f_y / f_x = {aspect:.3g}, where a camera's pixels are "
            "near square): check that each u, v is paired with its x, y, z"
        )
    projected = cv2.projectPoints(xyz, rvec, tvec, k, dist)[0].reshape(-1, 2)
    errors = np.linalg.norm(projected - uv, axis=1)
    intrinsics = Intrinsics(
        w,
        h,
        float(k[0, 0]),
        float(k[1, 1]),
        float(k[0, 2]),
        float(k[1, 2]),
        "OPENCV",
        (float(dist[0]), float(dist[1]), 0.0, 0.0),
    )
    rotation = cv2.Rodrigues(rvec)[0]  # world → camera (OpenCV axes)
    eye = -rotation.T @ tvec.reshape(3)
    forward, down = rotation.T @ (0.0, 0.0, 1.0), rotation.T @ (0.0, 1.0, 0.0)
    if (((xyz - eye) @ forward) <= 0).any():
        raise InputError(
            "calibration put some points behind the camera: check that each u, v is paired with its x, y, z"
        )
    depth = float(((xyz - eye) @ forward).max())
    view = View(Pose(tuple(eye), tuple(eye + forward), tuple(-down)), intrinsics.camera(0.05, max(100.0, 4 * depth)))
    return Calibration(intrinsics, view, errors, float(np.sqrt(np.mean(errors**2))))


def write_camera(path, calibration: Calibration) -> Path:
    """camera.json for ``calibration`` (the module docstring), written atomically."""
    i, pose = calibration.intrinsics, calibration.view.pose
    doc = {
        "position": list(pose.position),
        "target": list(pose.target),
        "up": list(pose.up),
        "width": i.width,
        "height": i.height,
        "fx": i.fx,
        "fy": i.fy,
        "cx": i.cx,
        "cy": i.cy,
        "distortion": list(i.distortion) or [0.0, 0.0, 0.0, 0.0],
        "reprojection_error_px": calibration.rms,
    }
    path = Path(path)
    with atomic_output(path) as tmp:
        Path(tmp).write_text(json.dumps(doc, indent=2) + "\n")
    return path


def read_camera(path) -> tuple[View, Intrinsics | None, tuple[int, int] | None]:
    """(view, intrinsics or None, size or None) from a camera.json: with ``fx`` the full intrinsics
    and distortion, else a vertical ``fov`` (degrees) and an optional width, height."""
    path = Path(path)
    try:
        c = json.loads(read_text(path, "a camera (camera.json)"))
        pose = Pose(
            tuple(map(float, c["position"])),
            tuple(map(float, c["target"])),
            tuple(map(float, c.get("up", (0.0, 1.0, 0.0)))),
        )
        size = (int(c["width"]), int(c["height"])) if "width" in c or "height" in c else None
        if "fx" in c:
            if size is None:
                raise KeyError("width and height (with fx, fy, cx, cy)")
            distortion = tuple(float(x) for x in c.get("distortion", ()))
            if distortion and len(distortion) != 4:
                raise ValueError(f"distortion is [k1, k2, p1, p2], got {len(distortion)} values")
            intrinsics = Intrinsics(
                size[0],
                size[1],
                float(c["fx"]),
                float(c["fy"]),
                float(c["cx"]),
                float(c["cy"]),
                "OPENCV" if any(distortion) else "PINHOLE",
                distortion if any(distortion) else (),
            )
            return View(pose, intrinsics.camera(0.05, 100.0)), intrinsics, size
        return View(pose, Camera(fov_y=float(c["fov"]))), None, size
    except InputError as exc:
        raise InputError(f"{path}: {exc}") from None
    except (ValueError, KeyError, TypeError, AttributeError) as exc:
        raise InputError(
            f"{path}: a camera needs position, target and fov, or width, height, fx, fy, cx, cy (and distortion): {exc}"
        ) from None
