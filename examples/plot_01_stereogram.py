"""
A random-dot autostereogram
===========================

The torus knot rendered to a depth map and hidden in random dots by the sequential algorithm of
Dehos et al. (2014): each pixel repeats the one a separation s = W_s + β·D to its left. Decoding the
image back (window matching along each row) finds that separation again; what it gets wrong lies
right of the near object, where two chains of dots fork (the left-anchored algorithms' echoes).
"""

from _display import display

from illusio.core.context import default_context
from illusio.scene import shape
from illusio.sis import StereogramParams, decode_separation, separation_to_depth, stereogram
from illusio.sis.depth import depth_from_scene, hidden_scene

size = (480, 270)
params = StereogramParams(strip_width=60, depth_factor=30)
depth = depth_from_scene(default_context(), hidden_scene(shape("torus-knot")), size)  # 0 = near
image = stereogram(depth, params)

# %%
# The depth map (white: near), the stereogram, and the depth decoded back from the stereogram alone.
found = decode_separation(image, int(params.strip_width), int(params.far_separation))
found = found[0]  # (separation, matching cost)
decoded = separation_to_depth(found, params.strip_width, params.depth_factor)
figure = display(1 - depth, image, 1 - decoded, titles=("depth", "stereogram", "decoded"))
