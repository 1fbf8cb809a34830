"""Real captures as reference views: an RGB-D folder (Open3D / Redwood layout), a TUM RGB-D sequence,
a COLMAP workspace. Each reader gives :class:`CaptureFrame` s — the photo, the depth in metres along
the view axis (0: a hole), the pinhole intrinsics and the camera-to-world pose in the capture's own
axes (x right, y down, z forward, as OpenCV, Open3D, TUM and COLMAP have them) — and
:func:`frames_to_references` turns the chosen ones into a ReferenceSet: the photo as the recorded
colour and as the albedo (there is no other; relighting a capture relights its photograph), the
normals estimated from the depth, the intrinsics kept whole (principal point off centre, f_x ≠ f_y:
``Camera.from_intrinsics``), lens distortion undone first.

Every mistake is one InputError naming the file and the entry (line, frame)."""

from __future__ import annotations

import json
import math
import re
import warnings
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ..core.errors import InputError
from ..core.files import read_text
from ..core.images import read_image
from ..core.progress import phase
from ..scene.camera import Pose, View
from ..scene.intrinsics import Intrinsics, undistort_image
from .reference_views import ReferenceSet, ReferenceView

__all__ = [
    "Intrinsics",
    "CaptureFrame",
    "read_capture",
    "read_rgbd_folder",
    "read_tum",
    "read_colmap",
    "read_intrinsics",
    "read_trajectory_log",
    "read_colmap_array",
    "normals_from_depth",
    "undistort",
    "frames_to_references",
    "TUM_DEFAULT",
    "KINDS",
]

KINDS = ("rgbd", "tum", "colmap")


#: TUM RGB-D's default intrinsics (its "ROS default" calibration of the Kinect, 640×480)
TUM_DEFAULT = Intrinsics(640, 480, 525.0, 525.0, 319.5, 239.5)


@dataclass
class CaptureFrame:
    """name: where it came from; colour (H, W, 3) linear float32; depth (H, W) metres, 0 = hole;
    pose: camera-to-world 4×4 (camera axes x right, y down, z forward)."""

    name: str
    colour: np.ndarray
    depth: np.ndarray
    intrinsics: Intrinsics
    pose: np.ndarray

    def view(self, far: float) -> View:
        """The frame's camera as illusio's View (y up, looking down −z)."""
        eye, forward, down = self.pose[:3, 3], self.pose[:3, 2], self.pose[:3, 1]
        return View(Pose(tuple(eye), tuple(eye + forward), tuple(-down)), self.intrinsics.camera(0.05, far))


# --- shared readers ---------------------------------------------------------------------------


def read_intrinsics(path) -> Intrinsics:
    """``{"width", "height", "fx", "fy", "cx", "cy"}``, or Open3D's ``{"width", "height",
    "intrinsic_matrix": [9 numbers, column-major]}``."""
    try:
        doc = json.loads(read_text(path, "intrinsics"))
    except json.JSONDecodeError as exc:
        raise InputError(f"{path}: line {exc.lineno}, column {exc.colno}: {exc.msg}") from None
    try:
        if "intrinsic_matrix" in doc:
            k = np.asarray(doc["intrinsic_matrix"], np.float64).reshape(3, 3).T  # stored column-major
            return Intrinsics(int(doc["width"]), int(doc["height"]), k[0, 0], k[1, 1], k[0, 2], k[1, 2])
        return Intrinsics(
            int(doc["width"]),
            int(doc["height"]),
            float(doc["fx"]),
            float(doc["fy"]),
            float(doc["cx"]),
            float(doc["cy"]),
        )
    except (KeyError, TypeError, ValueError, AttributeError) as exc:
        raise InputError(
            f"{path}: intrinsics need width, height and fx, fy, cx, cy or an intrinsic_matrix ({exc})"
        ) from None
    except InputError as exc:
        raise InputError(f"{path}: {exc}") from None


def read_trajectory_log(path) -> list[np.ndarray]:
    """Redwood/Open3D ``.log``: per frame a header line (three integers) then four rows of a 4×4
    camera-to-world matrix."""
    lines = [(k + 1, line.split()) for k, line in enumerate(read_text(path, "trajectory").splitlines()) if line.strip()]
    if len(lines) % 5:
        raise InputError(f"{path}: a trajectory is 5 lines a frame (a header, then 4 rows); it has {len(lines)}")
    poses = []
    for f in range(len(lines) // 5):
        rows = lines[5 * f + 1 : 5 * f + 5]
        try:
            m = np.array([[float(v) for v in words] for _, words in rows])
        except ValueError:
            raise InputError(f"{path}: line {rows[0][0]}: frame {f}: the matrix rows must be numbers") from None
        if m.shape != (4, 4) or not np.isfinite(m).all():
            raise InputError(f"{path}: line {rows[0][0]}: frame {f}: expected a finite 4×4 matrix")
        poses.append(_checked_pose(m, f"{path}: line {rows[0][0]}: frame {f}"))
    return poses


def _checked_pose(m: np.ndarray, where: str) -> np.ndarray:
    r = m[:3, :3]
    if not np.isfinite(m).all() or not np.allclose(r.T @ r, np.eye(3), atol=1e-3) or np.linalg.det(r) < 0:
        raise InputError(f"{where}: not a rigid camera-to-world pose (its rotation is not orthonormal)")
    return m


def _depth_image(path: Path, scale: float) -> np.ndarray:
    """Metres from a 16-bit PNG (÷ scale), a .npy (metres) or COLMAP's .bin (metres)."""
    if path.suffix.lower() == ".bin":
        return read_colmap_array(path)
    if path.suffix.lower() == ".npy":
        d = read_image(path, srgb=False)[..., 0]
    else:
        d = np.round(read_image(path, srgb=False)[..., 0] * 65535.0) / scale
    return np.where(np.isfinite(d) & (d > 0), d, 0.0).astype(np.float32)


def _frame(
    name: str, colour_path: Path, depth_path: Path, intrinsics: Intrinsics, pose: np.ndarray, scale: float
) -> CaptureFrame:
    colour = read_image(colour_path)[..., :3]
    depth = _depth_image(depth_path, scale)
    if depth.shape != colour.shape[:2]:
        raise InputError(
            f"{depth_path}: depth is {depth.shape[1]}×{depth.shape[0]}, its colour "
            f"{colour_path.name} {colour.shape[1]}×{colour.shape[0]}"
        )
    if (intrinsics.width, intrinsics.height) != (colour.shape[1], colour.shape[0]):
        raise InputError(
            f"{colour_path}: the image is {colour.shape[1]}×{colour.shape[0]}, the intrinsics "
            f"{intrinsics.width}×{intrinsics.height}"
        )
    return CaptureFrame(name, colour, depth, intrinsics, pose)


def _check_scale(scale: float) -> float:
    if not (math.isfinite(scale) and scale > 0):
        raise InputError(f"--depth-scale must be positive (depth units per metre), got {scale:g}")
    return scale


_IMAGES = (".png", ".jpg", ".jpeg")


# --- an RGB-D folder ----------------------------------------------------------------------------


def read_rgbd_folder(src, intrinsics=None, poses=None, depth_scale: float = 1000.0) -> list[CaptureFrame]:
    """``color/`` (or ``rgb/``, ``image/``) and ``depth/`` paired by sorted name; ``intrinsic.json``
    (or ``intrinsics``, a file); ``trajectory.log`` (or ``poses``): one pose per frame."""
    root = Path(src)
    _check_scale(depth_scale)
    colour_dir = next((root / d for d in ("color", "rgb", "image") if (root / d).is_dir()), None)
    if colour_dir is None or not (root / "depth").is_dir():
        raise InputError(f"{root}: an RGB-D folder holds color/ (or rgb/, image/) and depth/")
    colours = sorted(p for p in colour_dir.iterdir() if p.suffix.lower() in _IMAGES)
    depths = sorted(p for p in (root / "depth").iterdir() if p.suffix.lower() in (".png", ".npy"))
    if not colours or len(colours) != len(depths):
        raise InputError(
            f"{root}: {len(colours)} colour images and {len(depths)} depth images; they pair by sorted name"
        )
    intrinsics_path = Path(intrinsics) if intrinsics else root / "intrinsic.json"
    if not intrinsics_path.is_file():
        raise InputError(f"{intrinsics_path}: no intrinsics (width, height, fx, fy, cx, cy); give --intrinsics FILE")
    intr = read_intrinsics(intrinsics_path)
    poses_path = Path(poses) if poses else root / "trajectory.log"
    if not poses_path.is_file():
        raise InputError(f"{poses_path}: no poses (a trajectory .log); give --poses FILE")
    trajectory = read_trajectory_log(poses_path)
    if len(trajectory) < len(colours):
        raise InputError(f"{poses_path}: {len(trajectory)} poses for {len(colours)} frames")
    return [_frame(c.name, c, d, intr, trajectory[k], depth_scale) for k, (c, d) in enumerate(zip(colours, depths))]


# --- TUM RGB-D ------------------------------------------------------------------------------------


def _timestamped(path: Path, columns: int) -> list[tuple[float, list[str], int]]:
    out = []
    for k, line in enumerate(read_text(path, "TUM list").splitlines(), 1):
        words = line.split()
        if not words or words[0].startswith("#"):
            continue
        if len(words) != columns:
            raise InputError(f"{path}: line {k}: expected {columns} columns, got {len(words)}")
        try:
            out.append((float(words[0]), words[1:], k))
        except ValueError:
            raise InputError(f"{path}: line {k}: the first column is a timestamp, got {words[0]!r}") from None
    if not out:
        raise InputError(f"{path}: no entries")
    return out


def _quaternion_matrix(qx, qy, qz, qw) -> np.ndarray:
    q = np.array([qw, qx, qy, qz], np.float64)
    n = np.linalg.norm(q)
    if not np.isfinite(n) or n < 1e-9:
        raise ValueError("a zero or non-finite quaternion")
    w, x, y, z = q / n
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def read_tum(src, intrinsics=None, tolerance: float = 0.02, depth_scale: float = 5000.0) -> list[CaptureFrame]:
    """``rgb.txt``, ``depth.txt`` (timestamp, file) and ``groundtruth.txt`` (timestamp tx ty tz qx
    qy qz qw, camera-to-world): each colour frame with the depth and the pose nearest in time,
    within ``tolerance`` seconds (others dropped). Intrinsics: ``intrinsics`` or an
    ``intrinsic.json`` in the folder, else TUM's default (with a warning)."""
    root = Path(src)
    _check_scale(depth_scale)
    for name in ("rgb.txt", "depth.txt", "groundtruth.txt"):
        if not (root / name).is_file():
            raise InputError(f"{root}: a TUM sequence holds rgb.txt, depth.txt and groundtruth.txt; {name} is missing")
    rgb, depth = _timestamped(root / "rgb.txt", 2), _timestamped(root / "depth.txt", 2)
    truth = _timestamped(root / "groundtruth.txt", 8)
    poses = []
    for t, words, line in truth:
        try:
            m = np.eye(4)
            m[:3, 3] = [float(v) for v in words[:3]]
            m[:3, :3] = _quaternion_matrix(*(float(v) for v in words[3:]))
        except ValueError as exc:
            raise InputError(f"{root / 'groundtruth.txt'}: line {line}: {exc}") from None
        if not np.isfinite(m).all():
            raise InputError(f"{root / 'groundtruth.txt'}: line {line}: the pose is not finite")
        poses.append((t, m))
    pose_times = np.array([t for t, _ in poses])
    depth_times = np.array([t for t, _, _ in depth])
    path = Path(intrinsics) if intrinsics else root / "intrinsic.json"
    if path.is_file():
        intr = read_intrinsics(path)
    else:
        warnings.warn(
            f"{root}: no intrinsic.json and no --intrinsics: TUM's default (fx = fy = 525, "
            f"cx = 319.5, cy = 239.5) assumed",
            stacklevel=2,
        )
        intr = TUM_DEFAULT
    frames = []
    for t, (name,), _ in rgb:
        d = int(np.abs(depth_times - t).argmin())
        p = int(np.abs(pose_times - t).argmin())
        if abs(depth_times[d] - t) > tolerance or abs(pose_times[p] - t) > tolerance:
            continue
        frames.append(_frame(name, root / name, root / depth[d][1][0], intr, poses[p][1], depth_scale))
    if not frames:
        raise InputError(f"{root}: no colour frame has a depth and a pose within {tolerance:g} s")
    return frames


# --- COLMAP ---------------------------------------------------------------------------------------

#: COLMAP camera models read, and how many parameters each has
COLMAP_MODELS = {"SIMPLE_PINHOLE": 3, "PINHOLE": 4, "SIMPLE_RADIAL": 4, "OPENCV": 8}


def read_colmap_array(path) -> np.ndarray:
    """A COLMAP dense ``.bin`` map (``width&height&channels&`` then float32, column-major): (H, W)."""
    p = Path(path)
    data = p.read_bytes()
    match = re.match(rb"(\d+)&(\d+)&(\d+)&", data)
    if not match:
        raise InputError(f"{p}: not a COLMAP array (it starts with width&height&channels&)")
    w, h, c = (int(v) for v in match.groups())
    body = data[match.end() :]
    if len(body) != 4 * w * h * c:  # checked in bytes: a file cut mid-value is no whole float32
        raise InputError(
            f"{p}: {len(body):,} bytes of values for a {w}×{h}×{c} map of float32 ({4 * w * h * c:,} bytes): "
            f"{'cut short' if len(body) < 4 * w * h * c else 'too long'}"
        )
    values = np.frombuffer(body, dtype="<f4")
    a = values.reshape((w, h, c), order="F").transpose(1, 0, 2)[..., 0]
    return np.where(np.isfinite(a) & (a > 0), a, 0.0).astype(np.float32)


def _colmap_cameras(path: Path) -> dict[int, Intrinsics]:
    cams = {}
    for k, line in enumerate(read_text(path, "COLMAP cameras").splitlines(), 1):
        words = line.split()
        if not words or words[0].startswith("#"):
            continue
        where = f"{path}: line {k}"
        if len(words) < 4 or words[1] not in COLMAP_MODELS:
            raise InputError(
                f"{where}: camera model {words[1] if len(words) > 1 else '?'!r} is not read; "
                f"models: {', '.join(COLMAP_MODELS)}"
            )
        model, n = words[1], COLMAP_MODELS[words[1]]
        try:
            cid, w, h = int(words[0]), int(words[2]), int(words[3])
            p = [float(v) for v in words[4:]]
        except ValueError:
            raise InputError(f"{where}: camera id, width, height and parameters must be numbers") from None
        if len(p) != n:
            raise InputError(f"{where}: {model} has {n} parameters, got {len(p)}")
        # COLMAP puts the top-left pixel's centre at (0.5, 0.5); OpenCV at (0, 0)
        if model == "SIMPLE_PINHOLE":
            intr = Intrinsics(w, h, p[0], p[0], p[1] - 0.5, p[2] - 0.5)
        elif model == "PINHOLE":
            intr = Intrinsics(w, h, p[0], p[1], p[2] - 0.5, p[3] - 0.5)
        elif model == "SIMPLE_RADIAL":
            intr = Intrinsics(w, h, p[0], p[0], p[1] - 0.5, p[2] - 0.5, "OPENCV", (p[3], 0.0, 0.0, 0.0))
        else:
            intr = Intrinsics(w, h, p[0], p[1], p[2] - 0.5, p[3] - 0.5, "OPENCV", tuple(p[4:]))
        cams[cid] = intr
    return cams


def read_colmap(src) -> list[CaptureFrame]:
    """A COLMAP workspace: ``sparse/`` text model (``cameras.txt``, ``images.txt``: world-to-camera
    quaternion and translation), photos in ``images/``, depth in ``stereo/depth_maps/``
    (``NAME.geometric.bin``, else ``.photometric.bin``, else ``NAME.npy`` or a 16-bit ``NAME.png``,
    millimetres)."""
    root = Path(src)
    sparse = next((d for d in (root / "sparse", root / "sparse" / "0") if (d / "cameras.txt").is_file()), None)
    if sparse is None or not (sparse / "images.txt").is_file():
        raise InputError(f"{root}: a COLMAP workspace holds sparse/cameras.txt and sparse/images.txt (the text model)")
    cams = _colmap_cameras(sparse / "cameras.txt")
    lines = [
        (k, line)
        for k, line in enumerate(read_text(sparse / "images.txt", "COLMAP images").splitlines(), 1)
        if not line.startswith("#")
    ]
    frames = []
    for (k, line), _ in zip(lines[0::2], lines[1::2] + [(0, "")] * (len(lines) % 2)):
        words = line.split()
        if not words:
            continue
        where = f"{sparse / 'images.txt'}: line {k}"
        try:
            q = [float(v) for v in words[1:5]]
            t = np.array([float(v) for v in words[5:8]])
            cid, name = int(words[8]), words[9]
            rotation = _quaternion_matrix(q[1], q[2], q[3], q[0])  # COLMAP writes QW first
        except (ValueError, IndexError):
            raise InputError(f"{where}: expected IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME") from None
        if cid not in cams:
            raise InputError(f"{where}: camera {cid} is not in cameras.txt")
        pose = np.eye(4)
        pose[:3, :3], pose[:3, 3] = rotation.T, -rotation.T @ t  # world-to-camera inverted
        if not np.isfinite(pose).all():
            raise InputError(f"{where}: the pose is not finite")
        maps = root / "stereo" / "depth_maps"
        candidates = [
            maps / f"{name}.geometric.bin",
            maps / f"{name}.photometric.bin",
            maps / f"{Path(name).stem}.npy",
            maps / f"{Path(name).stem}.png",
        ]
        depth = next((c for c in candidates if c.is_file()), None)
        if depth is None:
            raise InputError(
                f"{where}: no depth map for {name} in {maps} (.geometric.bin, .photometric.bin, .npy or .png)"
            )
        frames.append(undistort(_frame(name, root / "images" / name, depth, cams[cid], pose, 1000.0)))
    if not frames:
        raise InputError(f"{sparse / 'images.txt'}: no images")
    return frames


# --- to references --------------------------------------------------------------------------------


def undistort(frame: CaptureFrame) -> CaptureFrame:
    """The frame as a pinhole would have seen it (scene.intrinsics.undistort_image: colour bilinear,
    depth nearest and 0 outside the recorded image — a depth is not blended across an edge)."""
    intr = frame.intrinsics
    if not intr.distorted:
        return replace(frame, intrinsics=intr.pinhole)
    return replace(
        frame,
        colour=undistort_image(frame.colour, intr).astype(np.float32),
        depth=undistort_image(frame.depth, intr, order=0, cval=0.0).astype(np.float32),
        intrinsics=intr.pinhole,
    )


def normals_from_depth(depth: np.ndarray, intrinsics: Intrinsics, max_jump: float = 0.05) -> np.ndarray:
    """(H, W, 3) unit normals in the camera's frame (x right, y down, z forward), facing the camera:
    the cross product of the back-projected points' central differences; where a neighbour is a hole
    or lies across a depth jump (relative, ``max_jump``), the normal faces the camera along its ray."""
    h, w = depth.shape
    v, u = np.mgrid[0:h, 0:w].astype(np.float64)
    z = depth.astype(np.float64)
    points = np.stack([(u - intrinsics.cx) / intrinsics.fx * z, (v - intrinsics.cy) / intrinsics.fy * z, z], axis=-1)
    pad = np.pad(points, ((1, 1), (1, 1), (0, 0)), mode="edge")
    zp = np.pad(z, 1, mode="edge")
    du = pad[1:-1, 2:] - pad[1:-1, :-2]
    dv = pad[2:, 1:-1] - pad[:-2, 1:-1]
    near = [zp[1:-1, 2:], zp[1:-1, :-2], zp[2:, 1:-1], zp[:-2, 1:-1]]
    ok = (z > 0) & np.all([(n > 0) & (np.abs(n - z) <= max_jump * np.maximum(z, 1e-9)) for n in near], axis=0)
    n = np.cross(dv, du)
    length = np.linalg.norm(n, axis=-1, keepdims=True)
    ray = np.stack([(u - intrinsics.cx) / intrinsics.fx, (v - intrinsics.cy) / intrinsics.fy, np.ones_like(u)], axis=-1)
    ray /= np.linalg.norm(ray, axis=-1, keepdims=True)
    n = np.where(ok[..., None] & (length > 1e-12), n / np.maximum(length, 1e-12), -ray)
    n = np.where((np.einsum("ijk,ijk->ij", n, ray) > 0)[..., None], -n, n)  # facing the camera
    return n.astype(np.float32)


def read_capture(kind: str, source, intrinsics=None, poses=None, depth_scale: float | None = None):
    """The frames of a capture folder of ``kind`` ("rgbd", "tum" or "colmap"; depth_scale None: the
    kind's own, 1000 or 5000 units a metre), read inside one reported phase."""
    with phase(f"ibr: reading the {kind} capture"):
        if kind == "rgbd":
            return read_rgbd_folder(source, intrinsics, poses, 1000.0 if depth_scale is None else depth_scale)
        if kind == "tum":
            return read_tum(source, intrinsics, depth_scale=5000.0 if depth_scale is None else depth_scale)
        if kind == "colmap":
            return read_colmap(source)
    raise InputError(f"a capture is rgbd, tum or colmap, got {kind!r}")


def frames_to_references(frames: list[CaptureFrame], chosen: list[int], max_depth: float | None = None) -> ReferenceSet:
    """The ``chosen`` frames as reference views; every frame's camera (chosen or not) kept in
    ``ReferenceSet.frames`` with its photo, for ``--camera frame:K`` and ``--compare-photo K``."""
    if max_depth is not None and not max_depth > 0:
        raise InputError(f"--max-depth must be positive, got {max_depth:g}")
    deepest = max(float(f.depth.max()) for f in frames)
    far = max(1.0, 1.5 * (min(deepest, max_depth) if max_depth else deepest))
    views = []
    with phase(f"ibr: {len(chosen)} reference views from the capture", total=len(chosen)) as view_done:
        for k in chosen:
            f = frames[k]
            depth = np.where(f.depth <= max_depth, f.depth, 0.0) if max_depth else f.depth
            normal_cv = normals_from_depth(depth, f.intrinsics)
            world = (normal_cv.reshape(-1, 3) @ f.pose[:3, :3].T).reshape(normal_cv.shape)  # camera → world
            albedo = np.dstack([f.colour, np.zeros(depth.shape, np.float32)])  # k_s = 0: matte
            normal = np.dstack([world, np.full(depth.shape, 32.0, np.float32)])
            views.append(
                ReferenceView(f.view(far), albedo, normal, np.zeros_like(f.colour), depth.astype(np.float32), f.colour)
            )
            view_done()
    return ReferenceSet(
        views, [], (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), [(f.view(far), f.colour) for f in frames], albedo_from_photo=True
    )
