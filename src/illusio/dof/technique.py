"""The stereoscopic depth-of-field technique (Piranda & Desorbier)."""

from ..core.technique import Technique

TECHNIQUES = (
    Technique(
        name="dof",
        title="Stereoscopic depth of field: thin-lens blur by planes around the focus (Piranda & Desorbier)",
        renderer="illusio.dof.renderer:DofRenderer",
        params="illusio.dof.params:DofParams",
        subject="illusio.scene.sources:scene_subject",
        source_kind="scene",
        default_source="museum",
        presets=("walk", "scenario"),
        viewer_mode="illusio.viewer.modes.dof:DofMode",
        commands=("dof=illusio.cli.dof:dof",),
        showcase="illusio.gallery.dof:dof_showcase",
        benchmarks=("dof",),
    ),
)
