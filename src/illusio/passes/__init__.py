"""Passes shared by several techniques: G-buffer, shadows, shading, and the scene renderer.

Names are imported on first use (``core.lazy``): a Params that holds ``RenderSettings`` loads no GL."""

from ..core.lazy import lazy_exports

_EXPORTS = {
    "TECHNIQUES": "technique",
    **dict.fromkeys(("ForwardPass", "ScreenMaterial"), "forward"),
    **dict.fromkeys(("GBuffer", "GBufferImages", "GBufferPass"), "gbuffer"),
    "GpuScene": "gpu_scene",
    **dict.fromkeys(("Emitters", "emitters_from_lights"), "lights"),
    **dict.fromkeys(("SceneRenderer", "render_scene"), "scene_renderer"),
    **dict.fromkeys(("RenderSettings", "COMPOSITES"), "settings"),
    **dict.fromkeys(("ShadingParams", "ShadingPass"), "shading"),
    "ShadowPass": "shadows",
    "StereoCompositePass": "stereo",
}

__all__ = list(_EXPORTS)

__getattr__ = lazy_exports(__name__, _EXPORTS)
