"""GPU plumbing shared by every technique: context, programs, textures, images, errors."""

from .lazy import lazy_exports

_EXPORTS = {
    **dict.fromkeys(("Context", "default_context"), "context"),
    **dict.fromkeys(("MAX_SIZE", "check_size", "set_uniform"), "gl"),
    **dict.fromkeys(("ParamInfo", "check_ranges", "describe", "param", "with_values"), "params"),
    **dict.fromkeys(("DEFAULT_SIZE", "Frame", "Renderer", "fingerprint"), "renderer"),
    **dict.fromkeys(("GLUnavailable", "IllusioError", "InputError", "OutputError", "ShaderError"), "errors"),
    **dict.fromkeys(
        ("atomic_output", "check_output_path", "linear_to_srgb", "read_image", "srgb_to_linear", "write_image"),
        "images",
    ),
    **dict.fromkeys(("TexturePool", "TextureSpec", "readback", "upload"), "textures"),
    **dict.fromkeys(("Picture", "show"), "show"),
}

__all__ = list(_EXPORTS)

__getattr__ = lazy_exports(__name__, _EXPORTS)
