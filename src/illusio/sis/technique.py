"""The autostereogram techniques: a stereogram of a depth map, and the multi-scene pipeline that
textures a host surface of a scene with one (Dehos et al. 2014)."""

from __future__ import annotations

from pathlib import Path

from ..core.technique import Technique

#: what the multi-scene subject hides when nothing else is said
DEFAULT_HIDDEN = "torus-knot"


def depth_subject(source: str, size: tuple[int, int], ctx):
    """D (H, W), 0 = near: read from a depth image or .npy, or the depth of a built-in shape or mesh
    file seen as the hidden scene of the paper, at ``size``."""
    from ..scene.sources import is_mesh_source, resolve_mesh
    from .depth import depth_from_scene, hidden_scene, read_depth

    if not is_mesh_source(source) and Path(source).suffix.lower() in (".png", ".npy", ".exr", ".jpg", ".jpeg"):
        return read_depth(source)
    return depth_from_scene(ctx, hidden_scene(resolve_mesh(source)), size)


def multiscene_subject(source: str, size: tuple[int, int], ctx, hidden: str = DEFAULT_HIDDEN):
    """The scene ``source`` hosting a stereogram that hides ``hidden`` (a shape or mesh file)."""
    from ..scene.sources import resolve_mesh, resolve_scene
    from .depth import hidden_scene
    from .multiscene import MultiSceneSubject

    return MultiSceneSubject(resolve_scene(source), hidden_scene(resolve_mesh(hidden)))


TECHNIQUES = (
    Technique(
        name="sis",
        title="Autostereograms of a depth map (Dehos et al. 2014): sequential, strip-parallel, symmetric",
        renderer="illusio.sis.stereogram:StereogramRenderer",
        params="illusio.sis.params:StereogramParams",
        subject="illusio.sis.technique:depth_subject",
        source_kind="depth map or hidden shape",
        default_source=DEFAULT_HIDDEN,
        presets=("raw",),
        viewer_mode="illusio.viewer.modes.sis:SisMode",
        commands=(
            "sis=illusio.cli.sis:sis",
            "sis-decode=illusio.cli.sis:sis_decode",
        ),
        showcase="illusio.gallery.sis:sis_showcase",
        benchmarks=("sis", "sis_quality", "sis_video"),
    ),
    Technique(
        name="sis-scene",
        title="A stereogram on a surface of a 3D scene: the multi-scene pipeline (Dehos et al. 2014)",
        renderer="illusio.sis.multiscene:MultiSceneRenderer",
        params="illusio.sis.params:MultiSceneParams",
        subject="illusio.sis.technique:multiscene_subject",
        source_kind="scene",
        default_source="living-room",
        presets=("tv", "wall", "interactive"),
        viewer_mode="illusio.viewer.modes.sis:SisMode",
        commands=("sis-scene=illusio.cli.sis:sis_scene",),
    ),
)
