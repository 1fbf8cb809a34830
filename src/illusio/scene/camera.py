"""Cameras, poses, physical screens and stereo rigs.

Conventions: world right-handed, y up, metres; the camera looks down its −z axis; angles in degrees.
Pixel coordinates: x to the right, y down, (0, 0) at the top-left corner of the top-left pixel.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from ..core.errors import InputError
from ..core.params import check_ranges, param
from .transforms import frustum, look_at

__all__ = ["Camera", "Pose", "View", "Screen", "StereoRig"]


@dataclass(frozen=True)
class Camera:
    """Perspective projection only (where the camera is comes from :class:`Pose`).

    fov_y: vertical field of view, degrees. near, far: clip distances, metres.

    shift: lens shift (x right, y up) as the tangent of the angle between the view axis and the
    centre of the frustum window; (0, 0) is a symmetric frustum. Stereo rigs use it for off-axis
    frusta (no toe-in); a photograph's principal point off the image centre is a shift too.

    pixel_aspect: f_y / f_x of a pinhole's intrinsics: the frustum's width is tan(fov_y/2) ×
    the image's aspect × this (1: square pixels). See :meth:`from_intrinsics`.
    """

    fov_y: float = 50.0
    near: float = 0.05
    far: float = 100.0
    shift: tuple[float, float] = (0.0, 0.0)
    pixel_aspect: float = 1.0

    @classmethod
    def from_intrinsics(
        cls, width: int, height: int, fx: float, fy: float, cx: float, cy: float, near: float = 0.05, far: float = 100.0
    ) -> Camera:
        """A pinhole's camera from its intrinsics in pixels (OpenCV's convention: the centre of the
        top-left pixel at (0, 0), x right, y down): fov_y from f_y, the principal point as a shift,
        f_x ≠ f_y as pixel_aspect. Its projection puts the point (x, y, z) of the camera's frame at
        pixel (f_x·x/z + c_x, f_y·y/z + c_y), as the intrinsics do."""
        if not (fx > 0 and fy > 0 and width > 0 and height > 0):
            raise InputError(
                f"intrinsics need positive fx, fy, width and height, got fx={fx}, fy={fy}, {width}×{height}"
            )
        fov_y = math.degrees(2 * math.atan(height / (2 * fy)))
        shift = (((width - 1) / 2 - cx) / fx, (cy - (height - 1) / 2) / fy)
        return cls(fov_y, near, far, shift, fy / fx)

    def __post_init__(self):
        if not 0.0 < self.fov_y < 180.0:
            raise InputError(f"camera fov_y must be in ]0, 180[ degrees, got {self.fov_y}")
        if not 0.0 < self.near < self.far:
            raise InputError(f"camera clip distances need 0 < near < far, got near={self.near}, far={self.far}")
        if not 0.0 < self.pixel_aspect < 100.0:
            raise InputError(f"camera pixel_aspect must be in ]0, 100[, got {self.pixel_aspect}")

    def projection(self, aspect: float) -> np.ndarray:
        """OpenGL projection matrix for an image of width/height ``aspect``."""
        t = math.tan(math.radians(self.fov_y) / 2)
        sx, sy = self.shift
        n = self.near
        half_width = t * aspect * self.pixel_aspect
        return frustum(n * (-half_width + sx), n * (half_width + sx), n * (-t + sy), n * (t + sy), n, self.far)


@dataclass(frozen=True)
class Pose:
    """Where the camera is: eye position, the point it looks at, and the up direction."""

    position: tuple[float, float, float] = (0.0, 0.0, 3.0)
    target: tuple[float, float, float] = (0.0, 0.0, 0.0)
    up: tuple[float, float, float] = (0.0, 1.0, 0.0)

    def __post_init__(self):
        for name in ("position", "target", "up"):
            v = np.asarray(getattr(self, name), dtype=float)
            if v.shape != (3,) or not np.isfinite(v).all():
                raise InputError(f"pose {name} must be 3 finite numbers, got {getattr(self, name)}")
            object.__setattr__(self, name, tuple(float(x) for x in v))
        if np.allclose(self.position, self.target):
            raise InputError("pose position and target coincide")

    @classmethod
    def orbit(cls, target=(0.0, 0.0, 0.0), distance: float = 3.0, azimuth: float = 0.0, elevation: float = 0.0) -> Pose:
        """Eye on a sphere around ``target``: azimuth about +y from +z towards +x, elevation up from
        the horizontal plane, both in degrees."""
        az, el = math.radians(azimuth), math.radians(elevation)
        offset = np.array([math.cos(el) * math.sin(az), math.sin(el), math.cos(el) * math.cos(az)]) * distance
        return cls(tuple(np.asarray(target, dtype=float) + offset), tuple(target))

    def matrix(self) -> np.ndarray:
        """World -> camera matrix."""
        return look_at(self.position, self.target, self.up)

    def axes(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(right, up, forward) unit vectors in world space."""
        m = self.matrix().astype(np.float64)
        return m[0, :3], m[1, :3], -m[2, :3]

    def translated(self, offset) -> Pose:
        o = np.asarray(offset, dtype=float)
        return Pose(tuple(np.asarray(self.position) + o), tuple(np.asarray(self.target) + o), self.up)


@dataclass(frozen=True)
class View:
    """A pose seen through a camera."""

    pose: Pose = field(default_factory=Pose)
    camera: Camera = field(default_factory=Camera)

    def view_matrix(self) -> np.ndarray:
        return self.pose.matrix()

    def projection_matrix(self, aspect: float) -> np.ndarray:
        return self.camera.projection(aspect)

    def view_projection(self, size: tuple[int, int]) -> np.ndarray:
        """World → clip space for an image of ``size`` = (width, height): projection @ view."""
        return self.projection_matrix(size[0] / size[1]) @ self.view_matrix()

    def project(self, points: np.ndarray, size: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
        """Pixel coordinates (N, 2) (x right, y down) and linear depths (N,) (metres along the view
        axis) of world ``points`` (N, 3) in an image of ``size`` = (width, height)."""
        w, h = size
        p = np.c_[np.asarray(points, dtype=np.float64), np.ones(len(points))]
        cam = p @ self.view_matrix().astype(np.float64).T
        clip = cam @ self.projection_matrix(w / h).astype(np.float64).T
        ndc = clip[:, :2] / clip[:, 3:4]
        px = np.c_[(ndc[:, 0] + 1) * 0.5 * w, (1 - ndc[:, 1]) * 0.5 * h]
        return px, -cam[:, 2]

    def ray_directions(self, size: tuple[int, int]) -> np.ndarray:
        """World-space unit directions (H, W, 3) through each pixel centre."""
        w, h = size
        proj = self.projection_matrix(w / h).astype(np.float64)
        xs = (np.arange(w) + 0.5) / w * 2 - 1
        ys = 1 - (np.arange(h) + 0.5) / h * 2
        nx, ny = np.meshgrid(xs, ys)
        # invert the frustum mapping at z = -1 in camera space
        cx = (nx + proj[0, 2]) / proj[0, 0]
        cy = (ny + proj[1, 2]) / proj[1, 1]
        d = np.stack([cx, cy, -np.ones_like(cx)], axis=-1)
        rot = self.view_matrix().astype(np.float64)[:3, :3]
        d = d @ rot  # camera -> world (rot is orthonormal: inverse is transpose)
        return d / np.linalg.norm(d, axis=-1, keepdims=True)


@dataclass(frozen=True)
class Screen:
    """A physical display and the viewer in front of it.

    diagonal_cm: d, the screen diagonal. aspect: a = width/height. width_px: w_p.
    height_px: defaults to width_px / aspect. viewing_distance_cm: f, eye to screen.
    eye_separation_cm: e, between the pupils.
    """

    diagonal_cm: float = param(
        53.0, range=(1.0, 10000.0), unit="cm", label="d", flag="screen-diagonal", help="the screen's diagonal"
    )
    aspect: float = param(16 / 9, range=(0.05, 20.0), label="a", help="width / height of the screen")
    width_px: int = param(
        1920, range=(16, 65536), unit="px", step=1, flag="screen-width-px", label="w_p", help="pixels across the screen"
    )
    # None: width_px / aspect (a command that changes either clears it: see Screen.derived)
    height_px: int | None = param(None, panel=False)
    viewing_distance_cm: float = param(
        100.0, range=(1.0, 100000.0), unit="cm", label="f", flag="distance", help="viewer to screen"
    )
    eye_separation_cm: float = param(
        6.5, range=(0.5, 20.0), unit="cm", label="e", flag="eye-separation", help="between the pupils"
    )

    def __post_init__(self):
        for name in ("diagonal_cm", "aspect", "width_px", "viewing_distance_cm", "eye_separation_cm"):
            if not getattr(self, name) > 0:
                raise InputError(f"screen {name} must be positive, got {getattr(self, name)}")
        check_ranges(self)
        if self.height_px is None:
            object.__setattr__(self, "height_px", int(round(self.width_px / self.aspect)))

    def derived(self) -> Screen:
        """This screen with its height in pixels taken again from width_px / aspect."""
        return replace(self, height_px=None)

    @property
    def width_cm(self) -> float:
        """w = a·d / √(1 + a²)."""
        return self.aspect * self.diagonal_cm / math.sqrt(1 + self.aspect**2)

    @property
    def height_cm(self) -> float:
        return self.diagonal_cm / math.sqrt(1 + self.aspect**2)

    @property
    def pixels_per_cm(self) -> float:
        return self.width_px / self.width_cm

    @property
    def fov_y(self) -> float:
        """Vertical angle the screen subtends at the viewer's eye, degrees."""
        return math.degrees(2 * math.atan(self.height_cm / 2 / self.viewing_distance_cm))


@dataclass(frozen=True)
class StereoRig:
    """Left and right views with parallel axes and off-axis frusta (no toe-in).

    view: the cyclopean (centre) view. eye_separation: distance between the two eyes in world
    units (metres). screen_distance: distance of the zero-parallax plane along the view axis: a
    point there projects to the same pixel in both images; farther points have uncrossed parallax.
    """

    view: View
    eye_separation: float = 0.065
    screen_distance: float = 1.0

    def __post_init__(self):
        if not self.eye_separation >= 0:
            raise InputError(f"eye separation must be ≥ 0, got {self.eye_separation}")
        if not self.screen_distance > 0:
            raise InputError(f"screen distance must be positive, got {self.screen_distance}")

    def eye(self, side: int) -> View:
        """side = −1 for the left eye, +1 for the right."""
        right, _, _ = self.view.pose.axes()
        offset = right * (side * self.eye_separation / 2)
        sx, sy = self.view.camera.shift
        shift = (sx - side * self.eye_separation / 2 / self.screen_distance, sy)
        return View(self.view.pose.translated(offset), replace(self.view.camera, shift=shift))

    @property
    def left(self) -> View:
        return self.eye(-1)

    @property
    def right(self) -> View:
        return self.eye(+1)

    @classmethod
    def from_screen(
        cls, screen: Screen, pose: Pose, metres_per_cm: float = 0.01, near: float = 0.05, far: float = 100.0
    ) -> StereoRig:
        """A rig that reproduces the viewer's geometry: the field of view the screen subtends, the
        eye separation and the viewing distance, scaled to the world by ``metres_per_cm``."""
        camera = Camera(fov_y=screen.fov_y, near=near, far=far)
        return cls(
            View(pose, camera), screen.eye_separation_cm * metres_per_cm, screen.viewing_distance_cm * metres_per_cm
        )
