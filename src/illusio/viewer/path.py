"""Camera paths: the JSON a scripted run plays and a recording writes.

The file is a JSON list of keyframes ``{"t": seconds, "eye": [x, y, z], "target": [x, y, z]}`` in
increasing time. Between keyframes eye and target follow cubic Hermite curves whose tangents are the
finite differences of the neighbouring keyframes over their time span (a non-uniform Catmull–Rom
spline; one-sided differences at the first and last keyframe): the path passes through every
keyframe with a continuous velocity. Before the first and
after the last keyframe it holds still.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..core.errors import InputError
from ..core.files import read_text
from ..core.images import atomic_output
from ..scene.camera import Camera, Pose, View

__all__ = ["Keyframe", "CameraPath", "PathRecorder"]


@dataclass(frozen=True)
class Keyframe:
    t: float
    eye: tuple[float, float, float]
    target: tuple[float, float, float]


class CameraPath:
    """Keyframes and their smooth interpolation (:meth:`at`, :meth:`view`)."""

    def __init__(self, keyframes):
        self.keyframes = tuple(keyframes)
        if not self.keyframes:
            raise InputError("a camera path needs at least one keyframe")
        times = np.array([k.t for k in self.keyframes], np.float64)
        if (np.diff(times) <= 0).any():
            i = int(np.argmax(np.diff(times) <= 0)) + 1
            raise InputError(
                f"keyframe {i + 1}: time {times[i]:g} s is not after the previous one ({times[i - 1]:g} s)"
            )
        self._t = times
        self._eye = np.array([k.eye for k in self.keyframes], np.float64)
        self._target = np.array([k.target for k in self.keyframes], np.float64)

    @property
    def duration(self) -> float:
        """Seconds from t = 0 to the last keyframe."""
        return float(self._t[-1])

    @classmethod
    def parse(cls, text: str, name: str = "camera path") -> CameraPath:
        try:
            data = json.loads(text)
        except json.JSONDecodeError as exc:
            raise InputError(f"{name}: line {exc.lineno}, column {exc.colno}: {exc.msg}") from None
        if not isinstance(data, list):
            raise InputError(f'{name}: expected a JSON list of keyframes {{"t", "eye", "target"}}')
        keyframes = []
        for i, item in enumerate(data, 1):
            if (
                not isinstance(item, dict)
                or set(item) - {"t", "eye", "target"}
                or not {"t", "eye", "target"} <= set(item)
            ):
                raise InputError(f"{name}: keyframe {i} must be an object with exactly t, eye and target")
            try:
                t = float(item["t"])
                eye = tuple(float(v) for v in item["eye"])
                target = tuple(float(v) for v in item["target"])
            except (TypeError, ValueError):
                raise InputError(
                    f"{name}: keyframe {i}: t must be a number, eye and target lists of 3 numbers"
                ) from None
            if len(eye) != 3 or len(target) != 3 or not np.isfinite([t, *eye, *target]).all():
                raise InputError(f"{name}: keyframe {i}: eye and target need 3 finite numbers, t a finite time")
            if np.allclose(eye, target):
                raise InputError(f"{name}: keyframe {i}: eye and target are the same point")
            keyframes.append(Keyframe(t, eye, target))
        try:
            return cls(keyframes)
        except InputError as exc:
            raise InputError(f"{name}: {exc}") from None

    @classmethod
    def load(cls, path: str | os.PathLike) -> CameraPath:
        return cls.parse(read_text(path, "camera path"), str(path))

    def to_json(self) -> str:
        rows = [
            {"t": round(k.t, 6), "eye": [round(v, 6) for v in k.eye], "target": [round(v, 6) for v in k.target]}
            for k in self.keyframes
        ]
        return "[\n" + ",\n".join("  " + json.dumps(r) for r in rows) + "\n]\n"

    def save(self, path: str | os.PathLike) -> Path:
        p = Path(path)
        with atomic_output(p) as tmp:
            Path(tmp).write_text(self.to_json(), encoding="utf-8")
        return p

    def _tangents(self, points: np.ndarray) -> np.ndarray:
        t = self._t
        n = len(t)
        m = np.zeros_like(points)
        if n > 1:  # one-sided at the ends: two keyframes give a straight line at constant speed
            m[0] = (points[1] - points[0]) / (t[1] - t[0])
            m[-1] = (points[-1] - points[-2]) / (t[-1] - t[-2])
        if n > 2:
            m[1:-1] = (points[2:] - points[:-2]) / (t[2:] - t[:-2])[:, None]
        return m

    def at(self, t: float) -> tuple[np.ndarray, np.ndarray]:
        """(eye, target) at time ``t`` seconds."""
        times = self._t
        if len(times) == 1 or t <= times[0]:
            return self._eye[0].copy(), self._target[0].copy()
        if t >= times[-1]:
            return self._eye[-1].copy(), self._target[-1].copy()
        i = int(np.searchsorted(times, t, side="right")) - 1
        span = times[i + 1] - times[i]
        s = (t - times[i]) / span
        h00, h10, h01, h11 = 2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s, -2 * s**3 + 3 * s**2, s**3 - s**2
        out = []
        for points in (self._eye, self._target):
            m = self._tangents(points)
            out.append(h00 * points[i] + h10 * span * m[i] + h01 * points[i + 1] + h11 * span * m[i + 1])
        return out[0], out[1]

    def view(self, t: float, camera: Camera) -> View:
        eye, target = self.at(t)
        return View(Pose(tuple(float(v) for v in eye), tuple(float(v) for v in target)), camera)


class PathRecorder:
    """Collects the views of a walk as keyframes, one every ``interval`` seconds (and the last)."""

    def __init__(self, interval: float = 0.25):
        self.interval = interval
        self.keyframes: list[Keyframe] = []
        self._last: Keyframe | None = None

    def add(self, t: float, view: View) -> None:
        frame = Keyframe(
            float(t), tuple(float(v) for v in view.pose.position), tuple(float(v) for v in view.pose.target)
        )
        if not self.keyframes or t - self.keyframes[-1].t >= self.interval:
            self.keyframes.append(frame)
            self._last = None
        else:
            self._last = frame

    def path(self) -> CameraPath:
        frames = self.keyframes + (
            [self._last] if self._last is not None and self._last.t > self.keyframes[-1].t else []
        )
        return CameraPath(frames)

    def save(self, path: str | os.PathLike) -> Path:
        return self.path().save(path)
