"""The plain technique: a scene through the shared scene renderer (G-buffer, shadows, shading)."""

from ..core.technique import Technique

TECHNIQUES = (
    Technique(
        name="plain",
        title="Scenes through the shared core: G-buffer, cube shadow maps, Lambert + Phong shading",
        renderer="illusio.passes.scene_renderer:SceneRenderer",
        params="illusio.passes.scene_renderer:RenderSettings",
        subject="illusio.scene.sources:scene_subject",
        source_kind="scene",
        default_source="living-room",
        viewer_mode="illusio.viewer.modes.plain:PlainMode",
        commands=("render=illusio.cli.render:render",),
        benchmarks=("core",),
    ),
)
