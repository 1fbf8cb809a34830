"""The command line as a user meets it: exit codes, one-line errors, files written."""

import json
import subprocess
import sys

from illusio.core import read_image


def illusio(*args, cwd=None):
    return subprocess.run(
        [sys.executable, "-m", "illusio", *map(str, args)], capture_output=True, text=True, cwd=cwd, timeout=300
    )


def assert_one_line_error(result, *words):
    assert result.returncode == 2, result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, result.stderr
    assert "Traceback" not in result.stderr
    assert lines[0].startswith("illusio: error:")
    for w in words:
        assert w in lines[0]


def test_missing_corrupt_and_nan_meshes_give_one_line_and_status_2(tmp_path):
    assert_one_line_error(illusio("render", tmp_path / "missing.obj", "-o", tmp_path / "x.png"), "missing.obj")
    corrupt = tmp_path / "corrupt.ply"
    corrupt.write_bytes(b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n1\n")
    assert_one_line_error(illusio("render", corrupt, "-o", tmp_path / "x.png"), "corrupt.ply")
    nan = tmp_path / "nan.obj"
    nan.write_text("v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n")
    assert_one_line_error(illusio("render", nan, "-o", tmp_path / "x.png"), "nan.obj", "not finite")
    assert not (tmp_path / "x.png").exists()


def test_output_over_input_is_refused_and_input_kept(tmp_path):
    mesh = tmp_path / "tri.obj"
    mesh.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    before = mesh.read_bytes()
    assert_one_line_error(illusio("render", mesh, "-o", mesh), "overwrite")
    assert mesh.read_bytes() == before
    # the same file reached through a symbolic link or through ..
    (tmp_path / "sub").mkdir()
    (tmp_path / "link.obj").symlink_to(mesh)
    for output in (tmp_path / "link.obj", tmp_path / "sub" / ".." / "tri.obj"):
        assert_one_line_error(illusio("render", mesh, "-o", output), "overwrite")
        assert mesh.read_bytes() == before


def test_bad_options_are_one_line_errors(tmp_path):
    assert_one_line_error(illusio("render", "office", "--size", "big", "-o", tmp_path / "x.png"), "--size")
    assert_one_line_error(illusio("render", "office", "--camera", "nope", "-o", tmp_path / "x.png"), "nope")
    assert_one_line_error(illusio("render", "kitchen", "-o", tmp_path / "x.png"), "kitchen")


def test_render_writes_a_picture_of_the_scene(tmp_path):
    out = tmp_path / "office.png"
    r = illusio("render", "office", "--size", "160x100", "-o", out)
    assert r.returncode == 0, r.stderr
    img = read_image(out)
    assert img.shape == (100, 160, 3)
    assert img.std() > 0.03  # not a blank frame
    assert (img.max(axis=2) > 0.9).sum() > 20  # the glowing ceiling lamps are in view


def test_info_reports_renderer_and_versions():
    r = illusio("info")
    assert r.returncode == 0, r.stderr
    assert "GL renderer" in r.stdout and "moderngl" in r.stdout and "illusio" in r.stdout


def test_demo_writes_gallery_with_existing_images(tmp_path):
    import re

    from illusio.gallery import SHOWCASES

    r = illusio("demo", "--out", tmp_path / "g", "--size", "160x100")
    assert r.returncode == 0, r.stderr
    # each section says when it starts and, when done, what it made and in how long
    for k, (name, _) in enumerate(SHOWCASES, 1):
        assert f"demo: [{k}/{len(SHOWCASES)}] {name} ..." in r.stdout
        assert re.search(rf"^demo: \[{k}/{len(SHOWCASES)}\] {name}: \d+ images in [\d.]+ s", r.stdout, re.M), r.stdout
    page = (tmp_path / "g" / "index.html").read_text()

    images = re.findall(r"<img src='([^']+)'", page)
    assert len(images) >= 4 + 8
    for rel in images:
        assert (tmp_path / "g" / rel).is_file()
    assert all(f"scenes/{n}-main.png" in page for n in ("living-room", "office", "museum", "turntable"))
    written = {p.relative_to(tmp_path / "g").as_posix() for p in (tmp_path / "g").rglob("*") if p.is_file()}
    unshown = sorted(w for w in written - {"index.html", "gallery.json"} if f"'{w}'" not in page)
    assert not unshown, f"written but not on the page: {unshown}"
    # scores in tables, and most items say how to make them again (the maps and patterns that are a
    # step of another item's pipeline have no command of their own)
    assert page.count("<table>") >= 3 and page.count("<code>illusio ") >= 0.75 * page.count("<figure>")
    _captions_parse_back(json.loads((tmp_path / "g" / "gallery.json").read_text()))


def _captions_parse_back(records: list[dict]) -> None:
    """Every caption's command is a command of ours whose options parse; where the item records the
    Params that made its image, the caption's options make the same Params (fields the command sets
    from its own options, like --focus-object, aside)."""
    import dataclasses
    import shlex

    import typer

    from illusio.cli.main import app
    from illusio.core.lazy import load
    from illusio.core.options import params_from_options
    from tests.cli.test_params_options import _technique_commands

    group = typer.main.get_command(app)
    table = {name: (click_command, callback) for name, click_command, callback in _technique_commands()}
    for name, click_command in group.commands.items():
        table.setdefault(name, (click_command, None))
    with_params = 0
    for record in records:
        if not record["command"]:
            continue
        pieces = [shlex.split(piece) for piece in record["command"].split("&&")]
        for k, words in enumerate(pieces):
            assert words[0] == "illusio", record
            name = " ".join(words[1:3]) if " ".join(words[1:3]) in table else words[1]
            click_command, callback = table[name]
            args = words[1 + len(name.split()) :]
            ctx = click_command.make_context(name, args)
            if k < len(pieces) - 1 or "params" not in record:
                continue
            recorded = record["params"]
            cls = load(recorded["class"])
            (key,) = [key for key, c in callback.params_classes.items() if c is cls]
            parsed = params_from_options(cls, callback.option_specs[key], ctx.params)
            made = json.loads(json.dumps(dataclasses.asdict(parsed), default=repr))
            for path in recorded["derived"]:
                head, *rest = path.split(".")
                holder_made, holder_recorded = made, recorded["values"]
                for part in rest:
                    holder_made, holder_recorded = holder_made[head], holder_recorded[head]
                    head = part
                holder_made.pop(head), holder_recorded.pop(head)
            assert made == recorded["values"], (record["image"], record["command"])
            with_params += 1
    assert with_params >= 20, with_params


def test_demo_unknown_showcase_is_an_error(tmp_path):
    assert_one_line_error(illusio("demo", "--out", tmp_path, "--only", "nope"), "nope")


def test_version_list_and_did_you_mean(capsys):
    """--version prints the package's version; `illusio list` names the scenes with their cameras,
    hosts and lamps, and the shapes, patterns, algorithms, line types and techniques; a mistyped name
    is answered with the closest valid one."""
    import illusio
    from tests.conftest import call_cli

    code, out = call_cli(["--version"], capsys)
    assert code == 0 and out.out.strip() == f"illusio {illusio.__version__}"
    code, out = call_cli(["list"], capsys)
    assert code == 0
    assert "office: cameras main, top; hosts back-wall; lamps lamp-0, lamp-1, lamp-2, lamp-3" in out.out
    for name in ("torus-knot", "pink-noise", "symmetric", "apparent-ridges"):
        assert f"  {name}\n" in out.out
    from illusio.core.technique import techniques

    for t in techniques().values():  # each technique with its title, source and views
        assert f"  {t.name}: {t.title}; source: {t.source_kind} (default {t.default_source})" in out.out
    assert "  relight: Relighting" in out.out and "views tv, wall, interactive" in out.out
    code, out = call_cli(["list", "shapes"], capsys)
    assert code == 0 and "scenes:" not in out.out and "  gear" in out.out
    for args, hint in (
        (["list", "scene"], "did you mean scenes?"),
        (["render", "living-rom", "-o", "x.png"], "did you mean living-room?"),
        (["sis-scene", "living-room", "-o", "x.png", "--host", "tv-scren"], "its hosts: back-wall, tv-screen"),
        (["sis-scene", "living-room", "-o", "x.png", "--camera", "sofa"], "has no camera 'sofa' (cameras: main, tv)"),
        (["sis-scene", "living-room", "-o", "x.png", "--host-layout", "tilted"], "not one of uv, viewer"),
    ):
        code, out = call_cli(args, capsys)
        assert code == 2 and hint in out.err, out.err


def test_switches_are_switches_with_their_default():
    """Every on/off option of every command is a --x/--no-x switch (not --x <bool>), except the
    eager --version and --no-cache (already a negative), and every option shows its default."""
    import typer

    from illusio.cli.main import app

    def commands(group):
        for name, command in group.commands.items():
            if getattr(command, "commands", None):  # a group (ibr): its commands
                yield from commands(command)
            else:
                yield name, command

    checked = 0
    for name, command in commands(typer.main.get_command(app)):
        for p in command.params:
            if getattr(p, "param_type_name", "") != "option":
                continue
            checked += 1
            if p.is_flag and p.opts not in (["--version"], ["--no-cache"], ["--help"]):
                assert p.secondary_opts, f"{name} {p.opts[0]} is a flag without its --no- form"
            if not p.required and p.opts != ["--help"]:
                assert p.show_default is not False, f"{name} {p.opts[0]} hides its default"
    assert checked > 100


def test_help_cites_papers_by_author_and_year():
    """A figure, equation or algorithm named in a command's help says whose paper it is from."""
    import re

    import typer

    from illusio.cli.main import app

    def texts(group):
        for command in group.commands.values():
            if getattr(command, "commands", None):
                yield from texts(command)
                continue
            yield command.help or ""
            yield from (getattr(p, "help", None) or "" for p in command.params)

    authors = ("Dehos", "Loscos", "Porquet", "Piranda", "Hanrahan", "Judd", "report", "DeCarlo", "Rusinkiewicz")
    cited = 0
    for text in texts(typer.main.get_command(app)):
        if re.search(r"\b(Figure|[Ee]quation|eq\.|Algorithm) ?\(?\d", text):
            assert any(a in text for a in authors), text
            cited += 1
    assert cited >= 4


def test_no_gl_driver_gives_the_install_hint(tmp_path):
    """A machine without Mesa's EGL (the loader pointed at a library that is not there): one line,
    exit 2, the apt-get line to run, and no output file."""
    import os

    from illusio.core.errors import APT_HINT

    env = {
        **os.environ,
        "GLCONTEXT_LINUX_LIBEGL": str(tmp_path / "missing" / "libEGL.so.1"),
        "ILLUSIO_GL_BACKEND": "egl",
    }
    r = subprocess.run(
        [sys.executable, "-m", "illusio", "render", "torus-knot", "-o", str(tmp_path / "x.png")],
        capture_output=True,
        text=True,
        env=env,
        timeout=120,
    )
    assert_one_line_error(r, "OpenGL 4.3", APT_HINT)
    assert not (tmp_path / "x.png").exists()
