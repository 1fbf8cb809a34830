"""A "real scene": coarse geometry (polygons, with the lamps marked), one photograph and its camera.

No photograph of a real room ships with the package, so the built-in case makes one: the office's
polygons path-traced by Mitsuba 3 from its ``main`` camera (the same camera and exposure as
``illusio radiosity office --reference``). The model then forgets the true reflectances and lamp
powers: relighting estimates them from the photograph (relight.estimate)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.errors import InputError
from ..core.progress import phase
from ..radiosity import Polygons, scene_polygons
from ..scene.camera import View
from ..scene.sources import resolve_scene
from .params import DEFAULT_PATHS, DEFAULT_SIZE

__all__ = [
    "RealScene",
    "builtin_real_scene",
    "load_real_scene",
    "read_photograph",
    "polygon_ids",
    "PHOTOGRAPH_NAMES",
    "RESPONSES",
]

#: the photograph of a real-scene folder, by the first of these names found
PHOTOGRAPH_NAMES = (
    "photograph.exr",
    "photograph.hdr",
    "photograph.png",
    "photograph.npy",
    "photograph.tif",
    "photograph.tiff",
    "photograph.jpg",
    "photograph.jpeg",
)
#: how a photograph's stored values map to linear radiance: auto (8- and 16-bit PNG, JPEG, TIFF
#: decoded from sRGB, as cameras and editors write them; EXR, Radiance HDR and .npy linear as
#: stored), srgb, linear, or gamma:G (value^G, a camera's plain power-law response)
RESPONSES = ("auto", "srgb", "linear", "gamma:G")
_FLOAT_FORMATS = (".exr", ".hdr", ".npy")


def _response(response: str):
    """The decoding function of a RESPONSES value (values in [0, 1] → linear)."""
    from ..core.images import srgb_to_linear

    if response == "srgb":
        return srgb_to_linear
    if response == "linear":
        return lambda v: v
    if response.startswith("gamma:"):
        try:
            g = float(response[6:])
        except ValueError:
            g = float("nan")
        if not 0.1 <= g <= 10:
            raise InputError(f"--response gamma:G takes G in [0.1, 10], got {response[6:]!r}")
        return lambda v: np.power(np.clip(v, 0, None), g)
    raise InputError(f"--response must be one of {', '.join(RESPONSES)}, got {response!r}")


def read_photograph(path, response: str = "auto") -> np.ndarray:
    """A photograph file as linear radiance (H, W, 3) float32, row 0 at the top: PNG (8 or 16 bits),
    JPEG and TIFF through ``response`` (RESPONSES; auto: sRGB), OpenEXR, Radiance HDR (.hdr, read by
    OpenCV) and .npy as stored (auto; another response is applied to their values as well)."""
    from pathlib import Path

    from ..core.images import read_image

    p = Path(path)
    ext = p.suffix.lower()
    if ext == ".hdr":
        if not p.is_file():
            raise InputError(f"{p}: no such file")
        try:
            import cv2
        except ImportError:
            raise InputError(f"{p}: Radiance HDR is read by OpenCV: pip install 'illusio[photo]'") from None
        bgr = cv2.imread(str(p), cv2.IMREAD_UNCHANGED)
        if bgr is None or bgr.ndim != 3 or bgr.shape[2] < 3:
            raise InputError(f"{p}: not a Radiance HDR image OpenCV can read")
        image = np.ascontiguousarray(bgr[..., 2::-1], np.float32)
    else:
        image = read_image(p, srgb=False)
        if image.ndim != 3 or image.shape[2] < 3:
            raise InputError(f"{p}: the photograph must have three colour channels, got shape {image.shape}")
        image = image[..., :3]
    if response == "auto":
        return image if ext in _FLOAT_FORMATS else _response("srgb")(image).astype(np.float32)
    return np.asarray(_response(response)(image), np.float32)


@dataclass(eq=False)
class RealScene:
    """polygons: the model (its ``lamps`` groups are the real lamps; reflectances and exitances are
    not used); view: the photograph's camera; photograph: radiance, float32 (H, W, 3), row 0 on top."""

    polygons: Polygons
    view: View
    photograph: np.ndarray

    def __post_init__(self):
        photo = np.asarray(self.photograph, np.float32)
        if photo.ndim != 3 or photo.shape[2] < 3 or min(photo.shape[:2]) < 8:
            raise InputError(f"the photograph must be an H×W×3 image of at least 8×8 pixels, got shape {photo.shape}")
        if not np.isfinite(photo).all():
            raise InputError("the photograph has non-finite pixels")
        if (photo[..., :3] < 0).any():
            y, x = np.argwhere((photo[..., :3] < 0).any(axis=2))[0]
            raise InputError(
                f"the photograph has negative values (first at pixel x={x}, y={y}): it must be radiance ≥ 0, linear"
            )
        self.photograph = photo[..., :3]
        if not self.polygons.lamps:
            raise InputError("the real scene has no lamp: relighting estimates the lamps' exitance")

    @property
    def size(self) -> tuple[int, int]:
        return self.photograph.shape[1], self.photograph.shape[0]


def builtin_real_scene(
    name: str = "office",
    size: tuple[int, int] = DEFAULT_SIZE,
    samples: int = DEFAULT_PATHS,
    seed: int = 0,
    denoise: bool | None = None,
) -> RealScene:
    """The built-in case: the polygons of scene ``name`` (a built-in scene, or a scene file: glTF,
    OBJ, YAML, MGF) photographed by Mitsuba from its main camera, at
    ``samples`` paths a pixel and, with ``denoise`` (default: when pyoidn is installed), through Open
    Image Denoise guided by the first hit's albedo and normal — a camera's clean photograph, where
    the raw path tracer's grain would be carried into every relit image."""
    from ..passes.denoise import denoiser_available
    from ..radiosity import render_mitsuba

    scene = resolve_scene(name)
    # each polygon one reflectance (its texture's mean over it): the photograph relighting estimates
    # reflectance from, at the scale of its elements
    polygons = scene_polygons(scene).without_textures()
    view = scene.camera()  # main, or a scene file's first camera
    denoise = denoiser_available() if denoise is None else bool(denoise)
    with phase(f"relight: the photograph, path-traced ({samples} paths a pixel, {size[0]}×{size[1]})"):
        photograph = render_mitsuba(polygons, view, size, samples, seed, denoise=denoise)
    return RealScene(polygons, view, photograph)


#: the model of a real scene, the first of these a folder holds
MODEL_NAMES = ("scene.yaml", "scene.yml", "scene.glb", "scene.gltf", "scene.obj")


def load_real_scene(folder, response: str = "auto", camera_guess: bool = False) -> RealScene:
    """A real scene from a folder: its model (MODEL_NAMES: illusio's scene schema, or glTF or OBJ as
    other tools write it; the lamps are its lights, a surface with an emission is self-luminous), a
    photograph (PHOTOGRAPH_NAMES, read by read_photograph) and its camera — ``camera.json``
    (relight.calibrate: a pose and either full intrinsics with OpenCV's distortion, as
    ``illusio relight calibrate`` writes it, or a vertical fov); without it the folder is refused
    unless ``camera_guess`` takes the model's own camera (a wrong guess relights a wrong image).
    The photograph must be the camera's size when camera.json gives one; a distorted lens's
    photograph is undistorted here, so every pass sees a pinhole's image."""
    from pathlib import Path

    from ..scene import load_scene
    from ..scene.intrinsics import undistort_image
    from ..scene.scene_file import SCENE_FILE_FORMATS, load_scene_file
    from .calibrate import read_camera

    root = Path(folder)
    if not root.is_dir():
        raise InputError(f"{root}: not a folder (a real scene is a folder with scene.yaml and a photograph)")
    scene_file = next((root / n for n in MODEL_NAMES if (root / n).is_file()), None)
    if scene_file is None:
        raise InputError(f"{root}: no model of the real scene ({', '.join(MODEL_NAMES)})")
    photo_file = next((root / n for n in PHOTOGRAPH_NAMES if (root / n).is_file()), None)
    if photo_file is None:
        raise InputError(f"{root}: no photograph ({', '.join(PHOTOGRAPH_NAMES)})")
    scene = load_scene_file(scene_file) if scene_file.suffix in SCENE_FILE_FORMATS else load_scene(scene_file)
    _response(response) if response != "auto" else None  # a bad response named before any reading
    photograph = read_photograph(photo_file, response)
    camera_file = root / "camera.json"
    if camera_file.is_file():
        view, intrinsics, size = read_camera(camera_file)
        if size is not None and size != (photograph.shape[1], photograph.shape[0]):
            raise InputError(
                f"{photo_file} is {photograph.shape[1]}x{photograph.shape[0]} pixels but {camera_file.name} "
                f"says {size[0]}x{size[1]}"
            )
        if intrinsics is not None and intrinsics.distorted:
            photograph = undistort_image(photograph, intrinsics)
    elif camera_guess:
        view = scene.camera()  # main, or a glTF's first camera: the user's explicit guess
    else:
        raise InputError(
            f"{root}: no camera.json (where the photograph was taken from): make it with `illusio relight "
            f"calibrate {photo_file} --points POINTS.txt -o {camera_file}`, or relight with --camera-guess "
            f"(the model's own camera, unchecked)"
        )
    return RealScene(scene_polygons(scene), view, photograph)


def polygon_ids(polygons: Polygons, view: View, size: tuple[int, int]) -> np.ndarray:
    """The polygon seen through each pixel centre, (H, W) int, −1 where none (rays cast with Embree)."""
    from embreex import rtcore_scene
    from embreex.mesh_construction import TriangleMesh

    vertices, faces = polygons.triangles()
    face_polygon = np.r_[np.arange(len(polygons)), np.flatnonzero(~polygons.triangle)]
    scene = rtcore_scene.EmbreeScene()
    TriangleMesh(scene, vertices[faces])
    w, h = size
    directions = view.ray_directions((w, h)).reshape(-1, 3).astype(np.float32)
    origins = np.repeat(np.asarray(view.pose.position, np.float32)[None], len(directions), axis=0)
    prim = np.asarray(scene.run(origins, directions))
    ids = np.where(prim >= 0, face_polygon[np.maximum(prim, 0)], -1)
    return ids.reshape(h, w)
