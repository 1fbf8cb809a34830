"""GPU plumbing shared by every technique: context, programs, textures, images, errors."""

from .context import Context
from .errors import GLUnavailable, IllusioError, InputError, OutputError, ShaderError
from .images import atomic_output, check_output_path, linear_to_srgb, read_image, srgb_to_linear, write_image
from .textures import TexturePool, TextureSpec, readback, upload

__all__ = [
    "Context", "IllusioError", "InputError", "OutputError", "GLUnavailable", "ShaderError",
    "read_image", "write_image", "srgb_to_linear", "linear_to_srgb", "atomic_output", "check_output_path",
    "TexturePool", "TextureSpec", "upload", "readback",
]
