"""
Depth of field in the museum
============================

The museum through a wide lens (15 cm aperture, to make the blur plain at this size), focused near,
then far: the sampled gather (the default method)
blurs each pixel by its circle of confusion around the focal plane.
"""

from _display import display

from illusio.core.renderer import Frame
from illusio.dof import DofParams, depth_of_field
from illusio.scene import builtin_scene

museum = builtin_scene("museum")
frame = Frame(size=(400, 250))
near = depth_of_field(museum, DofParams(focus_distance=1.5, aperture_mm=150.0), frame)
far = depth_of_field(museum, DofParams(focus_distance=6.0, aperture_mm=150.0), frame)
figure = display(near, far, titles=("focus at 1.5 m", "focus at 6 m"))
