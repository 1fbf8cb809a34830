"""The hierarchical radiosity technique (Hanrahan et al. 1991; Loscos 1999, ch. 4)."""

from ..core.technique import Technique

TECHNIQUES = (
    Technique(
        name="radiosity",
        title="Hierarchical radiosity (Hanrahan et al. 1991), the engine relighting runs on",
        renderer="illusio.radiosity.renderer:RadiosityRenderer",
        params="illusio.radiosity.params:RadiosityParams",
        subject="illusio.scene.sources:scene_subject",
        source_kind="scene",
        default_source="office",
        presets=("radiosity", "mesh", "links"),
        viewer_mode="illusio.viewer.modes.radiosity:RadiosityMode",
        commands=("radiosity=illusio.cli.radiosity:radiosity",),
        showcase="illusio.gallery.radiosity:radiosity_showcase",
        benchmarks=("radiosity",),
    ),
)
