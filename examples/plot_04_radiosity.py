"""
Hierarchical radiosity of the Cornell box
=========================================

The Cornell box solved by hierarchical radiosity (links refined by the BF criterion, clusters,
gather and push–pull) and drawn by gathering each pixel's light at its own point from the solution
(the final gather: the lamp through exact form factors and shadow rays, the reflected light through
rays to the solved elements).
"""

from _display import display

from illusio.radiosity import RadiosityParams, radiosity_image
from illusio.scene import builtin_scene

box = builtin_scene("cornell-box")
image = radiosity_image(box, (240, 240), RadiosityParams())
figure = display(image, titles=("radiosity",))
