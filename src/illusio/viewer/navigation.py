"""Camera navigation for the viewer: first-person walking (WASD + mouse look) and orbiting a mesh.

Both are plain state machines fed with held keys, mouse moves and scrolls, and produce a
``scene.camera.View``; nothing here knows about windows, so tests drive them directly.
Conventions: yaw 0 looks down −z, positive yaw turns left (towards −x); pitch up is positive;
angles in degrees, distances in metres (scene units), speeds per second.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..scene.camera import Camera, Pose, View

__all__ = ["WalkCamera", "OrbitCamera", "FixedCamera", "MOVE_KEYS"]

#: keys the navigation reads: forward, back, left, right, down, up
MOVE_KEYS = ("w", "s", "a", "d", "q", "e")


def _direction(yaw: float, pitch: float) -> np.ndarray:
    y, p = math.radians(yaw), math.radians(pitch)
    return np.array([-math.sin(y) * math.cos(p), math.sin(p), -math.cos(y) * math.cos(p)])


def _angles(direction) -> tuple[float, float]:
    d = np.asarray(direction, np.float64)
    d = d / max(np.linalg.norm(d), 1e-12)
    return math.degrees(math.atan2(-d[0], -d[2])), math.degrees(math.asin(np.clip(d[1], -1.0, 1.0)))


@dataclass
class WalkCamera:
    """First-person: W/S walk along the view's heading, A/D step sideways, Q/E go down and up; a mouse
    drag turns the head (``sensitivity`` degrees per pixel)."""

    position: np.ndarray
    yaw: float = 0.0
    pitch: float = 0.0
    camera: Camera = field(default_factory=Camera)
    speed: float = 1.5
    sensitivity: float = 0.2
    kind = "walk"

    @classmethod
    def from_view(cls, view: View, speed: float = 1.5) -> WalkCamera:
        eye = np.asarray(view.pose.position, np.float64)
        yaw, pitch = _angles(np.asarray(view.pose.target, np.float64) - eye)
        return cls(eye, yaw, pitch, view.camera, speed)

    @property
    def forward(self) -> np.ndarray:
        return _direction(self.yaw, self.pitch)

    def move(self, keys, dt: float) -> None:
        heading = _direction(self.yaw, 0.0)
        right = np.array([-heading[2], 0.0, heading[0]])
        step = np.zeros(3)
        for key, direction in (
            ("w", heading),
            ("s", -heading),
            ("d", right),
            ("a", -right),
            ("e", np.array([0.0, 1.0, 0.0])),
            ("q", np.array([0.0, -1.0, 0.0])),
        ):
            if key in keys:
                step += direction
        if step.any():
            self.position = self.position + step / np.linalg.norm(step) * self.speed * dt

    def look(self, dx: float, dy: float) -> None:
        self.yaw = (self.yaw - dx * self.sensitivity + 180.0) % 360.0 - 180.0
        self.pitch = float(np.clip(self.pitch - dy * self.sensitivity, -89.0, 89.0))

    def zoom(self, steps: float) -> None:
        self.position = self.position + self.forward * 0.25 * steps

    def view(self) -> View:
        eye = tuple(float(v) for v in self.position)
        return View(Pose(eye, tuple(float(v) for v in self.position + self.forward)), self.camera)


@dataclass
class OrbitCamera:
    """Around a target: a mouse drag or A/D, W/S turn and tilt, the wheel (or Q/E) moves closer and
    farther (``distance`` stays positive)."""

    target: np.ndarray
    distance: float = 3.0
    azimuth: float = 0.0
    elevation: float = 0.0
    camera: Camera = field(default_factory=Camera)
    sensitivity: float = 0.3
    turn_speed: float = 60.0  # degrees per second with keys
    kind = "orbit"
    # near and far planes as shares of the distance, so they follow a zoom (the line drawing's
    # visibility test needs planes that hug the mesh)
    near_ratio: float | None = None
    far_ratio: float | None = None

    @classmethod
    def from_view(cls, view: View) -> OrbitCamera:
        target = np.asarray(view.pose.target, np.float64)
        offset = np.asarray(view.pose.position, np.float64) - target
        distance = float(np.linalg.norm(offset))
        azimuth = math.degrees(math.atan2(offset[0], offset[2]))
        elevation = math.degrees(math.asin(np.clip(offset[1] / max(distance, 1e-12), -1, 1)))
        d = max(distance, 1e-12)
        return cls(
            target,
            distance,
            azimuth,
            elevation,
            view.camera,
            near_ratio=view.camera.near / d,
            far_ratio=view.camera.far / d,
        )

    def move(self, keys, dt: float) -> None:
        turn = self.turn_speed * dt
        self.azimuth += turn * (("d" in keys) - ("a" in keys))
        self.elevation = float(np.clip(self.elevation + turn * (("w" in keys) - ("s" in keys)), -89.0, 89.0))
        self.zoom((("e" in keys) - ("q" in keys)) * dt * 4)

    def look(self, dx: float, dy: float) -> None:
        self.azimuth -= dx * self.sensitivity
        self.elevation = float(np.clip(self.elevation + dy * self.sensitivity, -89.0, 89.0))

    def zoom(self, steps: float) -> None:
        self.distance = max(self.distance * 0.9**steps, 1e-3)

    def view(self) -> View:
        pose = Pose.orbit(tuple(float(v) for v in self.target), self.distance, self.azimuth, self.elevation)
        if self.near_ratio is None:
            return View(pose, self.camera)
        return View(
            pose,
            Camera(
                self.camera.fov_y, self.near_ratio * self.distance, self.far_ratio * self.distance, self.camera.shift
            ),
        )


@dataclass
class FixedCamera:
    """No navigation (a full-screen image): keys and the mouse do nothing."""

    fixed: View | None = None
    kind = "none"

    def move(self, keys, dt: float) -> None:
        pass

    def look(self, dx: float, dy: float) -> None:
        pass

    def zoom(self, steps: float) -> None:
        pass

    def view(self) -> View | None:
        return self.fixed
