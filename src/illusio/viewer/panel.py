"""The imgui panel: technique, variant and camera controls, the frame-time readout, and a widget for
every field of the mode's Params, generated from its field metadata (illusio.core.params): sliders
with the declared ranges, check boxes for flags and for each choice of a multiple choice, combos for
single choices, a tree node per nested Params, the fields in their groups (core.params.GROUPS: the
method and the paper's parameters shown, the output under an open header, advanced settings under a
closed one). A change goes through ``Viewer.set_param``."""

from __future__ import annotations

from pathlib import Path

from ..core.params import GROUPS, ParamInfo, describe
from .modes import MODES
from .viewer import Viewer

__all__ = ["GLYPH_RANGES", "draw_fields", "draw_panel", "load_panel_font", "panel_font_path", "widget_value"]

#: the panel's font size (px); its face is Roboto, which imgui_bundle ships: ImGui's own font has ASCII
#: only, so ρ, τ, λ, ε and the dashes of the labels showed as "?"
PANEL_FONT_SIZE = 16.0
#: what of the face is loaded, as (first, last) code points: Latin-1, Greek, general punctuation (the
#: dashes), arrows and mathematical operators (−, √); a test keeps every label's characters inside
#: them and in the face
GLYPH_RANGES = ((0x20, 0xFF), (0x370, 0x3FF), (0x2010, 0x2027), (0x2190, 0x21FF), (0x2200, 0x22FF))
#: the panel's width (window px): the longest labels beside a widget of useful width. The window
#: keeps it as a column left of the image, so the image is the size asked for, at its aspect
PANEL_WIDTH = 480

#: groups drawn under a header (open or closed at first); the others are drawn as they are
_HEADERS = {"output": True, "advanced": False}


def widget_value(info: ParamInfo, imgui):
    """Draw the widget for one field; returns (changed, new value)."""
    label = f"{info.title}##{info.name}"
    if info.kind == "bool":
        return imgui.checkbox(label, bool(info.value))
    if info.kind == "float":
        lo, hi = info.range or (min(0.0, info.value), max(1.0, 2 * info.value))
        flags = imgui.SliderFlags_.logarithmic.value if info.log else 0
        return imgui.slider_float(label, float(info.value), float(lo), float(hi), "%.3g", flags)
    if info.kind == "int":
        lo, hi = info.range or (0, max(10, 2 * info.value))
        if hi - lo <= 4096:
            return imgui.slider_int(label, int(info.value), int(lo), int(hi))
        changed, value = imgui.input_int(label, int(info.value), int(info.step or 1))
        return changed, int(min(max(value, lo), hi))
    if info.kind == "choice":
        changed, value = False, info.value
        if imgui.begin_combo(label, str(info.value)):
            for choice in info.choices:
                picked, _ = imgui.selectable(str(choice), choice == info.value)
                if picked and choice != info.value:
                    changed, value = True, choice
            imgui.end_combo()
        return changed, value
    if info.kind == "multi":
        imgui.text(info.title)
        chosen = list(info.value)
        changed = False
        for choice in info.choices:
            on, now = imgui.checkbox(f"{choice}##{info.name}.{choice}", choice in chosen)
            if on:
                changed = True
                chosen = [c for c in info.choices if (c in chosen or c == choice) and (now or c != choice)]
        return changed, tuple(chosen)
    imgui.text(f"{info.title}: {info.value}")
    return False, info.value


def _fields(viewer: Viewer, infos, imgui, prefix: str = "") -> None:
    for info in infos:
        name = prefix + info.name
        if info.kind == "params":
            if imgui.tree_node(f"{info.title}##{name}"):
                _fields(viewer, info.children, imgui, name + ".")
                imgui.tree_pop()
            continue
        changed, value = widget_value(info, imgui)
        if changed:
            viewer.set_param(name, value)
        if info.help and imgui.is_item_hovered():
            imgui.set_tooltip(info.help)


def panel_font_path() -> Path | None:
    """Roboto-Regular.ttf as imgui_bundle ships it (None without it)."""
    try:
        import imgui_bundle
    except ImportError:
        return None
    path = Path(imgui_bundle.__file__).parent / "assets" / "fonts" / "Roboto" / "Roboto-Regular.ttf"
    return path if path.is_file() else None


def load_panel_font(imgui) -> bool:
    """Make the panel's font ImGui's default (call before the renderer builds the font texture);
    False, and ImGui's own font kept, where the face is not there."""
    path = panel_font_path()
    if path is None:
        return False
    ranges = [c for pair in GLYPH_RANGES for c in pair] + [0]
    imgui.get_io().fonts.add_font_from_file_ttf(str(path), PANEL_FONT_SIZE, None, ranges)
    return True


def draw_fields(viewer: Viewer, infos, imgui) -> None:
    """The widgets of ``infos`` (describe's) by group, in GROUPS' order; the widgets leave room
    for the longest label at their right, so no label is cut."""
    longest = max((imgui.calc_text_size(info.title).x for info in infos), default=0.0)
    imgui.push_item_width(-(longest + 12.0))
    for group, title in GROUPS.items():
        members = [info for info in infos if info.group == group]
        if not members:
            continue
        if group in _HEADERS:
            flags = imgui.TreeNodeFlags_.default_open.value if _HEADERS[group] else 0
            if not imgui.collapsing_header(title, flags):
                continue
        _fields(viewer, members, imgui)
    imgui.pop_item_width()


def draw_panel(viewer: Viewer, imgui, actions: dict, state: dict | None = None, height: float | None = None) -> None:
    """The panel for the viewer's current mode. ``actions``: callbacks the window provides
    ("screenshot"); ``state``: what the panel keeps between frames (the file field's text);
    ``height``: the window's height (px), the panel then a fixed column PANEL_WIDTH wide at its left
    (None: a floating panel that starts at the top left)."""
    state = {} if state is None else state
    if height is None:
        imgui.set_next_window_pos((10, 10), imgui.Cond_.first_use_ever.value)
        imgui.set_next_window_size((PANEL_WIDTH, 0), imgui.Cond_.first_use_ever.value)
        imgui.begin("illusio")
    else:
        imgui.set_next_window_pos((0, 0), imgui.Cond_.always.value)
        imgui.set_next_window_size((PANEL_WIDTH, float(height)), imgui.Cond_.always.value)
        fixed = imgui.WindowFlags_
        imgui.begin("illusio", None, fixed.no_move.value | fixed.no_resize.value | fixed.no_collapse.value)
    ms = viewer.frame_ms
    imgui.text(f"{ms:.1f} ms a frame ({1000 / ms if ms > 0 else 0:.0f} fps), {viewer.size[0]}x{viewer.size[1]}")
    mode = viewer.mode
    if imgui.begin_combo("technique", mode.name):
        for name in MODES:
            if imgui.selectable(name, name == mode.name)[0] and name != mode.name:
                viewer.set_mode(name)
        imgui.end_combo()
    if len(mode.variants) > 1 and imgui.begin_combo("view", mode.variant):
        for variant in mode.variants:
            if imgui.selectable(variant, variant == mode.variant)[0] and variant != mode.variant:
                viewer.set_variant(variant)
        imgui.end_combo()
    if imgui.begin_combo(mode.source_label, str(mode.source)):
        for name in mode.source_choices:
            if imgui.selectable(name, name == mode.source)[0] and name != mode.source:
                viewer.set_source(name)
        imgui.end_combo()
    _, state["path"] = imgui.input_text("file##source", state.get("path", ""))
    imgui.same_line()
    if imgui.button("open") and state["path"].strip():
        viewer.set_source(state["path"].strip())
    if imgui.button("home (H)"):
        viewer.home()
    imgui.same_line()
    if imgui.button("screenshot (P)"):
        actions["screenshot"]()
    imgui.text(f"navigation: {viewer.navigation.kind}; Tab technique, V view")
    imgui.separator()
    viewer.mode.panel(imgui, viewer)
    draw_fields(viewer, describe(viewer.mode.params), imgui)
    if viewer.last_error:
        imgui.text_colored((1.0, 0.4, 0.3, 1.0), viewer.last_error)
    imgui.end()
