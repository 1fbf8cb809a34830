import warnings

import numpy as np
import pytest
import trimesh

from illusio.core import InputError
from illusio.scene import MeshWarning, load_mesh
from illusio.scene.mesh import crease_split

TETRA_V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
TETRA_F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])


@pytest.mark.parametrize("ext", [".obj", ".ply", ".off", ".stl", ".glb"])
def test_every_format_loads_through_trimesh(tmp_path, ext):
    path = tmp_path / f"tetra{ext}"
    trimesh.Trimesh(TETRA_V, TETRA_F, process=False).export(path)
    m = load_mesh(path)
    assert len(m.faces) == 4
    np.testing.assert_allclose(np.sort(m.vertices, axis=0), np.sort(np.unique(TETRA_V, axis=0), axis=0), atol=1e-6)
    assert np.isfinite(m.normals).all()


def _obj(tmp_path, text, name="m.obj"):
    p = tmp_path / name
    p.write_text(text)
    return p


def test_nan_vertices_are_refused_with_the_file_named(tmp_path):
    p = _obj(tmp_path, "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n")
    with pytest.raises(InputError, match=r"m\.obj.*not finite"):
        load_mesh(p)


def test_out_of_range_indices_missing_empty_and_corrupt_files(tmp_path):
    off = tmp_path / "bad.off"
    off.write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n")
    with pytest.raises(InputError, match="bad.off"):
        load_mesh(off)
    with pytest.raises(InputError, match="no such file"):
        load_mesh(tmp_path / "missing.obj")
    (tmp_path / "empty.stl").write_bytes(b"")
    with pytest.raises(InputError, match="empty"):
        load_mesh(tmp_path / "empty.stl")
    (tmp_path / "junk.ply").write_bytes(b"\x00\x01garbage")
    with pytest.raises(InputError, match="junk.ply"):
        load_mesh(tmp_path / "junk.ply")
    with pytest.raises(InputError, match="empty"):
        load_mesh(_obj(tmp_path, "# nothing here\n", "none.obj"))
    with pytest.raises(InputError, match="unsupported"):
        load_mesh(_obj(tmp_path, "x", "m.xyz"))


def test_unreferenced_vertices_and_duplicate_faces_dropped_with_warning(tmp_path):
    p = _obj(tmp_path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 9 9 9\nf 1 2 3\nf 2 3 1\nf 1 1 2\n")
    with pytest.warns(MeshWarning) as record:
        m = load_mesh(p)
    messages = " ".join(str(r.message) for r in record)
    assert "1 duplicate faces" in messages and "1 unreferenced vertices" in messages
    assert len(m.vertices) == 3 and len(m.faces) == 1
    assert any("degenerate" in n for n in m.notes)


def test_triangle_strip_ply(tmp_path):
    """PLY files with an ``element tristrips`` (the Igea scan) become triangles."""
    p = tmp_path / "strip.ply"
    p.write_text(
        "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
        "element tristrips 1\nproperty list int int vertex_indices\nend_header\n"
        "0 0 0\n1 0 0\n0 1 0\n1 1 0\n1.5 2 0\n5 0 1 2 3 4\n"
    )
    m = load_mesh(p)
    assert len(m.faces) == 3
    n = np.cross(*(m.vertices[m.faces[:, k]] - m.vertices[m.faces[:, 0]] for k in (1, 2)))
    assert (np.sign(n[:, 2]) == np.sign(n[0, 2])).all()  # strip winding alternation undone


def test_crease_split_keeps_flat_faces_flat():
    v, f = TETRA_V, TETRA_F
    nv, nf, nn, _ = crease_split(v, f, 30.0)
    assert len(nv) == 12  # every corner of a tetrahedron is a crease
    fn = np.cross(nv[nf[:, 1]] - nv[nf[:, 0]], nv[nf[:, 2]] - nv[nf[:, 0]])
    fn /= np.linalg.norm(fn, axis=1, keepdims=True)
    np.testing.assert_allclose(nn[nf[:, 0]], fn, atol=1e-6)


def test_shared_dirty_meshes_load_finite(models):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MeshWarning)
        for name in ("stanford-bunny.obj", "dragon_vrip_res3.ply", "igea.ply", "fandisk.off"):
            m = load_mesh(models / name)
            assert np.isfinite(m.vertices).all() and np.isfinite(m.normals).all()
            assert m.faces.max() < len(m.vertices)
    assert len(load_mesh(models / "igea.ply").faces) == 268_686  # SOURCES.md's count


def test_obj_negative_indices_and_off_counts_on_the_keyword_line_load(tmp_path):
    """Both are in their formats: an OBJ face may count back from the last vertex (-1 is the latest),
    and an OFF file may give its counts on the line of the keyword."""
    obj = tmp_path / "relative.obj"
    obj.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf -4 -3 -2\nf -3 -1 -2\n")
    m = load_mesh(obj)
    assert len(m.faces) == 2 and np.allclose(np.ptp(m.vertices, axis=0), (1, 1, 0))
    off = tmp_path / "inline.off"
    off.write_text("OFF 4 2 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2\n3 1 3 2\n")
    m = load_mesh(off)
    assert len(m.faces) == 2 and np.allclose(np.ptp(m.vertices, axis=0), (1, 1, 0))


def _cube_obj(relative: bool) -> str:
    """A cube whose faces follow their own v/vt/vn lines, indexed relatively (``f -4/-4/-1 ...``,
    the construct of the peer's file, with more uvs and normals than positions) or absolutely."""
    corners = [(x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1)]
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    lines = ["# relative indices, interleaved"]
    for k, quad in enumerate(quads):
        lines += [f"v {x} {y} {z}" for x, y, z in (corners[v] for v in quad)]
        lines += ["vt 0 0", "vt 1 0", "vt 1 1", "vt 0 1", "vt 0.5 0.5", "vt 0.25 0.25", "vn 0 0 1", "vn 0 1 0"]
        if relative:
            lines.append("f " + " ".join(f"{c - 4}/{c - 6}/-2" for c in range(4)))
        else:
            lines.append("f " + " ".join(f"{4 * k + c + 1}/{6 * k + c + 1}/{2 * k + 1}" for c in range(4)))
    return "\n".join(lines) + "\n"


def test_an_obj_with_relative_indices_and_uvs_normals_reads_as_its_absolute_twin(tmp_path):
    (tmp_path / "relative.obj").write_text(_cube_obj(True))
    (tmp_path / "absolute.obj").write_text(_cube_obj(False))
    a, b = load_mesh(tmp_path / "relative.obj"), load_mesh(tmp_path / "absolute.obj")
    assert len(a.faces) == 12 and np.array_equal(a.vertices, b.vertices) and np.array_equal(a.faces, b.faces)
    assert np.allclose(a.bounds[0], 0) and np.allclose(a.bounds[1], 1)


def test_an_off_whose_header_is_indented_glued_and_commented_reads(tmp_path):
    """``\\t   OFF8 6 12 # ...``: whitespace first, the vertex count glued to the keyword, a comment."""
    corners = [(x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1)]
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    text = "\t   OFF8 6 12 # a cube, as a peer's test set writes it\n"
    text += (
        "\n".join(f"{x} {y} {z}" for x, y, z in corners)
        + "\n"
        + "\n".join(f"4 {a} {b} {c} {d}" for a, b, c, d in quads)
    )
    (tmp_path / "cube.off").write_text(text + "\n")
    mesh = load_mesh(tmp_path / "cube.off")
    assert len(mesh.vertices) == 8 and len(mesh.faces) == 12
    (tmp_path / "cut.off").write_text(text.rsplit("\n", 2)[0] + "\n")  # the last face cut off
    with pytest.raises(InputError, match="cut short"):
        load_mesh(tmp_path / "cut.off")
