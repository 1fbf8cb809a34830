"""Real captures in the formats people have (ibr.captures): each test writes a capture of the office
in that format — colour, 16-bit or float depth with sensor-like noise and holes, intrinsics with the
principal point off centre and f_x ≠ f_y, poses in the format's own convention (quaternions by
scipy, an independent statement of the rotation) — imports it with the CLI, renders a held-out
frame and scores it against that frame's photo."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from illusio.core.errors import InputError
from illusio.core.images import write_image
from illusio.ibr import captures
from illusio.ibr.reference_views import capture, load_references
from illusio.scene import load_scene
from illusio.scene.camera import Camera, Pose, View
from tests.conftest import call_cli

W, H = 96, 72
INTRINSICS = captures.Intrinsics(W, H, 70.0, 78.0, 50.3, 33.1)  # off centre, f_x ≠ f_y
FLIP = np.diag([1.0, -1.0, -1.0, 1.0])  # GL camera axes ↔ OpenCV's


def _views(count: int = 5):
    """Cameras along a short path inside the office, with the test's intrinsics."""
    scene = load_scene("office")
    base = scene.camera()
    eye, target = np.array(base.pose.position), np.array(base.pose.target)
    ahead = target - eye
    right = np.cross(ahead / np.linalg.norm(ahead), (0, 1, 0))
    lens = INTRINSICS.camera(0.05, 30.0)
    return scene, [
        View(Pose(tuple(eye + 0.25 * ahead + (k - count // 2) * 0.12 * right), tuple(target)), lens)
        for k in range(count)
    ]


def _camera_to_world(view: View) -> np.ndarray:
    return np.linalg.inv(view.view_matrix().astype(np.float64)) @ FLIP


@pytest.fixture(scope="module")
def office_capture(ctx):
    """(views, photos, depths with noise and holes): what a depth camera walking the office records."""
    scene, views = _views()
    refs = capture(scene, views, (W, H), ctx)
    rng = np.random.default_rng(3)
    depths = []
    for v in refs.views:
        d = v.depth * (1 + rng.normal(0, 0.004, v.depth.shape))  # ~0.4 % noise, as a structured-light sensor
        d[rng.random(d.shape) < 0.03] = 0.0  # dropped pixels
        depths.append(np.where(v.depth > 0, d, 0.0))
    return views, [np.clip(v.colour, 0, 1) for v in refs.views], depths


def _write_rgbd(folder, office_capture, open3d_matrix=False):
    views, photos, depths = office_capture
    (folder / "color").mkdir(parents=True)
    (folder / "depth").mkdir()
    log = []
    for k, (view, photo, depth) in enumerate(zip(views, photos, depths)):
        write_image(folder / "color" / f"{k:05d}.png", photo)
        write_image(folder / "depth" / f"{k:05d}.png", np.round(depth * 1000) / 65535.0, bit_depth=16, srgb=False)
        m = _camera_to_world(view)
        log += [f"{k} {k} {len(views)}"] + [" ".join(f"{x:.9f}" for x in row) for row in m]
    (folder / "trajectory.log").write_text("\n".join(log) + "\n")
    i = INTRINSICS
    if open3d_matrix:  # Open3D's PinholeCameraIntrinsic JSON: the matrix column-major
        doc = {"width": W, "height": H, "intrinsic_matrix": [i.fx, 0, 0, 0, i.fy, 0, i.cx, i.cy, 1]}
    else:
        doc = {"width": W, "height": H, "fx": i.fx, "fy": i.fy, "cx": i.cx, "cy": i.cy}
    (folder / "intrinsic.json").write_text(json.dumps(doc))


def _score(tmp_path, capsys, refs, frame, extra=()):
    code, cap = call_cli(
        ["ibr", "render", str(refs), "-o", str(tmp_path / f"frame-{frame}.png"), "--compare-photo", str(frame), *extra],
        capsys,
    )
    assert code == 0, cap.err
    assert "(sRGB, the displayed image)" in cap.out  # the convention papers score in
    psnr = float(re.search(r"PSNR ([\d.]+) dB", cap.out).group(1))
    ssim = float(re.search(r"SSIM ([\d.]+)", cap.out).group(1))
    return psnr, ssim


def test_an_rgbd_folder_imports_and_renders_its_held_out_frames(tmp_path, capsys, office_capture):
    src = tmp_path / "capture"
    _write_rgbd(src, office_capture, open3d_matrix=True)
    code, cap = call_cli(["ibr", "import", "rgbd", str(src), "-o", str(tmp_path / "refs"), "--frames", "0,2,4"], capsys)
    assert code == 0 and "3 references of 5 frames" in cap.out, cap.err
    refs = load_references(tmp_path / "refs")
    assert refs.albedo_from_photo and len(refs.frames) == 5
    lens = refs.views[0].view.camera
    assert lens.pixel_aspect == pytest.approx(78.0 / 70.0) and lens.shift != (0.0, 0.0)
    psnr, ssim = _score(tmp_path, capsys, tmp_path / "refs", 1)  # frame 1 is not a reference
    assert psnr > 24 and ssim > 0.75, (psnr, ssim)
    # the pose of a reference frame gives back its photo closely
    psnr_ref, _ = _score(tmp_path, capsys, tmp_path / "refs", 2)
    assert psnr_ref > psnr


def test_the_intrinsics_put_points_where_the_photo_has_them(office_capture):
    """Camera.from_intrinsics projects a point of the camera's frame to (f_x x/z + c_x, f_y y/z + c_y)
    (+½: illusio counts pixel edges, OpenCV pixel centres)."""
    rng = np.random.default_rng(5)
    points = np.c_[rng.uniform(-0.5, 0.5, (20, 2)), rng.uniform(1, 4, 20)]
    view = View(Pose((0, 0, 0), (0, 0, -1)), INTRINSICS.camera())
    pixels, _ = view.project(points * [1, -1, -1], (W, H))
    i = INTRINSICS
    want = np.c_[i.fx * points[:, 0] / points[:, 2] + i.cx, i.fy * points[:, 1] / points[:, 2] + i.cy] + 0.5
    assert np.allclose(pixels, want, atol=1e-4)


def test_a_tum_sequence_associates_by_time_and_reads_quaternions(tmp_path, capsys, office_capture):
    views, photos, depths = office_capture
    src = tmp_path / "tum"
    (src / "rgb").mkdir(parents=True)
    (src / "depth").mkdir()
    rgb, depth, truth = ["# color images"], ["# depth maps"], ["# timestamp tx ty tz qx qy qz qw"]
    for k, (view, photo, d) in enumerate(zip(views, photos, depths)):
        t = 1305031102.0 + 0.5 * k
        write_image(src / "rgb" / f"{t:.6f}.png", photo)
        write_image(src / "depth" / f"{t + 0.004:.6f}.png", np.round(d * 5000) / 65535.0, bit_depth=16, srgb=False)
        rgb.append(f"{t:.6f} rgb/{t:.6f}.png")
        depth.append(f"{t + 0.004:.6f} depth/{t + 0.004:.6f}.png")
        m = _camera_to_world(view)
        qx, qy, qz, qw = Rotation.from_matrix(m[:3, :3]).as_quat()
        truth.append(f"{t - 0.003:.4f} {m[0, 3]:.6f} {m[1, 3]:.6f} {m[2, 3]:.6f} {qx:.8f} {qy:.8f} {qz:.8f} {qw:.8f}")
    rgb.append("1305031199.000000 rgb/extra.png")  # no depth near it: dropped
    for name, lines in (("rgb.txt", rgb), ("depth.txt", depth), ("groundtruth.txt", truth)):
        (src / name).write_text("\n".join(lines) + "\n")
    i = INTRINSICS
    (src / "intrinsic.json").write_text(
        json.dumps({"width": W, "height": H, "fx": i.fx, "fy": i.fy, "cx": i.cx, "cy": i.cy})
    )
    frames = captures.read_tum(src)
    assert len(frames) == 5
    assert np.allclose(frames[3].pose, _camera_to_world(views[3]), atol=1e-5)
    code, cap = call_cli(["ibr", "import", "tum", str(src), "-o", str(tmp_path / "refs"), "--every", "2"], capsys)
    assert code == 0, cap.err
    psnr, _ = _score(tmp_path, capsys, tmp_path / "refs", 1)
    assert psnr > 24, psnr


def _colmap_array(path, a):
    h, w = a.shape
    # as COLMAP's own write_array: the (W, H) transpose, flattened in Fortran order
    path.write_bytes(f"{w}&{h}&1&".encode() + np.asarray(a, "<f4").T.reshape(-1, order="F").tobytes())


def test_a_colmap_workspace_imports(tmp_path, capsys, office_capture):
    views, photos, depths = office_capture
    src = tmp_path / "colmap"
    for d in ("sparse", "images", "stereo/depth_maps"):
        (src / d).mkdir(parents=True)
    i = INTRINSICS
    (src / "sparse" / "cameras.txt").write_text(
        f"# CAMERA_ID MODEL WIDTH HEIGHT PARAMS[]\n1 PINHOLE {W} {H} {i.fx} {i.fy} {i.cx + 0.5} {i.cy + 0.5}\n"
    )
    lines = ["# IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME"]
    for k, (view, photo, d) in enumerate(zip(views, photos, depths)):
        name = f"img{k}.png"
        write_image(src / "images" / name, photo)
        _colmap_array(src / "stereo" / "depth_maps" / f"{name}.geometric.bin", d)
        world_to_camera = np.linalg.inv(_camera_to_world(view))
        qx, qy, qz, qw = Rotation.from_matrix(world_to_camera[:3, :3]).as_quat()
        t = world_to_camera[:3, 3]
        lines += [f"{k + 1} {qw} {qx} {qy} {qz} {t[0]} {t[1]} {t[2]} 1 {name}", "1.0 2.0 -1"]
    (src / "sparse" / "images.txt").write_text("\n".join(lines) + "\n")
    frames = captures.read_colmap(src)
    assert np.allclose(frames[2].pose, _camera_to_world(views[2]), atol=1e-6)
    assert np.allclose(frames[2].depth, depths[2].astype(np.float32))
    code, cap = call_cli(
        ["ibr", "import", "colmap", str(src), "-o", str(tmp_path / "refs"), "--frames", "0,2,4", "--max-depth", "20"],
        capsys,
    )
    assert code == 0, cap.err
    psnr, _ = _score(tmp_path, capsys, tmp_path / "refs", 3)
    assert psnr > 24, psnr
    # a depth map cut short mid-value (a copy interrupted): one line naming it, exit 2, nothing written
    from tests.cli.test_cli import assert_one_line_error, illusio

    cut = src / "stereo" / "depth_maps" / "img2.png.geometric.bin"
    cut.write_bytes(cut.read_bytes()[:-1001])
    assert_one_line_error(
        illusio("ibr", "import", "colmap", src, "-o", tmp_path / "refs-2", "--frames", "0,2,4"),
        "img2.png.geometric.bin",
        "cut short",
    )
    assert not (tmp_path / "refs-2").exists()


def _distort(image, intr, k1, k2, p1, p2, order):
    """What a lens with OPENCV distortion records of ``image`` (a pinhole's view): each recorded
    pixel's ray undistorted by fixed-point iteration (as OpenCV's undistortPoints), then sampled."""
    from scipy import ndimage

    v, u = np.mgrid[0 : intr.height, 0 : intr.width].astype(np.float64)
    xd, yd = (u - intr.cx) / intr.fx, (v - intr.cy) / intr.fy
    x, y = xd.copy(), yd.copy()
    for _ in range(20):
        r2 = x * x + y * y
        radial = 1 + k1 * r2 + k2 * r2 * r2
        x = (xd - (2 * p1 * x * y + p2 * (r2 + 2 * x * x))) / radial
        y = (yd - (p1 * (r2 + 2 * y * y) + 2 * p2 * x * y)) / radial
    coords = np.stack([y * intr.fy + intr.cy, x * intr.fx + intr.cx])
    if image.ndim == 2:
        return ndimage.map_coordinates(image, coords, order=order, mode="nearest")
    return np.stack([ndimage.map_coordinates(image[..., c], coords, order=order, mode="nearest") for c in range(3)], -1)


def test_opencv_distortion_is_undone(office_capture):
    _, photos, depths = office_capture
    k = (-0.35, 0.1, 0.004, -0.003)  # a strong barrel: corners move by pixels
    lens = captures.Intrinsics(W, H, INTRINSICS.fx, INTRINSICS.fy, INTRINSICS.cx, INTRINSICS.cy, "OPENCV", k)
    recorded = captures.CaptureFrame(
        "d",
        _distort(photos[0], lens, *k, order=1).astype(np.float32),
        _distort(depths[0], lens, *k, order=0).astype(np.float32),
        lens,
        np.eye(4),
    )
    fixed = captures.undistort(recorded)
    inner = (slice(8, H - 8), slice(8, W - 8))
    before = np.abs(recorded.colour - photos[0])[inner].mean()
    after = np.abs(fixed.colour - photos[0])[inner].mean()
    assert fixed.intrinsics.model == "PINHOLE" and after < 0.5 * before, (before, after)


def test_normals_from_depth_of_a_tilted_plane():
    """A plane z = 2 + 0.5·y (camera frame) has the normal (0, −0.5, 1)/‖·‖ flipped to face the
    camera; a hole's normal faces the camera along its ray."""
    intr = captures.Intrinsics(40, 30, 30.0, 30.0, 19.5, 14.5)
    v, u = np.mgrid[0:30, 0:40].astype(np.float64)
    y_over_z = (v - intr.cy) / intr.fy
    z = 2.0 / (1 - 0.5 * y_over_z)  # on the plane z = 2 + 0.5 y
    z[10, 10] = 0.0
    n = captures.normals_from_depth(z.astype(np.float32), intr)
    want = -np.array([0.0, -0.5, 1.0]) / np.linalg.norm([0.0, -0.5, 1.0])
    assert np.allclose(n[20, 30], want, atol=1e-3)
    ray = np.array([(10 - 19.5) / 30, (10 - 14.5) / 30, 1.0])
    assert np.allclose(n[10, 10], -ray / np.linalg.norm(ray), atol=1e-5)


@pytest.mark.parametrize(
    "break_it, message",
    [
        (
            lambda f: (f / "trajectory.log").write_text("0 0 1\n1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n"),
            "1 poses for 5 frames",
        ),
        (
            lambda f: write_image(f / "depth" / "00002.png", np.zeros((10, 10)), bit_depth=16, srgb=False),
            "depth is 10×10, its colour 00002.png 96×72",
        ),
        (
            lambda f: (f / "trajectory.log").write_text((f / "trajectory.log").read_text().replace("0.", "nan", 1)),
            "frame 0",
        ),
    ],
)
def test_bad_captures_say_where(tmp_path, capsys, office_capture, break_it, message):
    src = tmp_path / "capture"
    _write_rgbd(src, office_capture)
    break_it(src)
    code, cap = call_cli(["ibr", "import", "rgbd", str(src), "-o", str(tmp_path / "refs")], capsys)
    assert code == 2 and message in cap.err and cap.err.count("\n") == 1, cap.err
    assert not (tmp_path / "refs").exists()
    code, cap = call_cli(
        ["ibr", "import", "rgbd", str(src), "-o", str(tmp_path / "refs"), "--depth-scale", "0"], capsys
    )
    assert code == 2 and "--depth-scale must be positive" in cap.err


def test_an_unknown_colmap_camera_model_is_named(tmp_path):
    (tmp_path / "sparse").mkdir()
    (tmp_path / "sparse" / "cameras.txt").write_text("1 FISHEYE 96 72 70 48 36 0.1\n")
    (tmp_path / "sparse" / "images.txt").write_text("")
    with pytest.raises(InputError, match=r"cameras.txt: line 1: camera model 'FISHEYE' is not read"):
        captures.read_colmap(tmp_path)


def test_a_camera_keeps_its_pixel_aspect_through_a_references_file(tmp_path, ctx):
    from illusio.ibr.reference_views import save_references

    scene = load_scene("cornell-box")
    lens = Camera.from_intrinsics(32, 24, 30.0, 36.0, 14.0, 12.5)
    refs = capture(scene, [View(scene.camera().pose, lens)], (32, 24), ctx)
    again = load_references(save_references(refs, tmp_path / "refs")).views[0].view.camera
    assert again == lens


def test_an_import_reports_its_reading_and_each_reference_view(tmp_path, office_capture):
    """An import says what it is doing: the capture's reading, then one step per reference view
    made from it (core.progress, as a Python caller or the command line's bar hears it)."""
    from illusio.core.progress import reporting

    src = tmp_path / "capture"
    _write_rgbd(src, office_capture, open3d_matrix=True)
    heard = []
    with reporting(heard.append):
        frames = captures.read_capture("rgbd", src)
        captures.frames_to_references(frames, [0, 2, 4])
    finished = [(p.phase, p.done, p.total) for p in heard if p.finished]
    assert finished == [("ibr: reading the rgbd capture", 0, None), ("ibr: 3 reference views from the capture", 3, 3)]
    steps = [p.done for p in heard if p.phase.startswith("ibr: 3 reference") and not p.finished]
    assert steps == [0, 1, 2, 3] or steps[-3:] == [1, 2, 3], steps
