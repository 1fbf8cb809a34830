import numpy as np
from scipy import ndimage

from illusio.core.renderer import Frame
from illusio.passes import SceneRenderer, reference
from illusio.scene import Camera, Material, Node, Pose, Scene, View
from illusio.scene.builtin import shapes
from illusio.scene.mesh import Mesh
from illusio.scene.transforms import compose, rotate_euler, translate
from tests.conftest import prepared, tolerance


def _scene(*nodes):
    s = Scene("test", nodes=list(nodes))
    s.cameras["main"] = View(Pose((0.0, 0.0, 4.0), (0.0, 0.0, 0.0)), Camera(40.0, 0.1, 20.0))
    return s


def test_depth_of_a_tilted_plane_matches_the_analytic_ray_plane_distance(ctx):
    tilt = compose(translate((0, 0, -1.0)), rotate_euler((60, 20, 0)))
    s = _scene(Node("plane", shapes.plane((20, 20)), tilt))
    view = s.camera()
    size = (96, 72)
    g = prepared(SceneRenderer(ctx), s).gbuffer(Frame(view, size))
    img = g.read()
    g.release()
    normal = tilt[:3, :3] @ np.array([0, 1, 0.0])
    point = tilt[:3, 3]
    eye = np.asarray(view.pose.position)
    dirs = view.ray_directions(size)
    t = ((point - eye) @ normal) / (dirs @ normal)
    expected = t * (dirs @ view.pose.axes()[2])
    hit = img.mask
    assert hit.mean() > 0.95
    np.testing.assert_allclose(img.depth[hit], expected[hit], rtol=2e-5)
    np.testing.assert_allclose(np.abs(img.normal[hit] @ normal), 1, atol=1e-3)


def test_depth_of_a_sphere_matches_the_analytic_value(ctx):
    radius = 1.0
    s = _scene(Node("ball", shapes.sphere(radius, 256, 128)))
    view = s.camera()
    size = (80, 80)
    g = prepared(SceneRenderer(ctx), s).gbuffer(Frame(view, size))
    img = g.read()
    g.release()
    eye = np.asarray(view.pose.position)
    d = view.ray_directions(size)
    b = d @ eye
    disc = b * b - (eye @ eye - radius**2)
    inside = disc > 0.25  # view angle under 60° from the normal: the chord error is not magnified
    t = -b - np.sqrt(np.maximum(disc, 0))
    expected = t * (d @ view.pose.axes()[2])
    assert img.mask[inside].all()
    # chord error of a 256×128 UV sphere ≈ r(1 - cos(π/128)) ≈ 3e-4 m, at most doubled at 60°
    np.testing.assert_allclose(img.depth[inside], expected[inside], atol=6e-4)


def test_gbuffer_matches_ray_cast_reference_on_random_triangles(ctx, rng):
    nodes = []
    for k in range(3):
        v = rng.uniform(-1, 1, (12, 3))
        f = rng.integers(0, 12, (10, 3))
        f = f[(f[:, 0] != f[:, 1]) & (f[:, 1] != f[:, 2]) & (f[:, 0] != f[:, 2])]
        # two faces on the same three vertices coincide: they z-fight, and with opposite windings
        # either facing is right (this was the "few % of normals of the wrong sign" of issue 18)
        _, first = np.unique(np.sort(f, axis=1), axis=0, return_index=True)
        f = f[np.sort(first)]
        mat = Material(tuple(rng.random(3)), specular=float(rng.random()), shininess=float(rng.uniform(1, 100)))
        # vertex normals within 60° of +z: their interpolation never comes near zero length
        normals = rng.normal(size=(12, 3)) * 0.5 + (0, 0, 1)
        normals /= np.linalg.norm(normals, axis=1, keepdims=True)
        nodes.append(Node(f"soup-{k}", Mesh(v, f, normals), translate(rng.uniform(-0.3, 0.3, 3)), mat))
    s = _scene(*nodes)
    size = (64, 48)
    g = prepared(SceneRenderer(ctx), s).gbuffer(Frame(s.camera(), size))
    gpu = g.read()
    g.release()
    ref = reference.gbuffer(s, s.camera(), size)
    agree = gpu.object_id == ref.object_id
    assert agree.mean() > 0.97  # pixels differ only where an edge passes near a pixel centre
    both = agree & ref.mask
    # Within one node, triangles of a random soup cross and overlap: where an edge or a crossing
    # passes next to a pixel centre, the rasteriser and the ray caster may pick different triangles
    # of the same node. Those pixels are rare; count them, then compare the rest strictly.
    same_surface = both & np.isclose(gpu.depth, ref.depth, **tolerance("float32"))
    assert same_surface.sum() >= 0.99 * both.sum()
    both = same_surface
    np.testing.assert_allclose(gpu.position[both], ref.position[both], **tolerance("position"))
    np.testing.assert_allclose(gpu.colour[both], ref.colour[both], **tolerance("float16"))  # half-float target
    np.testing.assert_allclose(gpu.specular[both], ref.specular[both], **tolerance("float16"))
    # normals: interpolated in both, flipped towards the viewer on back faces in both (signed)
    alignment = (gpu.normal[both] * ref.normal[both]).sum(axis=1)
    assert (alignment > 1 - 5e-3).mean() > 0.99
    # A sign error on one triangle flips a patch of it (blocks of 3×3 pixels). Pixels of opposite sign
    # in thin lines are where two crossing triangles of one node meet at nearly one depth: up to 4 seen
    # in CI, at most 2 and never a 2×2 block over 600 seeds here.
    flipped = np.zeros(gpu.depth.shape, bool)
    flipped[both] = alignment <= 0
    assert not ndimage.binary_erosion(flipped, np.ones((3, 3))).any(), np.argwhere(flipped)
    assert flipped.sum() <= 0.005 * both.sum(), flipped.sum()
