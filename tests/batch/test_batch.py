"""illusio batch: job files validated before anything runs, the manifest's resume, failures and dead
workers that lose nothing, and the same bytes from every backend."""

import json
import os
import threading
import time
from pathlib import Path

import pytest

from illusio.batch import load_job, run_job
from illusio.batch.worker import run_task
from illusio.scene.builtin import shapes
from tests.conftest import call_cli

JOB = """
tasks:
  - command: lines
    inputs: ["meshes/*.off"]
    options: {size: 96x96}
    sweep: {tau: [0.5, 2.0]}
    output: "{input_stem}-tau{tau}.png"
  - command: sis-scene
    options: {size: 128x72}
    frames: [0, 3]
    output: "tv/{frame:05d}.png"
    video: tv.mp4
"""


def write_mesh(path: Path, mesh) -> None:
    import trimesh

    trimesh.Trimesh(mesh.vertices, mesh.faces, process=False).export(path)


@pytest.fixture
def job_dir(tmp_path) -> Path:
    (tmp_path / "meshes").mkdir()
    write_mesh(tmp_path / "meshes" / "knot.off", shapes.torus_knot())
    write_mesh(tmp_path / "meshes" / "gear.off", shapes.gear())
    (tmp_path / "job.yaml").write_text(JOB)
    return tmp_path


def outputs(folder: Path) -> dict:
    return {
        str(p.relative_to(folder)): p.read_bytes()
        for p in sorted(folder.rglob("*"))
        if p.is_file() and p.name != "manifest.jsonl"
    }


def test_expansion(job_dir):
    job = load_job(job_dir / "job.yaml")
    assert [t.output for t in job.tasks] == [
        "gear-tau0.5.png",
        "gear-tau2.0.png",
        "knot-tau0.5.png",
        "knot-tau2.0.png",
        "tv/00000.png",
        "tv/00001.png",
        "tv/00002.png",
        "tv/00003.png",
    ]
    assert job.tasks[1].argv[:2] == ("lines", str(job_dir / "meshes" / "gear.off"))
    assert job.tasks[1].argv[-2:] == ("--tau", "2.0") and job.tasks[6].argv[-2:] == ("--frame", "2")
    assert job.videos == [(2, "tv.mp4", 24.0, [f"tv/0000{k}.png" for k in range(4)])]


@pytest.mark.parametrize(
    "edit, message",
    [
        (lambda j: j.replace("command: lines", "command: linez"), "task 1: command: 'linez'"),
        (lambda j: j.replace("size: 96x96", "sise: 96x96"), "task 1: options: lines has no option 'sise'"),
        (lambda j: j.replace("meshes/*.off", "meshes/*.obj"), "task 1: inputs: 'meshes/*.obj' matches no file"),
        (lambda j: j.replace("{input_stem}-tau{tau}.png", "tau{tau}.png"), "is also the output of task 1"),
        (lambda j: j.replace("frames: [0, 3]", "frames: [3, 0]"), "task 2: frames"),
        (lambda j: j.replace("tv/{frame:05d}.png", "tv/{frames}.png"), "task 2: output: 'tv/{frames}.png' uses frames"),
        (
            lambda j: j.replace("command: sis-scene", "command: render\n    inputs: [meshes/gear.off]"),
            "render has no --frame",
        ),
        (lambda j: j.replace("    video: tv.mp4", "    vidéo: tv.mp4"), "task 2: unknown field"),
        (lambda j: j.replace("tv/{frame:05d}.png", "../tv/{frame:05d}.png"), "inside the out folder"),
        (lambda j: j + "  - [", "not valid YAML at line"),
    ],
)
def test_bad_jobs_are_refused_before_anything_runs(job_dir, capsys, edit, message):
    (job_dir / "job.yaml").write_text(edit(JOB))
    out = job_dir / "out"
    code, cap = call_cli(["batch", str(job_dir / "job.yaml"), "--out", str(out)], capsys)
    assert code == 2 and message in cap.err and "Traceback" not in cap.err, cap.err
    assert not out.exists()


def test_run_resume_and_redo(job_dir):
    out = job_dir / "out"
    job = load_job(job_dir / "job.yaml")
    first = run_job(job, out)
    assert first.ran == 8 and not first.failed and first.videos == ["tv.mp4"]
    made = outputs(out)
    assert len(made) == 9
    assert len((out / "manifest.jsonl").read_text().splitlines()) == 8
    again = run_job(job, out)
    assert again.ran == 0 and again.skipped == 8
    (out / "knot-tau2.0.png").unlink()  # missing: only it runs again
    (out / "tv" / "00001.png").write_bytes(b"not a png")  # corrupt: only it runs again
    third = run_job(job, out)
    assert third.ran == 2 and third.skipped == 6
    assert outputs(out) == made


def test_a_failing_task_is_retried_reported_and_the_rest_finish(job_dir, capsys):
    (job_dir / "meshes" / "broken.off").write_text("OFF\n8 12 0\n0 0 0\n")  # a truncated mesh
    code, cap = call_cli(["batch", str(job_dir / "job.yaml"), "--out", str(job_dir / "out"), "--retries", "2"], capsys)
    assert code == 1
    # (after the progress line a log shows for a phase of a second or more)
    summary = [line for line in cap.out.splitlines() if not line.startswith("illusio: ")]
    assert summary[0].startswith("8 ran, 0 already done, 2 failed, 4 retried")  # two tasks, two tries again each
    assert "failed: broken-tau0.5.png" in cap.err and "failed: broken-tau2.0.png" in cap.err
    made = outputs(job_dir / "out")
    assert "knot-tau2.0.png" in made and "tv.mp4" in made and not any(k.startswith("broken") for k in made)


def crash_once(task, out):
    """A worker that dies (the whole process) the first time it meets tv/00001.png."""
    marker = Path(out) / ".crashed"
    if task.output == "tv/00001.png" and not marker.exists():
        marker.write_text("x")
        os._exit(3)
    return run_task(task, out)


def test_workers_give_the_same_bytes_and_survive_a_dead_worker(job_dir):
    job = load_job(job_dir / "job.yaml")
    here = run_job(job, job_dir / "here")
    report = run_job(job, job_dir / "pool", workers=2, task_fn=crash_once)
    assert (job_dir / "pool" / ".crashed").exists() and report.restarted >= 1
    assert report.ran == 8 and not report.failed and len(report.workers) >= 2
    (job_dir / "pool" / ".crashed").unlink()
    assert outputs(job_dir / "pool") == outputs(job_dir / "here")
    assert here.ran == 8


@pytest.fixture(scope="module")
def ray_cluster():
    ray = pytest.importorskip("ray", reason="the cluster extra (pip install 'illusio[cluster]')")
    os.environ.setdefault("RAY_AUTH_MODE", "disabled")
    ray.init(num_cpus=2, log_to_driver=False, include_dashboard=False, configure_logging=False)
    yield ray
    ray.shutdown()


def test_ray_gives_the_same_bytes_and_survives_a_killed_actor(job_dir, ray_cluster):
    ray = ray_cluster
    job = load_job(job_dir / "job.yaml")
    run_job(job, job_dir / "here")
    killed = []

    def kill_one(actors):
        def watch():
            manifest = job_dir / "ray" / "manifest.jsonl"
            deadline = time.time() + 60
            while time.time() < deadline and not (manifest.exists() and manifest.read_text().strip()):
                time.sleep(0.05)
            ray.kill(actors[0])  # mid-job: one task done, others running or queued
            killed.append(actors[0])

        threading.Thread(target=watch, daemon=True).start()

    report = run_job(job, job_dir / "ray", workers=2, use_ray=True, on_start=kill_one)
    assert killed and report.ran == 8 and not report.failed
    assert outputs(job_dir / "ray") == outputs(job_dir / "here")
    rows = [json.loads(line) for line in (job_dir / "ray" / "manifest.jsonl").read_text().splitlines()]
    assert sorted(r["output"] for r in rows) == sorted(t.output for t in job.tasks)


def test_interrupt_leaves_a_valid_manifest(job_dir):
    """Ctrl-C in the middle: what finished is listed, nothing partial is left, a rerun completes."""
    job = load_job(job_dir / "job.yaml")
    count = {"n": 0}

    def interrupt_third(task, out):
        count["n"] += 1
        if count["n"] == 3:
            raise KeyboardInterrupt
        return run_task(task, out)

    from illusio.batch import Interrupted

    with pytest.raises(Interrupted) as stop:
        run_job(job, job_dir / "out", task_fn=interrupt_third)
    assert stop.value.report.ran == 2
    assert len((job_dir / "out" / "manifest.jsonl").read_text().splitlines()) == 2
    assert not [p for p in (job_dir / "out").rglob("*") if p.name.startswith(".") or p.suffix == ".tmp"]
    rest = run_job(job, job_dir / "out")
    assert rest.skipped == 2 and rest.ran == 6


def test_ray_missing_gives_the_install_hint(job_dir, capsys, monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "ray", None)  # import ray now fails as if not installed
    code, cap = call_cli(["batch", str(job_dir / "job.yaml"), "--out", str(job_dir / "out"), "--ray"], capsys)
    assert code == 2 and "pip install 'illusio[cluster]'" in cap.err and "Traceback" not in cap.err


def test_ray_takes_an_optional_address():
    from illusio.cli.batch import optional_values

    assert optional_values(["batch", "j.yaml", "--ray", "--workers", "2"]) == [
        "batch",
        "j.yaml",
        "--ray",
        "local",
        "--workers",
        "2",
    ]
    assert optional_values(["batch", "j.yaml", "--ray"]) == ["batch", "j.yaml", "--ray", "local"]
    assert optional_values(["batch", "j.yaml", "--ray", "auto"]) == ["batch", "j.yaml", "--ray", "auto"]


def test_a_group_command_writing_a_folder(tmp_path):
    """IBR captures along a sweep: 'ibr capture' by its two words, its output a folder; a file
    changed inside the folder makes it run again."""
    (tmp_path / "job.yaml").write_text(
        "tasks:\n  - command: ibr capture\n    arguments: [office]\n    options: {size: 64x48}\n"
        "    sweep: {views: [2, 3]}\n    output: refs-{views}\n"
    )
    job = load_job(tmp_path / "job.yaml")
    assert job.tasks[0].argv[:3] == ("ibr", "capture", "office")
    out = tmp_path / "out"
    assert run_job(job, out).ran == 2
    assert len(list((out / "refs-3").glob("view-*.npz"))) == 3
    assert run_job(job, out).ran == 0
    (out / "refs-2" / "references.json").write_text("{}")
    again = run_job(job, out)
    assert again.ran == 1 and again.skipped == 1


def test_scene_files_from_other_tools_as_inputs(tmp_path):
    """A job over Blender's own glTF and OBJ of one scene (tests/data/blender): each is read as a
    scene, with its materials (the cube's red sides), not as a grey shape on the turntable."""
    import shutil

    import numpy as np
    from PIL import Image

    blender = Path(__file__).parents[1] / "data" / "blender"
    (tmp_path / "scenes").mkdir()
    for name in ("blender.glb", "blender.obj", "blender.mtl", "checker.png"):
        shutil.copy(blender / name, tmp_path / "scenes" / name)
    (tmp_path / "job.yaml").write_text(
        "tasks:\n  - command: render\n    inputs: [scenes/*.glb, scenes/*.obj]\n"
        "    options: {size: 96x54}\n    output: '{input_name}.png'\n"
    )
    job = load_job(tmp_path / "job.yaml")
    out = tmp_path / "out"
    assert run_job(job, out).ran == 2
    images = {p.name: np.asarray(Image.open(p), np.float64) / 255 for p in out.glob("*.png")}
    assert sorted(images) == ["blender.glb.png", "blender.obj.png"]
    for image in images.values():  # the cube's red sides, as Blender made them
        red = (image[..., 0] > 0.2) & (image[..., 0] > 2 * image[..., 1])
        assert red.mean() > 0.005
