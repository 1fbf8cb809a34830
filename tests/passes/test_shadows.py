import numpy as np

from illusio.core.renderer import Frame
from illusio.passes import RenderSettings, SceneRenderer
from illusio.scene import Camera, Material, Node, PointLight, Pose, Scene, View
from illusio.scene.builtin import shapes
from illusio.scene.transforms import translate
from tests.conftest import prepared, tolerance


def test_shadow_of_a_sphere_on_a_plane_matches_the_analytic_shadow(ctx):
    light = np.array([0.4, 4.0, 0.2])
    centre, radius = np.array([0.0, 1.0, 0.0]), 0.6
    s = Scene(
        "shadow",
        ambient=(0.05, 0.05, 0.05),
        nodes=[
            Node("floor", shapes.plane((30, 30)), material=Material((0.8, 0.8, 0.8))),
            Node("ball", shapes.sphere(radius, 128, 64), translate(centre), Material((0.8, 0.2, 0.2))),
        ],
        lights=[PointLight(tuple(light), intensity=12.0)],
    )
    view = View(Pose((0, 9, 0.01), (0, 0, 0)), Camera(40.0, 0.1, 50.0))
    size = (128, 128)
    r = prepared(SceneRenderer(ctx), s)
    g = r.gbuffer(Frame(view, size))
    gb = g.read()
    g.release()
    lit = r.render(Frame(view, size), RenderSettings(shadows=True))[..., 1]
    floor = gb.object_id == 1
    # analytic: does the segment floor point -> light hit the sphere?
    p = gb.position[floor].astype(np.float64)
    d = light - p
    length = np.linalg.norm(d, axis=1)
    d /= length[:, None]
    oc = p - centre
    b = (oc * d).sum(1)
    disc = b * b - ((oc * oc).sum(1) - radius**2)
    t = -b - np.sqrt(np.maximum(disc, 0))
    shadowed = (disc > 0) & (t > 0) & (t < length)
    assert shadowed.sum() > 200  # the test sees a real shadow
    ambient_only = 0.05 * 0.8
    dark = lit[floor] < ambient_only + 0.01
    mismatch = (dark != shadowed).mean()
    assert mismatch < 0.01, f"{mismatch:.3%} of floor pixels disagree with the analytic shadow"


def test_shadow_maps_are_kept_until_the_scene_or_their_size_changes(ctx, monkeypatch):
    """The atlas depends on the scene and the tile size only: a new view reuses it (the same image
    as a renderer that draws it afresh), a moved light (prepared again) or another tile size makes
    it again."""
    from illusio.passes import shadows as shadows_module

    calls = []
    real = shadows_module.ShadowPass.__call__
    monkeypatch.setattr(
        shadows_module.ShadowPass, "__call__", lambda self, *a, **k: calls.append(1) or real(self, *a, **k)
    )
    s = Scene(
        "kept",
        ambient=(0.05, 0.05, 0.05),
        nodes=[
            Node("floor", shapes.plane((10, 10)), material=Material((0.8, 0.8, 0.8))),
            Node("ball", shapes.sphere(0.5, 32, 16), translate((0, 1, 0)), Material((0.8, 0.2, 0.2))),
        ],
        lights=[PointLight((0.5, 3.0, 0.2), intensity=8.0)],
    )
    views = [View(Pose((x, 5, 4), (0, 0, 0)), Camera(45.0, 0.1, 50.0)) for x in (0.0, 1.0)]
    size, settings = (64, 48), RenderSettings(shadows=True)
    r = prepared(SceneRenderer(ctx), s)
    first = r.render(Frame(views[0], size), settings)
    second = r.render(Frame(views[1], size), settings)
    assert len(calls) == 1
    np.testing.assert_allclose(
        second, prepared(SceneRenderer(ctx), s).render(Frame(views[1], size), settings), **tolerance("same arithmetic")
    )
    calls.clear()
    s.lights[0] = PointLight((-1.5, 3.0, 0.2), intensity=8.0)
    r.prepare(s)
    moved = r.render(Frame(views[0], size), settings)
    assert len(calls) == 1 and np.abs(moved - first).max() > 0.05
    r.render(Frame(views[0], size), RenderSettings(shadows=True, shadow_tile_size=256))
    assert len(calls) == 2
