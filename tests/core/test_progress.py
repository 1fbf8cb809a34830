"""Progress (core.progress): long work says what it is doing — to a Python caller's callback, as bars
on a terminal, as a line per long phase in logs, and not at all with --quiet."""

from __future__ import annotations

import io

import pytest

from illusio.core.progress import Progress, phase, reporting
from tests.cli.test_cli import illusio


def test_a_caller_hears_radiosity_s_phases_nested_counted_and_finished():
    from illusio.radiosity import HierarchyParams, Radiosity, scene_polygons
    from illusio.scene import load_scene

    heard: list[Progress] = []
    with reporting(heard.append):
        Radiosity(scene_polygons(load_scene("cornell-box")), HierarchyParams(epsilon=1e-3)).build()
    # (named "radiosity (compiling …)" where numba's cache lacks the kernels: a cold cache, a new version)
    outer = [e for e in heard if e.depth == 0 and e.phase.split(" (compiling")[0] == "radiosity"]
    assert outer[0].depth == 0 and outer[0].total == 2 and outer[-1].finished and outer[-1].done == 2
    inner = {e.phase for e in heard if e.depth == 1}
    assert {"radiosity: refine, round 1 of 2", "radiosity: solve, round 1 of 2"} <= inner
    assert all(e.seconds >= 0 for e in heard)
    # nobody listening outside the block
    with phase("nothing heard") as advance:
        advance()
    assert not [e for e in heard if e.phase == "nothing heard"]


def test_a_path_traced_reference_is_a_phase_the_caller_hears():
    """Mitsuba's references (the gallery's, --reference, relighting's photograph) say what they
    render and how many paths a pixel."""
    pytest.importorskip("mitsuba")
    from illusio.radiosity import scene_polygons
    from illusio.radiosity.mitsuba import render_mitsuba
    from illusio.scene import load_scene

    scene = load_scene("cornell-box")
    heard = []
    with reporting(heard.append):
        image = render_mitsuba(scene_polygons(scene), scene.camera(), (8, 6), 2)
    assert image.shape == (6, 8, 3)
    ends = [e for e in heard if e.finished]
    assert [e.phase for e in ends] == ["path tracing 8×6 at 2 paths a pixel (Mitsuba)"]


def test_a_phase_that_raises_still_reports_its_end():
    heard = []
    with reporting(heard.append), pytest.raises(ValueError), phase("breaks", total=3) as advance:
        advance()
        raise ValueError
    assert heard[-1].finished and heard[-1].done == 1 and heard[-1].phase == "breaks"


def test_a_log_gets_one_line_per_phase_of_a_second_or_more():
    from illusio.cli.reporter import LineReporter

    out = io.StringIO()
    log = LineReporter(out)
    log(Progress("radiosity: refine, round 1 of 2", 0, None, 0.0, False, 1))
    log(Progress("radiosity: refine, round 1 of 2", 0, None, 2.34, True, 1))
    log(Progress("quick", 0, None, 0.2, True, 0))
    log(Progress("render: 30 frames", 30, 30, 4.0, True, 0))
    assert out.getvalue().splitlines() == [
        "illusio:   radiosity: refine, round 1 of 2: 2.3 s",
        "illusio: render: 30 frames (30 of 30): 4.0 s",
    ]


def test_the_command_line_reports_long_phases_and_is_silent_with_quiet(tmp_path):
    args = ["radiosity", "office", "--size", "64x48", "-o", tmp_path / "r.png", "--epsilon", "3e-5"]
    r = illusio(*args)
    assert r.returncode == 0, r.stderr
    assert "illusio: radiosity (2 of 2): " in r.stdout, r.stdout
    r = illusio("--quiet", *args)
    assert r.returncode == 0 and "illusio: radiosity" not in r.stdout, r.stdout
