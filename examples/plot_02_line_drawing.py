"""
Apparent ridges of a trimesh mesh
=================================

A line drawing (Judd et al. 2007, by the hybrid GPU method) of a mesh made with trimesh: a trimesh
``Trimesh`` goes wherever illusio takes a mesh. The drawing holds the apparent ridges and the
silhouettes on white paper.
"""

import numpy as np
import trimesh
from _display import display

from illusio.lines import LineParams, line_drawing

ball = trimesh.creation.icosphere(subdivisions=5)
bumps = np.sin(5 * ball.vertices[:, [0]]) * np.cos(4 * ball.vertices[:, [1]]) * np.sin(3 * ball.vertices[:, [2]])
ball.vertices *= 1 + 0.25 * bumps  # a lumpy ball

ridges = line_drawing(ball, size=(360, 360))
more = line_drawing(ball, LineParams(lines=("apparent-ridges", "silhouettes", "suggestive")), size=(360, 360))
figure = display(ridges, more, titles=("apparent ridges, silhouettes", "+ suggestive contours"))
