"""The demo's path-traced renders are made once a run: equal arguments by value (not by identity)
give the one render, another seed or size a new one; radiosity's office reference and relighting's
photograph are such equal arguments, so the demo renders the office once for both."""

import numpy as np
import pytest

pytest.importorskip("mitsuba", reason="the photo extra (pip install 'illusio[photo]')")


def test_equal_arguments_share_one_render_and_others_do_not():
    from illusio.gallery import traced
    from illusio.radiosity.polygons import scene_polygons
    from illusio.scene.builtin import builtin_scene

    traced.clear()
    scene = builtin_scene("cornell-box")
    view = scene.camera("main")
    made = traced.renders_made()
    first = traced.path_traced(scene_polygons(scene), view, (16, 12), samples=2)
    again = traced.path_traced(scene_polygons(builtin_scene("cornell-box")), view, (16, 12), samples=2)
    assert again is first and traced.renders_made() == made + 1
    assert not first.flags.writeable  # a section cannot spoil what another reads
    other = traced.path_traced(scene_polygons(scene), view, (16, 12), samples=2, seed=1)
    assert traced.renders_made() == made + 2 and other.shape == (12, 16, 3)
    assert not np.array_equal(other, first)
    traced.clear()
    traced.path_traced(scene_polygons(scene), view, (16, 12), samples=2)
    assert traced.renders_made() == made + 3  # cleared: made again


def test_radiosity_office_reference_is_the_relight_photograph(ctx):
    """What lets the two sections share: the renderer's polygons equal the relight model's."""
    from illusio.core.renderer import fingerprint
    from illusio.radiosity import RadiosityRenderer
    from illusio.radiosity.polygons import scene_polygons
    from illusio.scene.builtin import builtin_scene

    office = builtin_scene("office")
    renderer = RadiosityRenderer(ctx)
    renderer.prepare(office)
    try:
        assert fingerprint(renderer.polygons) == fingerprint(scene_polygons(office))
    finally:
        renderer.release()
