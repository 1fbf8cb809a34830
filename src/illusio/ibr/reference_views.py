"""Reference views: what image-based rendering draws from. Each holds, per pixel, the surface's
albedo and specular weight, its normal and Phong exponent, its emission and its linear depth (0 =
nothing there), with the camera that saw it; a set also carries the scene's lights, so the new views
can be lit again. Captured from a scene by the rasteriser's G-buffer, saved to and loaded from a
folder (``references.json`` + one ``view-K.npz`` per view), so users can bring their own RGB-D
captures (albedo, depth in metres along the view axis, normals; see :func:`load_references`)."""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..core.context import Context
from ..core.errors import InputError
from ..core.files import load_npz, read_text
from ..core.images import atomic_output, read_image, write_image
from ..core.progress import phase
from ..core.renderer import Frame
from ..passes.scene_renderer import RenderSettings, SceneRenderer
from ..scene.camera import Camera, Pose, View
from ..scene.scene import AreaLight, PointLight, Scene

__all__ = [
    "ReferenceView",
    "ReferenceSet",
    "capture",
    "save_references",
    "load_references",
    "load_cameras",
    "orbit_views",
    "rig_placement",
    "WALL_MARGIN",
]


@dataclass(eq=False)
class ReferenceView:
    """albedo (H, W, 4): albedo rgb and specular k_s; normal (H, W, 4): world normal and Phong
    exponent; emission (H, W, 3); depth (H, W): metres along the view axis, 0 where nothing is;
    colour (H, W, 3), optional: the image as the camera recorded it (rasterised, or path-traced by
    Mitsuba), for the photographic output. Row 0 at the top."""

    view: View
    albedo: np.ndarray
    normal: np.ndarray
    emission: np.ndarray
    depth: np.ndarray
    colour: np.ndarray | None = None  # what the camera recorded (the lit image, a photograph): optional

    def __post_init__(self):
        h, w = np.shape(self.depth)[:2]
        for name, c in (("albedo", 4), ("normal", 4), ("emission", 3)):
            a = np.asarray(getattr(self, name), np.float32)
            if a.ndim == 3 and a.shape[2] == 3 and c == 4:
                a = np.dstack(
                    [
                        a,
                        np.zeros((h, w) if name == "albedo" else (h, w), np.float32)
                        + (0.0 if name == "albedo" else 32.0),
                    ]
                )
            if a.shape != (h, w, c):
                raise InputError(f"reference {name} is {a.shape[1]}×{a.shape[0]}, its depth {w}×{h}")
            if not np.isfinite(a).all():
                raise InputError(f"reference {name} holds non-finite values")
            setattr(self, name, a)
        if self.colour is not None:
            c = np.asarray(self.colour, np.float32)[..., :3]
            if c.shape != (h, w, 3) or not np.isfinite(c).all():
                raise InputError(f"reference colour must be finite and {w}×{h}×3, got {np.shape(self.colour)}")
            self.colour = c
        d = np.asarray(self.depth, np.float32)
        if not np.isfinite(d).all() or (d < 0).any():
            raise InputError("a reference depth holds non-finite or negative values (0 means nothing there)")
        self.depth = d

    @property
    def size(self) -> tuple[int, int]:
        return self.depth.shape[1], self.depth.shape[0]


@dataclass(eq=False)
class ReferenceSet:
    """views: the references; lights, ambient, background: the scene's light, to draw them lit
    again. frames: every frame of an imported capture, references or not, as (View, photo: an
    (H, W, 3) array or the path of its PNG), for ``--camera frame:K`` and ``--compare-photo K``.
    albedo_from_photo: the albedo is the recorded photo (a capture), so it is drawn as recorded."""

    views: list[ReferenceView]
    lights: list = field(default_factory=list)
    ambient: tuple[float, float, float] = (0.08, 0.08, 0.09)
    background: tuple[float, float, float] = (0.02, 0.02, 0.025)
    frames: list = field(default_factory=list)
    albedo_from_photo: bool = False

    def __post_init__(self):
        if not self.views:
            raise InputError("a reference set needs at least one view")
        sizes = {v.size for v in self.views}
        if len(sizes) > 1:
            raise InputError(f"reference views differ in size: {', '.join(f'{w}×{h}' for w, h in sorted(sizes))}")


#: the least room a reference camera keeps between itself and a surface beside it, metres
WALL_MARGIN = 0.3


def rig_placement(scene: Scene, baseline: float) -> tuple[np.ndarray, float]:
    """Where the sideways rig stands and how wide it is: at the main camera's eye when ``baseline``
    fits between the surfaces left and right of it (WALL_MARGIN clear), else slid towards the
    camera's target (up to half way) until it fits, else as wide as the roomiest place allows. A
    camera moved through a wall sees the wall's back from 0.2 m and gives nothing to new views (the
    office's main camera stands 0.4 m from a wall)."""
    from ..scene.raycast import first_hit, world_triangles

    base = scene.camera()
    right, _, _ = base.pose.axes()
    triangles = world_triangles(scene)
    eye = np.asarray(base.pose.position, np.float64)
    ahead = np.asarray(base.pose.target, np.float64) - eye
    best = (eye, 0.0)
    for k in np.linspace(0.0, 0.5, 11):
        centre = eye + k * ahead
        room = min(first_hit(triangles, centre, right), first_hit(triangles, centre, -right)) - WALL_MARGIN
        width = float(max(0.0, min(baseline / 2, room)) * 2)
        if width > best[1] + 1e-9:
            best = (centre, width)
        if width >= baseline - 1e-9:
            break
    return best


def orbit_views(scene: Scene, count: int, baseline: float = 1.2) -> list[View]:
    """``count`` views of ``scene`` from its main camera's eye moved sideways (along the camera's
    right) over ``baseline`` metres, all looking at the camera's target — a rig that stays inside
    the room the main camera is in (:func:`rig_placement` slides or narrows it clear of walls)."""
    base = scene.camera()
    right, _, _ = base.pose.axes()
    eye, baseline = rig_placement(scene, baseline)
    offsets = np.linspace(-baseline / 2, baseline / 2, count) if count > 1 else [0.0]
    return [View(Pose(tuple(eye + right * o), base.pose.target, base.pose.up), base.camera) for o in offsets]


def capture(scene: Scene, views: list[View], size: tuple[int, int], ctx: Context) -> ReferenceSet:
    """Reference views of ``scene`` from ``views``: its G-buffer at ``size``, and the lit image."""
    renderer = SceneRenderer(ctx)
    renderer.prepare(scene)
    refs = []
    with phase(f"ibr: capture {len(views)} views", total=len(views)) as view_done:
        for view in views:
            view_done()
            refs.append(_capture_view(renderer, view, size, ctx))
    renderer.release()
    return ReferenceSet(refs, list(scene.lights), tuple(scene.ambient), tuple(scene.background))


def _capture_view(renderer, view: View, size: tuple[int, int], ctx: Context) -> ReferenceView:
    """One reference view: the G-buffer's maps and the lit image (shadows off)."""
    g = renderer.gbuffer(Frame(view, size))
    images = {k: ctx.readback(t) for k, t in g.textures.items()}
    g.release()
    hit = images["object_id"][..., 0] > 0.5
    lit = renderer.render(Frame(view, size), RenderSettings(shadows=False))
    return ReferenceView(
        view,
        images["colour"],
        images["normal"],
        images["emission"][..., :3],
        np.where(hit, images["depth"][..., 0], 0.0),
        lit,
    )


def _floats(values) -> list[float]:
    return [float(v) for v in values]


def _camera_dict(view: View) -> dict:
    c = view.camera
    return {
        "eye": _floats(view.pose.position),
        "target": _floats(view.pose.target),
        "up": _floats(view.pose.up),
        "fov": float(c.fov_y),
        "near": float(c.near),
        "far": float(c.far),
        "shift": _floats(c.shift),
        "pixel_aspect": float(c.pixel_aspect),
    }


def _light_dict(light) -> dict:
    if isinstance(light, PointLight):
        return {
            "type": "point",
            "position": _floats(light.position),
            "colour": _floats(light.colour),
            "intensity": float(light.intensity),
        }
    return {
        "type": "area",
        "centre": _floats(light.centre),
        "edge_u": _floats(light.edge_u),
        "edge_v": _floats(light.edge_v),
        "colour": _floats(light.colour),
        "radiance": float(light.radiance),
        "samples": int(light.samples),
    }


def _camera_from_dict(cam, where: str) -> View:
    """A camera entry (eye, target, fov, near, far, optionally up and shift) → View."""
    try:
        return View(
            Pose(
                tuple(float(v) for v in cam["eye"]),
                tuple(float(v) for v in cam["target"]),
                tuple(float(v) for v in cam.get("up", (0, 1, 0))),
            ),
            Camera(
                float(cam["fov"]),
                float(cam["near"]),
                float(cam["far"]),
                tuple(float(v) for v in cam.get("shift", (0, 0))),
                float(cam.get("pixel_aspect", 1.0)),
            ),
        )
    except (KeyError, TypeError, ValueError, AttributeError) as exc:
        raise InputError(f"{where}: a camera needs eye, target, fov, near, far ({exc})") from None
    except InputError as exc:
        raise InputError(f"{where}: {exc}") from None


def load_cameras(path: str | os.PathLike) -> list[View]:
    """Cameras to capture from: a JSON list of camera entries (``eye``, ``target``, ``fov`` degrees,
    ``near``, ``far`` metres, optionally ``up`` and ``shift``), or a references.json (its views'
    cameras). Every mistake names the file and the entry."""
    try:
        doc = json.loads(read_text(path, "cameras"))
    except json.JSONDecodeError as exc:
        raise InputError(f"{path}: line {exc.lineno}, column {exc.colno}: {exc.msg}") from None
    if isinstance(doc, dict) and isinstance(doc.get("views"), list):
        entries = [
            (f"{path}: views[{k}]", e.get("camera") if isinstance(e, dict) else None)
            for k, e in enumerate(doc["views"])
        ]
    elif isinstance(doc, list):
        entries = [(f"{path}: camera {k + 1}", e) for k, e in enumerate(doc)]
    else:
        raise InputError(
            f"{path}: expected a JSON list of cameras {{eye, target, fov, near, far}} or a references.json"
        )
    if not 1 <= len(entries) <= 16:
        raise InputError(f"{path}: 1 to 16 cameras, got {len(entries)}")
    return [_camera_from_dict(cam, where) for where, cam in entries]


def save_references(refs: ReferenceSet, folder: str | os.PathLike) -> Path:
    """Write ``folder/references.json`` (cameras, lights) and ``folder/view-K.npz`` (albedo, normal,
    emission, depth), each file atomically."""
    out = Path(folder)
    out.mkdir(parents=True, exist_ok=True)
    entries = []
    for k, v in enumerate(refs.views):
        name = f"view-{k}.npz"
        with atomic_output(out / name) as tmp, open(tmp, "wb") as f:
            extra = {"colour": v.colour} if v.colour is not None else {}
            np.savez_compressed(f, albedo=v.albedo, normal=v.normal, emission=v.emission, depth=v.depth, **extra)
        entries.append({"file": name, "camera": _camera_dict(v.view)})
    frames = []
    for k, (view, photo) in enumerate(refs.frames):
        name = f"frames/frame-{k}.png"
        if not isinstance(photo, (str, os.PathLike)):
            (out / "frames").mkdir(exist_ok=True)
            write_image(out / name, np.asarray(photo))
        elif Path(photo).resolve() != (out / name).resolve():
            (out / "frames").mkdir(exist_ok=True)
            write_image(out / name, read_image(photo))
        frames.append({"photo": name, "camera": _camera_dict(view)})
    doc = {
        "views": entries,
        "lights": [_light_dict(light) for light in refs.lights],
        "ambient": list(refs.ambient),
        "background": list(refs.background),
    }
    if frames:
        doc["frames"] = frames
    if refs.albedo_from_photo:
        doc["albedo_from_photo"] = True
    with atomic_output(out / "references.json") as tmp:
        Path(tmp).write_text(json.dumps(doc, indent=1), encoding="utf-8")
    return out


def load_references(folder: str | os.PathLike) -> ReferenceSet:
    """The reference set in ``folder``: ``references.json`` lists ``views`` (``file``: an .npz with
    ``depth`` (H, W) metres, 0 = nothing, ``albedo`` (H, W, 3 or 4), ``normal`` (H, W, 3 or 4) and
    optionally ``emission``; ``camera``: eye, target, up, fov, near, far[, shift]) and optionally
    ``lights``, ``ambient``, ``background``. Every mistake names the file and the entry."""
    root = Path(folder)
    index = root / "references.json"
    if not index.is_file():
        raise InputError(f"{root}: no references.json (capture one with: illusio ibr capture SCENE -o {root})")
    try:
        doc = json.loads(read_text(index, "reference index"))
    except json.JSONDecodeError as exc:
        raise InputError(f"{index}: line {exc.lineno}, column {exc.colno}: {exc.msg}") from None
    if not isinstance(doc, dict) or not isinstance(doc.get("views"), list):
        raise InputError(f"{index}: expected an object with a list of views")
    views = []
    for k, entry in enumerate(doc["views"]):
        where = f"{index}: views[{k}]"
        if not isinstance(entry, dict) or not isinstance(entry.get("file"), str):
            raise InputError(f"{where}: a view needs a file name and a camera")
        path = root / entry["file"]
        if Path(entry["file"]).is_absolute() or not path.resolve().is_relative_to(root.resolve()):
            raise InputError(
                f"{where}: {entry['file']!r} is outside the folder; a view's file is named "
                "relative to references.json, inside its folder"
            )
        view = _camera_from_dict(entry.get("camera"), where)
        if not path.is_file():
            raise InputError(f"{where}: {path.name} is missing")
        data = load_npz(path, "reference view")
        if not {"depth", "albedo", "normal"} <= set(data):
            raise InputError(f"{where}: {path.name} needs depth, albedo and normal arrays")
        depth = data["depth"]
        emission = data.get("emission", np.zeros(np.shape(depth)[:2] + (3,), np.float32))
        try:
            views.append(ReferenceView(view, data["albedo"], data["normal"], emission, depth, data.get("colour")))
        except (InputError, ValueError, TypeError) as exc:
            raise InputError(f"{where}: {path.name}: {exc}") from None
    if not views:
        raise InputError(f"{index}: no views")
    lights = []
    if not isinstance(doc.get("lights") or [], list):
        raise InputError(f"{index}: lights must be a list")
    for k, ld in enumerate(doc.get("lights") or []):
        try:
            if ld.get("type", "point") == "point":
                lights.append(
                    PointLight(
                        tuple(ld["position"]), tuple(ld.get("colour", (1, 1, 1))), float(ld["intensity"]), shadows=False
                    )
                )
            else:
                lights.append(
                    AreaLight(
                        tuple(ld["centre"]),
                        tuple(ld["edge_u"]),
                        tuple(ld["edge_v"]),
                        tuple(ld.get("colour", (1, 1, 1))),
                        float(ld["radiance"]),
                        samples=int(ld.get("samples", 2)),
                        shadows=False,
                    )
                )
        except (KeyError, TypeError, ValueError, AttributeError) as exc:
            raise InputError(f"{index}: lights[{k}]: a light needs a type and its numbers ({exc})") from None
    colours = {}
    for name, default in (("ambient", (0.08, 0.08, 0.09)), ("background", (0.02, 0.02, 0.025))):
        try:
            colours[name] = tuple(float(c) for c in np.broadcast_to(np.asarray(doc.get(name, default), float), (3,)))
        except (TypeError, ValueError) as exc:
            raise InputError(f"{index}: {name} must be an RGB triple ({exc})") from None
    frames = []
    if not isinstance(doc.get("frames") or [], list):
        raise InputError(f"{index}: frames must be a list")
    for k, entry in enumerate(doc.get("frames") or []):
        where = f"{index}: frames[{k}]"
        if not isinstance(entry, dict) or not isinstance(entry.get("photo"), str):
            raise InputError(f"{where}: a frame needs a photo and a camera")
        photo = root / entry["photo"]
        if Path(entry["photo"]).is_absolute() or not photo.resolve().is_relative_to(root.resolve()):
            raise InputError(f"{where}: {entry['photo']!r} is outside the folder")
        frames.append((_camera_from_dict(entry.get("camera"), where), photo))
    try:
        return ReferenceSet(
            views, lights, colours["ambient"], colours["background"], frames, bool(doc.get("albedo_from_photo", False))
        )
    except InputError as exc:
        raise InputError(f"{index}: {exc}") from None
