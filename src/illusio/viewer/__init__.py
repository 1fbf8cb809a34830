"""The interactive viewer: every technique live in a window (moderngl-window + imgui), the same
frames offscreen from a camera path. One mode class per technique (viewer/modes/), no technique
logic here: modes call the techniques' Renderers through the protocol of illusio.core.renderer.

Python::

    from illusio.viewer import Viewer, CameraPath
    viewer = Viewer(Context(), "sis", variant="tv", size=(1280, 720))
    viewer.key("w", True); viewer.step(0.5); viewer.screenshot("closer.png")
"""

from .modes import MODES, Mode
from .navigation import FixedCamera, OrbitCamera, WalkCamera
from .path import CameraPath, Keyframe, PathRecorder
from .viewer import Viewer

__all__ = [
    "Viewer",
    "MODES",
    "Mode",
    "CameraPath",
    "Keyframe",
    "PathRecorder",
    "WalkCamera",
    "OrbitCamera",
    "FixedCamera",
]
