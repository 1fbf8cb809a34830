"""Scene files (issue 42): a textured glTF scene of about a million triangles (three icospheres of
327,680 triangles with uvs and a shared texture, on a textured floor) written by trimesh, read as
illusio's Scene (trimesh's load, then materials, lights and cameras through pygltflib) beside
trimesh's own load of the same file in the same run; the peak memory of each load (tracemalloc:
what Python and NumPy allocate) and one frame drawn from it."""

from __future__ import annotations

import tempfile
import tracemalloc
import warnings
from pathlib import Path

import numpy as np

from illusio.core.context import Context
from illusio.core.renderer import Frame

from .runner import Timing, time_interleaved


def write_scene(path: Path, subdivisions: int) -> int:
    """The test scene at ``path``; returns its triangle count."""
    import trimesh
    from PIL import Image
    from trimesh.visual.material import PBRMaterial

    cells = (np.indices((256, 256)) // 16).sum(0) % 2
    texture = Image.fromarray((cells * 160 + 60).astype(np.uint8)).convert("RGB")
    scene = trimesh.Scene()
    ball = trimesh.creation.icosphere(subdivisions, 0.45)
    uv = np.c_[np.arctan2(ball.vertices[:, 2], ball.vertices[:, 0]) / (2 * np.pi) + 0.5, ball.vertices[:, 1] + 0.5]
    for k, colour in enumerate(([0.8, 0.3, 0.2, 1.0], [0.2, 0.7, 0.3, 1.0], [0.2, 0.3, 0.8, 1.0])):
        copy = ball.copy()
        material = PBRMaterial(f"paint-{k}", baseColorFactor=colour, baseColorTexture=texture, metallicFactor=0.0)
        copy.visual = trimesh.visual.TextureVisuals(uv=uv, material=material)
        at = trimesh.transformations.translation_matrix([k - 1.0, 0.45, 0.0])
        scene.add_geometry(copy, node_name=f"ball-{k}", geom_name=f"ball-{k}", transform=at)
    floor = trimesh.creation.box((4, 0.05, 4))
    floor.visual = trimesh.visual.TextureVisuals(
        uv=floor.vertices[:, [0, 2]] / 4 + 0.5,
        material=PBRMaterial("floor", baseColorTexture=texture, metallicFactor=0.0),
    )
    scene.add_geometry(floor, node_name="floor", geom_name="floor")
    scene.export(str(path))
    return sum(len(g.faces) for g in scene.geometry.values())


def _peak_mb(fn) -> float:
    tracemalloc.start()
    try:
        fn()
        return tracemalloc.get_traced_memory()[1] / 2**20
    finally:
        tracemalloc.stop()


def run(ctx: Context, repeat: int, quick: bool = False) -> tuple[list[Timing], dict[str, float]]:
    import trimesh

    from illusio.passes.scene_renderer import SceneRenderer
    from illusio.scene.scene_file import load_scene_file

    with tempfile.TemporaryDirectory(prefix="illusio-scene-bench-") as tmp:
        path = Path(tmp) / "million.glb"
        triangles = write_scene(path, 5 if quick else 7)
        size_mb = path.stat().st_size / 2**20

        def ours():
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # no light in the file: lamps added, said once
                return load_scene_file(path)

        def theirs():
            return trimesh.load(str(path), force="scene", process=False)

        def theirs_with_normals():  # what drawing needs beside the arrays: vertex normals
            loaded = theirs()
            return [g.vertex_normals for g in loaded.geometry.values()]

        notes = f"{triangles:,} triangles, {size_mb:.0f} MB GLB"
        rounds = max(1, min(repeat, 3))
        timings = time_interleaved(
            {
                "scene-file/illusio load": (ours, notes + "; normals, materials, lights, cameras, checks"),
                "scene-file/trimesh load": (theirs, notes + "; arrays only (trimesh computes on demand)"),
                "scene-file/trimesh load + vertex normals": (theirs_with_normals, notes),
            },
            repeat=rounds,
            warmup=1,
        )
        peak_ours, peak_theirs = _peak_mb(ours), _peak_mb(theirs)
        scene = ours()
        renderer = SceneRenderer(ctx)
        renderer.prepare(scene)
        image = renderer.render(Frame(scene.camera(), (640, 360)))
        assert image.std() > 0.01
        renderer.release()
    by_name = {t.name: t for t in timings}
    ratios = {
        "illusio load / trimesh load (time)": by_name["scene-file/illusio load"].min_ms
        / by_name["scene-file/trimesh load"].min_ms,
        "illusio load / trimesh load + vertex normals (time)": by_name["scene-file/illusio load"].min_ms
        / by_name["scene-file/trimesh load + vertex normals"].min_ms,
        "illusio load peak memory (MB, tracemalloc)": peak_ours,
        "trimesh load peak memory (MB, tracemalloc)": peak_theirs,
        "triangles": float(triangles),
    }
    return timings, ratios
