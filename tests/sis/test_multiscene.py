"""The multi-scene pipeline: the TV of the living room shows a stereogram of the hidden shape."""

import numpy as np

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


def test_tv_shows_a_stereogram_of_the_hidden_scene():
    # its own context: after some other tests on the shared one the host mask comes out empty (a GL
    # state leak not yet found; see the note on issue 3)
    from illusio.core import Context

    ctx = Context()
    scene = load_scene("living-room")
    keep = {}
    size = (960, 540)
    params = MultiSceneParams()
    image = MultiSceneRenderer(ctx).render(scene, hidden_scene(), scene.camera("tv"), size, params, frame=3, keep=keep)
    depth = keep["depth"]
    host = depth >= 0
    # the TV screen covers a good part of that view, and the hidden knot covers part of the screen
    assert 0.1 < host.mean() < 0.6
    assert (depth[host] < 0.9).mean() > 0.1
    # inside the host, the stereogram encodes the screen-space depth
    sis = params.scaled_stereogram(size[0])
    sep = separation(np.where(host, depth, 1.0), sis.strip_width, sis.depth_factor)
    rows = np.where(host.any(axis=1), host.argmax(axis=1), size[0]).astype(np.int32)
    first = int(sis.far_separation + 0.5)
    report = check(np.where(host[..., None], keep["stereogram"], 0), sep, first, "left", row_start=rows)
    assert report.matched >= 0.97, str(report)
    # the TV glows with it: its pixels vary (snow) where the screen is seen
    assert image[host].std() > 0.1
    ctx.release_all()
