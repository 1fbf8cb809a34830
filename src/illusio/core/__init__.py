"""GPU plumbing shared by every technique: context, programs, textures, images, errors."""

from .context import Context, default_context
from .gl import MAX_SIZE, check_size, set_uniform
from .params import ParamInfo, check_ranges, describe, param, with_values
from .renderer import DEFAULT_SIZE, Frame, Renderer, fingerprint
from .errors import GLUnavailable, IllusioError, InputError, OutputError, ShaderError
from .images import atomic_output, check_output_path, linear_to_srgb, read_image, srgb_to_linear, write_image
from .textures import TexturePool, TextureSpec, readback, upload

__all__ = [
    "Context", "default_context", "Frame", "Renderer", "fingerprint", "DEFAULT_SIZE", "param", "ParamInfo",
    "describe", "check_ranges", "with_values", "set_uniform", "check_size", "MAX_SIZE", "IllusioError", "InputError", "OutputError", "GLUnavailable", "ShaderError",
    "read_image", "write_image", "srgb_to_linear", "linear_to_srgb", "atomic_output", "check_output_path",
    "TexturePool", "TextureSpec", "upload", "readback",
]
