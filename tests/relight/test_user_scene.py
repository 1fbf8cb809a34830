"""A user's own real scene (relight.photograph.load_real_scene): camera.json with full intrinsics —
a shifted principal point and f_x ≠ f_y drawn by the GPU passes as the ray-cast reference has it —
and a distorted lens's photograph undistorted on loading."""

import json

import numpy as np
import pytest

from illusio.core.errors import InputError
from illusio.core.images import linear_to_srgb, write_image
from illusio.relight import RelightSession
from illusio.relight.photograph import load_real_scene, polygon_ids
from illusio.scene.intrinsics import Intrinsics
from tests.relight.conftest import COARSE

ROOM = """
name: room
nodes:
  - {name: floor, shape: plane, params: {size: [4, 4]}, material: {colour: [0.6, 0.6, 0.6]}}
  - {name: back, shape: plane, params: {size: [4, 3]}, position: [0, 1.5, -2], rotation: [90, 0, 0],
     material: {colour: [0.5, 0.4, 0.3]}}
  - {name: block, shape: box, position: [0.3, 0.3, -0.5], scale: 0.6, material: {colour: [0.3, 0.5, 0.7]}}
lights:
  - {type: area, centre: [0, 2.5, -0.5], edge_u: [0.5, 0, 0], edge_v: [0, 0, 0.5], radiance: 6}
"""
W, H = 160, 120
OFF_CENTRE = Intrinsics(W, H, 118.0, 126.0, 91.3, 52.7)


def _folder(tmp_path, intrinsics: Intrinsics, photo: np.ndarray):
    tmp_path.mkdir(parents=True, exist_ok=True)
    (tmp_path / "scene.yaml").write_text(ROOM)
    write_image(tmp_path / "photograph.exr", photo)
    doc = {
        "position": [0.2, 1.2, 2.6],
        "target": [0.0, 0.6, -1.0],
        "up": [0, 1, 0],
        "width": W,
        "height": H,
        "fx": intrinsics.fx,
        "fy": intrinsics.fy,
        "cx": intrinsics.cx,
        "cy": intrinsics.cy,
        "distortion": list(intrinsics.distortion) or [0, 0, 0, 0],
    }
    (tmp_path / "camera.json").write_text(json.dumps(doc))
    return tmp_path


def test_a_shifted_principal_point_is_drawn_where_the_rays_put_it(ctx, tmp_path):
    real = load_real_scene(_folder(tmp_path, OFF_CENTRE, np.full((H, W, 3), 0.4, np.float32)))
    assert real.view.camera.shift != (0.0, 0.0) and real.view.camera.pixel_aspect != 1.0
    session = RelightSession(real, COARSE, ctx)
    try:
        h = session.solution.hierarchy
        gpu = np.where(session.pixel_element >= 0, h.polygon[np.maximum(session.pixel_element, 0)], -1)
        rays = polygon_ids(real.polygons, real.view, real.size)
        # the same polygon under 99 % of the pixels (edges may fall either way)
        assert (gpu == rays).mean() > 0.99
        # and not by chance: the centred camera puts them elsewhere
        centred = Intrinsics(W, H, 118.0, 126.0, (W - 1) / 2, (H - 1) / 2)
        other = polygon_ids(real.polygons, type(real.view)(real.view.pose, centred.camera(0.05, 100.0)), real.size)
        assert (other == rays).mean() < 0.95
    finally:
        session.release()


def test_a_distorted_photograph_is_undistorted_on_loading(tmp_path):
    """A pinhole image, distorted by the plain formula (each distorted pixel takes the pinhole pixel
    its undistorted ray hits), comes back within 0.012 (mean absolute) once loaded, where it was 0.027 off."""
    yy, xx = np.mgrid[0:H, 0:W]
    pinhole = np.stack(
        [0.5 + 0.4 * np.sin(xx / 7.0), 0.5 + 0.4 * np.cos(yy / 9.0), 0.5 + 0.3 * np.sin((xx + yy) / 5.0)], axis=-1
    ).astype(np.float32)
    lens = Intrinsics(W, H, 118.0, 126.0, 81.0, 58.0, "OPENCV", (-0.15, 0.02, 0.0, 0.0))
    # distorted image: for each distorted pixel, invert the distortion by fixed-point iteration
    xd, yd = (xx - lens.cx) / lens.fx, (yy - lens.cy) / lens.fy
    x, y = xd.copy(), yd.copy()
    for _ in range(20):
        r2 = x * x + y * y
        s = 1 - 0.15 * r2 + 0.02 * r2 * r2
        x, y = xd / s, yd / s
    u, v = (
        np.clip(np.rint(x * lens.fx + lens.cx), 0, W - 1).astype(int),
        np.clip(np.rint(y * lens.fy + lens.cy), 0, H - 1).astype(int),
    )
    distorted = pinhole[v, u]
    real = load_real_scene(_folder(tmp_path, lens, distorted))
    inner = (slice(15, H - 15), slice(20, W - 20))  # where the distorted image saw the scene
    error = np.abs(real.photograph[inner] - pinhole[inner]).mean()
    assert error < 0.012  # measured 0.0077 (nearest-pixel distortion)
    assert np.abs(distorted[inner] - pinhole[inner]).mean() > 0.02  # the lens did change it: 0.027


def _written_by_other_tools(tmp_path, linear: np.ndarray):
    """The photograph as other software writes it: (file, what loading it must give)."""
    import cv2
    import OpenEXR
    from PIL import Image

    from illusio.core.images import srgb_to_linear

    out = []
    exr = tmp_path / "exr"
    exr.mkdir()
    with OpenEXR.File(
        {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}, {"RGB": linear.astype(np.float32)}
    ) as f:  # OpenEXR's own writer
        f.write(str(exr / "photograph.exr"))
    out.append((exr, linear, 1e-6))
    hdr = tmp_path / "hdr"
    hdr.mkdir()
    cv2.imwrite(str(hdr / "photograph.hdr"), np.ascontiguousarray(linear[..., ::-1], np.float32))  # RGBE: 1 % steps
    out.append((hdr, linear, 0.01 * linear.max()))
    png16 = tmp_path / "png16"
    png16.mkdir()
    encoded16 = np.round(linear_to_srgb(linear) * 65535).astype(np.uint16)
    cv2.imwrite(str(png16 / "photograph.png"), np.ascontiguousarray(encoded16[..., ::-1]))
    out.append((png16, srgb_to_linear(encoded16 / 65535.0), 1e-4))
    jpg = tmp_path / "jpg"
    jpg.mkdir()
    encoded8 = np.round(linear_to_srgb(linear) * 255).astype(np.uint8)
    Image.fromarray(encoded8).save(jpg / "photograph.jpg", quality=98)
    out.append((jpg, srgb_to_linear(encoded8 / 255.0), 0.02))
    return out


def test_photographs_written_by_other_tools_read_as_linear_radiance(tmp_path):
    """EXR by OpenEXR's writer, Radiance HDR and a 16-bit PNG by OpenCV's, a JPEG by Pillow's: each
    read back as the linear radiance it encodes (sRGB decoded for the PNG and the JPEG)."""
    pytest.importorskip("cv2")
    yy, xx = np.mgrid[0:H, 0:W]
    linear = np.stack([0.05 + 0.9 * xx / W, 0.05 + 0.9 * yy / H, np.full((H, W), 0.3)], axis=-1).astype(np.float32)
    for folder, expected, tolerance in _written_by_other_tools(tmp_path, linear):
        real = load_real_scene(_with_model(folder))
        assert np.abs(real.photograph - expected).mean() < tolerance, folder.name
    # a response named: the 16-bit PNG read as linear, and as gamma 2.2
    png16 = tmp_path / "png16"
    raw = load_real_scene(png16, "linear").photograph
    assert np.abs(raw - linear_encoded(linear)).mean() < 1e-4
    assert np.abs(load_real_scene(png16, "gamma:2.2").photograph - raw**2.2).max() < 1e-5
    with pytest.raises(InputError, match="--response must be one of"):
        load_real_scene(png16, "log")


def linear_encoded(linear):
    return np.round(linear_to_srgb(linear) * 65535) / 65535.0


def _with_model(folder):
    (folder / "scene.yaml").write_text(ROOM)
    doc = {
        "position": [0.2, 1.2, 2.6],
        "target": [0.0, 0.6, -1.0],
        "width": W,
        "height": H,
        "fx": 118.0,
        "fy": 126.0,
        "cx": 91.3,
        "cy": 52.7,
    }
    (folder / "camera.json").write_text(json.dumps(doc))
    return folder


def test_the_viewer_opens_a_users_folder(tmp_path, capsys):
    """`illusio view FOLDER -t relight` shows that folder's photograph (as photographed: no lamp
    changed at opening), not the built-in office's."""
    from illusio.core.images import read_image
    from tests.conftest import call_cli

    yy, xx = np.mgrid[0:H, 0:W]
    photo = np.stack([0.1 + 0.6 * xx / W, 0.1 + 0.6 * yy / H, np.full((H, W), 0.25)], axis=-1).astype(np.float32)
    (tmp_path / "room").mkdir()
    folder = _folder(tmp_path / "room", OFF_CENTRE, photo)
    walk = tmp_path / "walk.json"
    walk.write_text(
        '[{"t": 0, "eye": [0, 1, 0], "target": [0, 1, -1]}, {"t": 0.1, "eye": [0, 1, 0], "target": [0, 1, -1]}]'
    )
    shot = tmp_path / "shot.png"
    code, cap = call_cli(
        [
            "view",
            str(folder),
            "-t",
            "relight",
            "--view",
            "baseline",
            "--path",
            str(walk),
            "-o",
            str(tmp_path / "v.gif"),
            "--screenshot",
            str(shot),
            "--size",
            f"{W}x{H}",
        ],
        capsys,
    )
    assert code == 0, cap.err
    shown = read_image(shot)[..., :3]
    real = load_real_scene(folder)
    model = polygon_ids(real.polygons, real.view, real.size) >= 0  # where the model is (black elsewhere)
    assert model.mean() > 0.5
    assert np.abs(shown - real.photograph)[model].mean() < 0.03  # the folder's gradient, not the office


def test_registration_scores_a_camera_that_lines_up_above_one_that_does_not(tmp_path, capsys):
    """The model's edges against the photograph's (relight.registration): the photograph of the
    model through its own camera scores high, the same camera turned by 3° is warned
    of, and --show registration draws the model's edges in red."""
    from illusio.core.images import read_image
    from illusio.radiosity import scene_polygons
    from illusio.relight.registration import POOR, registration
    from illusio.scene import load_scene
    from illusio.scene.camera import Pose, View
    from tests.conftest import call_cli

    folder = tmp_path / "room"
    folder.mkdir()
    (folder / "scene.yaml").write_text(ROOM)
    polygons = scene_polygons(load_scene(folder / "scene.yaml"))
    view = View(Pose((0.2, 1.2, 2.6), (0.0, 0.6, -1.0)), OFF_CENTRE.camera(0.05, 100.0))
    # a "photograph": each surface its own flat grey (what Canny finds are the model's outlines)
    ids = polygon_ids(polygons, view, (W, H))
    shade = np.where(ids >= 0, 0.15 + 0.7 * ((polygons.surfaces()[np.maximum(ids, 0)] * 0.37) % 1), 0.02)
    photo = np.repeat(shade[..., None], 3, axis=2).astype(np.float32)
    good = registration(polygons, view, photo)
    turned = View(Pose(view.pose.position, (0.2, 0.6, -1.0)), view.camera)  # ~3° to the right
    bad = registration(polygons, turned, photo)
    assert good.score > 0.8 and bad.score < POOR <= good.score
    _folder(folder, OFF_CENTRE, photo)
    out = tmp_path / "reg.png"
    code, cap = call_cli(["relight", str(folder), "-o", str(out), "--show", "registration"], capsys)
    assert code == 0, cap.err
    assert "registration:" in cap.out and "warning" not in cap.err
    red = read_image(out)
    assert ((red[..., 0] > 0.9) & (red[..., 1] < 0.2)).sum() > 100  # the model's edges drawn
    doc = json.loads((folder / "camera.json").read_text())
    doc["target"] = [0.2, 0.6, -1.0]
    (folder / "camera.json").write_text(json.dumps(doc))
    code, cap = call_cli(["relight", str(folder), "-o", str(tmp_path / "x.png")], capsys)
    assert code == 0 and "do not line up well" in cap.err


def test_a_folder_whose_model_is_gltf_is_the_same_real_scene(tmp_path):
    """The model as Blender users have it (scene.glb, written here through trimesh by illusio's
    exporter, area lamp in extras): the same polygons, reflectances and lamps as from scene.yaml."""
    from illusio.scene import load_scene
    from illusio.scene.export import export_gltf

    yaml_folder = _folder(tmp_path / "yaml", OFF_CENTRE, np.full((H, W, 3), 0.4, np.float32))
    gltf_folder = tmp_path / "gltf"
    gltf_folder.mkdir()
    export_gltf(load_scene(yaml_folder / "scene.yaml"), gltf_folder / "scene.glb")
    for name in ("photograph.exr", "camera.json"):
        (gltf_folder / name).write_bytes((yaml_folder / name).read_bytes())
    a, b = load_real_scene(yaml_folder), load_real_scene(gltf_folder)
    assert a.polygons.names == b.polygons.names and a.polygons.lamps == b.polygons.lamps
    assert np.allclose(a.polygons.corners, b.polygons.corners, atol=1e-5)
    assert np.allclose(a.polygons.reflectance, b.polygons.reflectance) and np.allclose(
        a.polygons.exitance, b.polygons.exitance
    )


def test_a_folder_without_camera_json_is_refused_unless_the_guess_is_asked_for(tmp_path):
    """Relit from a guessed camera, the image would be wrong with nothing to stop the user: the
    folder is refused with the command that makes camera.json; --camera-guess relights anyway."""
    from tests.cli.test_cli import assert_one_line_error, illusio

    folder = _folder(tmp_path / "room", OFF_CENTRE, np.full((H, W, 3), 0.4, np.float32))
    (folder / "camera.json").unlink()
    (folder / "scene.yaml").write_text(ROOM + "cameras:\n  main: {position: [0.2, 1.2, 2.6], target: [0, 0.6, -1]}\n")
    assert_one_line_error(
        illusio("relight", folder, "-o", tmp_path / "x.png", "--epsilon", "3e-3"), "no camera.json", "relight calibrate"
    )
    assert not (tmp_path / "x.png").exists()
    r = illusio("relight", folder, "-o", tmp_path / "x.png", "--epsilon", "3e-3", "--camera-guess")
    assert r.returncode == 0, r.stderr
