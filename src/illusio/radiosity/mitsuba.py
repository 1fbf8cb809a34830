"""Ground truth: the same polygons path-traced by Mitsuba 3 (diffuse BSDFs of reflectance ρ — a
textured polygon's the reflectance image through its uvs —, area emitters of radiance E/π, no other
light), and the score of a radiosity render against it.

Both images are radiance (W/(m²·sr)) in linear RGB for the same camera, so they compare pixel to
pixel once written with the same exposure and sRGB encoding."""

from __future__ import annotations

import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..core.progress import phase
from ..passes.mitsuba import load_mitsuba, load_scene, render, rgb, sensor
from ..scene.camera import View
from .polygons import Polygons

__all__ = ["render_mitsuba", "score", "Score"]


def _scene_dict(polygons: Polygons, folder: Path) -> dict:
    """Mitsuba's scene of ``polygons``: one mesh a shape — the polygons of one texture, or the
    untextured ones of one exitance and sidedness — holding only its own vertices; an untextured
    shape's reflectance is a face attribute (each triangle its polygon's), so a scene whose polygons
    each carry their own reflectance (``without_textures``) stays a handful of shapes."""
    import trimesh

    mi = load_mitsuba()
    out: dict = {"type": "scene"}
    uv = polygons.corner_uv()
    side = polygons.sides()
    textured = np.isin(polygons.group, list(polygons.textures)) & np.isfinite(uv).all(axis=(1, 2))
    # a textured polygon is grouped by its texture; a two-sided surface is its front with Mitsuba's
    # twosided BSDF (its twin, at the same place, left out)
    material = np.c_[polygons.exitance, np.where(textured, polygons.group, -1), side]
    _, group = np.unique(np.round(material, 9), axis=0, return_inverse=True)
    group = np.where(side == 2, -1, group.reshape(-1))
    vertices, faces = polygons.triangles()
    face_polygon = np.r_[np.arange(len(polygons)), np.flatnonzero(~polygons.triangle)]
    for g in np.unique(group[group >= 0]):
        members = np.flatnonzero(group == g)
        take = np.flatnonzero(np.isin(face_polygon, members))
        used, local = np.unique(faces[take], return_inverse=True)
        path = folder / f"group-{g}.ply"
        mesh = trimesh.Trimesh(vertices[used].astype(np.float64), local.reshape(-1, 3), process=False)
        k = members[0]
        if textured[k]:  # the reflectance image through the uvs (Mitsuba's v runs down the image)
            mesh.visual = trimesh.visual.TextureVisuals(uv=uv.reshape(-1, 2)[used])
            image = np.ascontiguousarray(polygons.textures[int(polygons.group[k])][::-1], np.float32)
            reflectance = {"type": "bitmap", "bitmap": mi.Bitmap(image), "raw": True}
        else:
            reflectance = {"type": "mesh_attribute", "name": "face_reflectance"}
        mesh.export(path)
        bsdf = {"type": "diffuse", "reflectance": reflectance}
        shape = {
            "type": "ply",
            "filename": str(path),
            "face_normals": True,
            "bsdf": {"type": "twosided", "bsdf": bsdf} if side[k] == 1 else bsdf,
        }
        if polygons.exitance[k].max() > 0:
            shape["emitter"] = {"type": "area", "radiance": rgb(polygons.exitance[k] / np.pi)}
        shape = mi.load_dict(shape)
        if not textured[k]:
            shape.add_attribute("face_reflectance", 3, polygons.reflectance[face_polygon[take]].ravel().tolist())
        out[f"group_{g}"] = shape
    return out


def render_mitsuba(
    polygons: Polygons,
    view: View,
    size: tuple[int, int],
    samples: int = 256,
    seed: int = 0,
    max_depth: int = -1,
    denoise: bool = False,
) -> np.ndarray:
    """Radiance (H, W, 3) float32 of ``polygons`` seen from ``view``: Mitsuba's path tracer with
    ``samples`` paths a pixel (box filter), unbounded path length (Russian roulette) by default.
    ``denoise``: through Open Image Denoise (``passes.denoise``), guided by the first hit's albedo
    and normal that the same paths give (Mitsuba's aov integrator)."""
    with phase(f"path tracing {size[0]}×{size[1]} at {samples} paths a pixel (Mitsuba)"):
        return _render_mitsuba(polygons, view, size, samples, seed, max_depth, denoise)


def _render_mitsuba(polygons, view, size, samples, seed, max_depth, denoise) -> np.ndarray:
    mi = load_mitsuba()
    integrator = {"type": "path", "max_depth": int(max_depth)}
    if denoise:
        integrator = {"type": "aov", "aovs": "albedo:albedo,normal:sh_normal", "integrator": integrator}
    with tempfile.TemporaryDirectory(prefix="illusio-radiosity-") as tmp:
        doc = _scene_dict(polygons, Path(tmp))
        doc["sensor"] = sensor(mi, view, size, samples, seed)
        doc["integrator"] = integrator
        image = np.array(render(mi, load_scene(mi, doc), seed=int(seed)), np.float32)
    if denoise:  # channels: the path tracer's RGB, then albedo, then normal
        from ..passes.denoise import denoise as oidn

        return oidn(np.clip(image[..., :3], 0, None), image[..., 3:6], image[..., 6:9])
    return np.clip(image[..., :3], 0, None)


@dataclass(frozen=True)
class Score:
    """mean_relative_error: the mean over scored pixels of |R − M| / M (RGB means); psnr: dB over the
    scored pixels with the reference's 99th percentile as the peak; pixels: how many were scored."""

    mean_relative_error: float
    psnr: float
    pixels: int


def score(
    render: np.ndarray, reference: np.ndarray, mask: np.ndarray | None = None, floor: float = 0.01, block: int = 1
) -> Score:
    """Score ``render`` against ``reference`` (both radiance, same exposure) over ``mask`` (e.g. the
    non-emitter geometry), leaving out pixels darker than ``floor`` × the reference's mean (a
    relative error of near-black is noise). ``block``: both images first averaged over block×block
    pixel squares (a square scored when wholly inside the mask), so a path tracer's per-pixel noise
    mostly averages out (the image is cropped to whole squares)."""
    if block > 1:
        h, w = (np.shape(reference)[0] // block) * block, (np.shape(reference)[1] // block) * block

        def squares(a):
            a = np.asarray(a, np.float64)[:h, :w]
            return a.reshape(h // block, block, w // block, block, *a.shape[2:]).mean(axis=(1, 3))

        whole = None if mask is None else squares(np.asarray(mask, np.float64)) == 1.0
        return score(squares(np.asarray(render)[..., :3]), squares(np.asarray(reference)[..., :3]), whole, floor)
    r = np.asarray(render, np.float64)[..., :3].mean(axis=2)
    m = np.asarray(reference, np.float64)[..., :3].mean(axis=2)
    keep = (
        np.ones(m.shape, bool) if mask is None else np.array(mask, bool)
    )  # a copy: the caller's mask is not ours to change
    keep &= m > floor * m[keep].mean()
    rel = np.abs(r - m)[keep] / m[keep]
    peak = np.percentile(np.asarray(reference, np.float64)[keep], 99)
    mse = ((np.asarray(render, np.float64)[..., :3] - np.asarray(reference, np.float64)[..., :3])[keep] ** 2).mean()
    return Score(float(rel.mean()), float(10 * np.log10(peak**2 / max(mse, 1e-30))), int(keep.sum()))
