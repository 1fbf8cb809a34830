"""
Novel views from reference images with depth
============================================

Three reference views of the office are captured with their depth, normals and materials (the
rig stays inside the room). A new camera between the first two is rendered from them alone, as
Porquet (2005) does: each reference's depth becomes a mesh that gives the new view an approximate
depth, then every pixel takes the reference that saw its point nearest (the source view, right).
"""

from _display import display

from illusio.core import Frame
from illusio.core.context import default_context
from illusio.ibr import IbrParams, capture, orbit_views, render_views
from illusio.passes import render_scene
from illusio.scene import View, builtin_scene
from illusio.scene.camera import Pose

office = builtin_scene("office")
size = (320, 240)
views = orbit_views(office, 3, baseline=1.6)
references = capture(office, views, size, default_context())

# %%
# A camera halfway between references 0 and 1, rendered from the references alone, beside the
# scene rasterised from that camera and the reference each pixel was taken from.
a, b = views[0].pose, views[1].pose
halfway = Pose(
    tuple((p + q) / 2 for p, q in zip(a.position, b.position)),
    tuple((p + q) / 2 for p, q in zip(a.target, b.target)),
    a.up,
)
frame = Frame(View(halfway, views[0].camera), size)
image = render_views(references, frame)
sources = render_views(references, frame, IbrParams(show_sources=True))
truth = render_scene(office, frame.view, size)
figure = display(image, truth, sources, titles=("from 3 references", "rasterised", "source view"))
