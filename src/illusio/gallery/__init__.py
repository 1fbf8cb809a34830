"""The HTML gallery of results that ``illusio demo`` writes: sections of images with captions.

Each technique contributes a *showcase*: a function ``(ctx, out_dir, size) -> Section`` listed in
:data:`SHOWCASES`. The demo runs them in order and writes ``index.html`` linking every image.
"""

from .html import Item, Section, write_gallery
from .showcases import SHOWCASES
from .traced import path_traced

__all__ = ["Item", "Section", "write_gallery", "SHOWCASES", "path_traced"]
