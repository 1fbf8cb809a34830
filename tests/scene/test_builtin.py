import numpy as np
import pytest

from illusio.core.renderer import Frame
from illusio.passes import SceneRenderer
from illusio.scene import SHAPES, builtin_scene, shape
from illusio.scene.mesh import face_normals
from tests.conftest import prepared


@pytest.mark.parametrize("name", list(SHAPES))
def test_shapes_are_finite_with_consistent_outward_winding(name):
    m = shape(name)
    assert np.isfinite(m.vertices).all() and np.isfinite(m.normals).all()
    fn = face_normals(m.vertices, m.faces)
    agree = (fn * m.normals[m.faces].mean(axis=1)).sum(axis=1) > 0
    assert agree.mean() > 0.999
    # outward: the signed volume of a closed, outward-wound surface is positive
    v = m.vertices.astype(np.float64)[m.faces]
    volume = np.einsum("ij,ij->i", v[:, 0], np.cross(v[:, 1], v[:, 2])).sum() / 6
    assert volume > 0


def test_gear_has_sharp_creases():
    """Creased: at many positions the vertices meeting there carry normals more than 60° apart (a
    smooth-shaded gear, one normal per position, has none)."""
    m = shape("gear")
    normals = np.asarray(m.normals, np.float64)
    _, position = np.unique(np.round(m.vertices, 6), axis=0, return_inverse=True)
    position = position.ravel()
    first = np.zeros((position.max() + 1, 3))
    first[position] = normals  # one of the normals at each position (the last written)
    creased = np.unique(position[(normals * first[position]).sum(axis=1) < np.cos(np.radians(60))])
    assert len(creased) > 100


# Parts that make each scene what it is named, and the share of the main view they must cover.
RECOGNISABLE = {
    "living-room": {"tv-screen": 0.01, "sofa-back": 0.02, "lamp-shade": 0.001, "cabinet": 0.005},
    "office": {
        "table-0-top": 0.002,
        "table-1-top": 0.005,
        "chair-seat": 0.0008,
        "lamp-0": 0.001,
        "lamp-1": 0.001,
        "lamp-2": 0.001,
        "lamp-3": 0.001,
    },
    "museum": {"exhibit-torus-knot": 0.001, "exhibit-blob": 0.001, "exhibit-gear": 0.001, "plinth-blob": 0.003},
    "turntable": {"subject": 0.05, "floor": 0.2},
}


@pytest.mark.parametrize("name", list(RECOGNISABLE))
def test_builtin_scene_main_view_shows_its_defining_parts(ctx, name):
    scene = builtin_scene(name)
    g = prepared(SceneRenderer(ctx), scene).gbuffer(Frame(scene.camera(), (320, 200)))
    ids = g.read().object_id
    g.release()
    total = ids.size
    for node, share in RECOGNISABLE[name].items():
        index = [n.name for n in scene.nodes].index(node) + 1
        assert (ids == index).sum() / total >= share, f"{node} covers too little of the {name} view"
