"""What every viewer mode is: a technique's renderer, its subject and params, a home view and the
navigation that suits it. Modes hold no technique logic: they choose subjects and params and call
the technique's Renderer through the protocol (illusio.core.renderer)."""

from __future__ import annotations

import dataclasses
from typing import ClassVar

import moderngl

from ...core.context import Context
from ...core.errors import InputError
from ...core.params import with_values
from ...core.renderer import Frame, Renderer
from ...scene.camera import Camera, View
from ...scene.sources import is_mesh_source
from ..navigation import FixedCamera, OrbitCamera, WalkCamera

__all__ = ["Mode"]


class Mode:
    """One technique in the viewer.

    ``variants``: the mode's setups (the sis mode's TV, wall, interactive wall, raw stereogram), the
    first the default. ``renderer`` and ``params`` are the technique's; the panel edits ``params``.
    ``render(frame)`` returns the image to show (pooled; the viewer releases it); ``aside()`` an
    optional second image shown beside it (owned by the renderer, a map) and how to show it."""

    name: ClassVar[str] = ""
    variants: ClassVar[tuple[str, ...]] = ("default",)
    #: what the CLI's SOURCE means in this mode, and what the panel calls it
    source_help: ClassVar[str] = ""
    source_label: ClassVar[str] = "source"
    #: built-in sources the panel offers (any file path works too)
    source_choices: ClassVar[tuple[str, ...]] = ()
    #: whether the params carry over from one variant to another (the same params class and meaning)
    shares_params: ClassVar[bool] = False

    def __init__(self, ctx: Context, source: str | None = None, variant: str | None = None):
        self.ctx = ctx
        variant = variant or self.variants[0]
        if variant not in self.variants:
            raise InputError(f"{self.name} mode has no variant {variant!r}; choose one of {', '.join(self.variants)}")
        self.variant = variant
        self.source = source
        self.renderer: Renderer | None = None
        self.params = None
        #: where the pointer is over the image, (x, y) in [0, 1]² from the top left, or None
        self.pointer: tuple[float, float] | None = None

    # -- for the viewer -------------------------------------------------------------------------
    def navigation(self) -> WalkCamera | OrbitCamera | FixedCamera:
        """A fresh camera controller at the mode's home view: orbiting a single mesh, walking a scene."""
        if self.source is not None and is_mesh_source(self.source):
            return OrbitCamera.from_view(self.home_view())
        return WalkCamera.from_view(self.home_view())

    def home_view(self) -> View | None:
        raise NotImplementedError

    def camera_at(self, eye) -> Camera:
        """The lens for a view from ``eye`` (a camera path's): the home view's."""
        return self.home_view().camera

    def image_size(self, size: tuple[int, int]) -> tuple[int, int]:
        """The size of the rendered image in a window of ``size`` (half the width with an aside)."""
        return size

    def render(self, frame: Frame) -> moderngl.Texture:
        return self.renderer.render_texture(frame, self.params)

    def aside(self) -> tuple | None:
        """(texture, "colour" | "depth") or (texture, "grey", scale) to show beside the image, or None."""
        return None

    def panel(self, imgui, viewer) -> None:
        """Widgets of the mode's own beyond its Params (a timeline scrubber...); none by default."""

    def keep_from(self, previous: Mode) -> None:
        """Take over what the user made in ``previous``, the same mode in another variant, beyond
        its params (the relight mode's virtual lamps and crate); nothing by default."""

    def key(self, name: str) -> bool:
        """A letter key (lower case) the viewer itself does not use; True when the mode used it."""
        return False

    def drag(self, dx: float, dy: float) -> bool:
        """A drag with the left button over the image (pixels); True when the mode used it — else the
        camera looks around."""
        return False

    def lamp_sliders(self, imgui, names, largest: float = 4.0) -> None:
        """A slider per lamp for params with ``lamp_scales`` ((name, factor) pairs): the radiosity and
        relight modes' panels."""
        scales = dict(self.params.lamp_scales)
        changed_any = False
        for name in names:
            changed, value = imgui.slider_float(f"{name}##lamp-{self.name}", float(scales.get(name, 1.0)), 0.0, largest)
            if changed:
                scales[name] = value
                changed_any = True
        if changed_any:
            self.params = dataclasses.replace(self.params, lamp_scales=tuple(sorted(scales.items())))

    def set_param(self, name: str, value) -> None:
        """Change one field of ``params`` (dotted for nested Params); raises InputError if refused."""
        self.params = with_values(self.params, **{name: value})

    def release(self) -> None:
        if self.renderer is not None:
            self.renderer.release()
