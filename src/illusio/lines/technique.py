"""The line-drawing technique: apparent ridges (curvature, view-dependent curvature, the
direction-adaptive filter) beside silhouettes, suggestive contours and ridges/valleys."""

from ..core.technique import Technique

TECHNIQUES = (
    Technique(
        name="lines",
        title="Line drawings: apparent ridges and the classic line types (Judd et al. 2007)",
        renderer="illusio.lines.drawing:LineRenderer",
        params="illusio.lines.params:LineParams",
        subject="illusio.scene.sources:mesh_subject",
        source_kind="mesh",
        default_source="torus-knot",
        presets=("drawing", "q1", "t1", "curvature"),
        viewer_mode="illusio.viewer.modes.lines:LinesMode",
        commands=(
            "lines=illusio.cli.lines:lines",
            "curvature=illusio.cli.lines:curvature",
        ),
        showcase="illusio.gallery.lines:lines_showcase",
        benchmarks=("lines", "lines_transfer"),
    ),
)
