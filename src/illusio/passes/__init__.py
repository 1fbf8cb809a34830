"""Passes shared by several techniques: G-buffer, shadows, shading, and the scene renderer."""

from .forward import ForwardPass, ScreenMaterial
from .gbuffer import GBuffer, GBufferImages, GBufferPass
from .gpu_scene import GpuScene
from .lights import Emitters, emitters_from_lights
from .scene_renderer import RenderSettings, SceneRenderer, render_scene
from .shading import ShadingParams, ShadingPass
from .shadows import ShadowPass
from .stereo import COMPOSITES, StereoCompositePass
from .technique import TECHNIQUES

__all__ = ["TECHNIQUES", "ForwardPass", "ScreenMaterial", "GBuffer", "GBufferImages", "GBufferPass", "GpuScene", "Emitters", "emitters_from_lights",
           "RenderSettings", "SceneRenderer", "render_scene", "ShadingParams", "ShadingPass", "ShadowPass",
           "StereoCompositePass", "COMPOSITES"]
