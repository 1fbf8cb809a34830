"""What is drawn and from where: meshes, cameras, screens, stereo rigs, scenes, built-in content."""

from .builtin import SCENES, SHAPES, builtin_scene, shape, turntable
from .camera import Camera, Pose, Screen, StereoRig, View
from .loader import load_scene
from .mesh import Mesh, MeshWarning, as_mesh, load_mesh
from .scene import Action, AreaLight, Curve, Material, Node, PointLight, Scene

__all__ = [
    "Mesh",
    "MeshWarning",
    "as_mesh",
    "load_mesh",
    "Camera",
    "Pose",
    "View",
    "Screen",
    "StereoRig",
    "Scene",
    "Action",
    "Node",
    "Material",
    "PointLight",
    "AreaLight",
    "Curve",
    "load_scene",
    "builtin_scene",
    "shape",
    "turntable",
    "SCENES",
    "SHAPES",
]
