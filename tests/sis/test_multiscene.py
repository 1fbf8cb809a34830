"""The multi-scene pipeline: the TV of the living room shows a stereogram of the hidden shape."""

import numpy as np
import pytest

from illusio.scene import load_scene
from illusio.scene.builtin import shape
from illusio.scene.camera import Camera, Pose, View
from illusio.scene.scene import Node, Scene
from illusio.sis.decode import check
from illusio.sis.multiscene import MultiSceneParams, MultiSceneRenderer
from illusio.sis.reference import separation


def hidden_scene():
    return Scene(name="hidden", nodes=[Node("subject", shape("torus-knot"))],
                 cameras={"main": View(Pose((0, 0, 4.5), (0, 0, 0)), Camera(35, 0.1, 20))})


@pytest.mark.parametrize("host, camera, emission", [("tv-screen", "tv", 0.9), ("back-wall", "main", 0.0)])
def test_host_shows_a_stereogram_of_the_hidden_scene(ctx, host, camera, emission):
    scene = load_scene("living-room")
    keep = {}
    size = (960, 540)
    params = MultiSceneParams(host=host, emission=emission)
    image = MultiSceneRenderer(ctx).render(scene, hidden_scene(), scene.camera(camera), size, params, frame=3, keep=keep)
    depth = keep["depth"]
    host_mask = depth >= 0
    visible = keep["visible"]
    # the host covers a good part of that view, and the hidden knot covers part of the host
    assert 0.1 < host_mask.mean() < 0.7
    assert (depth[host_mask] < 0.9).mean() > 0.02
    assert not (visible & ~host_mask).any()
    if host == "back-wall":  # the TV and its stand hide part of the wall, but do not cut its rows
        assert visible.sum() < 0.97 * host_mask.sum()
    # over the whole host, seen or hidden, the stereogram encodes the screen-space depth
    sis = params.scaled_stereogram(size[0])
    sep = separation(np.where(host_mask, depth, 1.0), sis.strip_width, sis.depth_factor)
    rows = np.where(host_mask.any(axis=1), host_mask.argmax(axis=1), size[0]).astype(np.int32)
    first = int(sis.far_separation + 0.5)
    report = check(np.where(host_mask[..., None], keep["stereogram"], 0), sep, first, "left", row_start=rows)
    assert report.matched >= 0.97, str(report)
    # where the host is seen, it shows the stereogram (snow or texture): its pixels vary
    assert image[visible].std() > 0.05


def test_still_camera_frames_change_only_on_the_host_and_match_whole_renders(ctx):
    scene = load_scene("living-room")
    view, size = scene.camera("tv"), (320, 180)
    multi = MultiSceneRenderer(ctx)
    keep = {}
    multi.render(scene, hidden_scene(), view, size, MultiSceneParams(), frame=1, keep=keep)
    host = keep["depth"] >= 0
    a = multi.render(scene, hidden_scene(), view, size, MultiSceneParams(), frame=4)
    b = multi.render(scene, hidden_scene(), view, size, MultiSceneParams(), frame=5)  # the kept layer
    whole = multi.render(scene, hidden_scene(), view, size, MultiSceneParams(reuse_static=False), frame=5)
    changed = np.abs(a - b).max(axis=-1) > 1e-6
    assert changed.any() and not (changed & ~host).any()  # the snow moves, nothing else
    assert (np.abs(b - whole) <= 1e-6).mean() > 0.999
    multi.release()  # frees the kept layer and the scenes' GPU copies; still usable
    np.testing.assert_allclose(multi.render(scene, hidden_scene(), view, size, MultiSceneParams(), frame=5), whole, atol=1e-6)


def test_texture_stereogram_covers_the_whole_host_with_its_texture(ctx, rng, tmp_path):
    """Figure 24's wall with a texture that is never black: every host pixel of the stereogram shows
    the texture projected on the host, never the black off it (rows of the wall that start less
    than a strip from the image's right edge once wrapped their first strip around the row)."""
    from illusio.core.images import write_image
    from illusio.sis.params import StereogramParams

    texture = tmp_path / "texture.png"
    write_image(texture, 0.3 + 0.6 * rng.random((64, 64, 3)))
    scene = load_scene("living-room")
    params = MultiSceneParams(host="back-wall", emission=0.0, stereogram=StereogramParams(pattern=str(texture)))
    keep = {}
    MultiSceneRenderer(ctx).render(scene, hidden_scene(), scene.camera("main"), (480, 300), params, frame=1, keep=keep)
    host = keep["depth"] >= 0
    last = np.where(host.any(axis=1), host.shape[1] - 1 - np.argmax(host[:, ::-1], axis=1), -1)
    assert (last == host.shape[1] - 1).any()  # the wall reaches the right edge in some rows
    assert (keep["stereogram"][host].max(axis=-1) > 0).all()
