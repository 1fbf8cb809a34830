"""The panel is generated from the Params' field metadata: each field gets the widget its kind asks
for, with the declared range, and an edit goes through Viewer.set_param (tested with a stand-in for
imgui that records the widgets and answers scripted edits)."""

import pytest

from illusio.core.params import describe
from illusio.lines.params import LineParams
from illusio.sis.multiscene import MultiSceneParams
from illusio.viewer.panel import widget_value


class FakeImgui:
    """Records widget calls; answers the edits in ``edits`` (label prefix -> new value)."""

    class SliderFlags_:
        class logarithmic:
            value = 32

    class TreeNodeFlags_:
        class default_open:
            value = 32

    def __init__(self, edits=None):
        self.calls = []
        self.edits = edits or {}

    def _answer(self, label, value):
        for prefix, new in self.edits.items():
            if label.startswith(prefix):
                return True, new
        return False, value

    def checkbox(self, label, value):
        self.calls.append(("checkbox", label))
        return self._answer(label, value)

    def slider_float(self, label, value, lo, hi, fmt="%.3f", flags=0):
        self.calls.append(("slider_float", label, lo, hi, flags))
        return self._answer(label, value)

    def slider_int(self, label, value, lo, hi):
        self.calls.append(("slider_int", label, lo, hi))
        return self._answer(label, value)

    def input_int(self, label, value, step):
        self.calls.append(("input_int", label, step))
        return self._answer(label, value)

    def begin_combo(self, label, preview):
        self.calls.append(("combo", label))
        self._combo = label
        return True

    def selectable(self, label, selected):
        picked = self.edits.get(self._combo.split("##")[0]) == label
        return picked, selected

    def end_combo(self):
        pass

    def text(self, text):
        self.calls.append(("text", text))

    def collapsing_header(self, title, flags):
        self.calls.append(("header", title, flags))
        return bool(flags)  # as at first: open where it opens by default

    def tree_node(self, label):
        self.calls.append(("tree", label))
        return True

    def tree_pop(self):
        pass

    def is_item_hovered(self):
        return False

    def calc_text_size(self, text):
        return type("Size", (), {"x": 7.0 * len(text), "y": 16.0})()

    def push_item_width(self, width):
        self.calls.append(("item width", width))

    def pop_item_width(self):
        self.calls.append(("item width", None))


def test_widgets_follow_the_metadata():
    infos = {i.name: i for i in describe(LineParams())}
    imgui = FakeImgui()
    widget_value(infos["tau"], imgui)
    widget_value(infos["relative"], imgui)
    widget_value(infos["min_ridge_pixels"], imgui)
    assert imgui.calls[0] == ("slider_float", "τ##tau", -12.0, 12.0, 0)
    assert imgui.calls[1][0] == "checkbox"
    assert imgui.calls[2] == (
        "input_int",
        "min ridge pixels (px)##min_ridge_pixels",
        1,
    )  # a range too wide for a slider
    settings = next(i for i in describe(MultiSceneParams()) if i.name == "settings")
    exposure = next(i for i in settings.children if i.name == "exposure")  # a log slider
    imgui = FakeImgui()
    widget_value(exposure, imgui)
    assert imgui.calls[0][-1] == 32


def test_multiple_choice_check_boxes_add_and_remove_in_declared_order():
    info = next(i for i in describe(LineParams()) if i.name == "lines")
    changed, value = widget_value(info, FakeImgui({"ridges##": True}))
    assert changed and value == ("apparent-ridges", "silhouettes", "ridges")
    changed, value = widget_value(info, FakeImgui({"silhouettes##": False}))
    assert changed and value == ("apparent-ridges",)
    changed, value = widget_value(info, FakeImgui())
    assert not changed and value == info.value


def test_choice_combo_picks_a_declared_choice():
    info = next(i for i in describe(LineParams()) if i.name == "method")
    changed, value = widget_value(info, FakeImgui({"method": "object-space"}))
    assert changed and value == "object-space"


def test_fields_are_drawn_by_group_the_advanced_ones_under_a_closed_header():
    from illusio.dof.params import DofParams
    from illusio.viewer.panel import draw_fields

    imgui = FakeImgui()
    draw_fields(type("Viewer", (), {"set_param": lambda *a: None})(), describe(DofParams()), imgui)
    labels = [c[1].split("##")[-1] for c in imgui.calls if c[0] not in ("header", "item width")]
    longest = max(7.0 * len(info.title) for info in describe(DofParams()))
    assert imgui.calls[0] == ("item width", -(longest + 12.0)) and imgui.calls[-1] == ("item width", None)
    headers = [c[1:] for c in imgui.calls if c[0] == "header"]
    assert headers == [("output", 32), ("advanced", 0)]
    assert labels[0] == "method" and labels.index("method") < labels.index("aperture_mm") < labels.index("stereo")
    assert "seed" not in labels and "shadows" not in labels  # advanced: under the closed header


def test_every_character_of_the_labels_is_in_the_panels_font():
    """The panel's face (Roboto, as imgui_bundle ships it) and its loaded ranges hold every
    character of every Params' labels, help and choices, and of the modes' own lines (ImGui's own
    font showed "?" for ρ, τ and the dashes)."""
    from pathlib import Path

    from fontTools.ttLib import TTFont

    import illusio.viewer.modes as modes
    from illusio.core.technique import techniques
    from illusio.lines.style import LineStyle
    from illusio.sis.params import StereogramParams
    from illusio.viewer.panel import GLYPH_RANGES, panel_font_path

    path = panel_font_path()
    if path is None:
        pytest.skip("the viewer extra (imgui_bundle) is not installed")
    text = []

    def walk(infos):
        for info in infos:
            text.extend([info.title, info.help, *map(str, info.choices)])
            walk(info.children)

    for params in [t.params_class()() for t in techniques().values()] + [LineStyle(), StereogramParams()]:
        walk(describe(params))
    for source in Path(modes.__file__).parent.glob("*.py"):
        text.append(source.read_text(encoding="utf-8"))  # the strings its panel draws are in its source
    cmap = TTFont(path).getBestCmap()
    used = {c for t in text for c in t if ord(c) > 126}
    missing = sorted(c for c in used if ord(c) not in cmap)
    outside = sorted(c for c in used if not any(lo <= ord(c) <= hi for lo, hi in GLYPH_RANGES))
    assert not missing and not outside, (missing, outside)
