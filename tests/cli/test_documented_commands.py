"""The command lines README.md and the documentation pages give, as written, against the commands:
every line names a command that exists, with options it takes and values they accept, and every input
file it names exists in the repository (or is written by an earlier line of the same page); those
that need no window and no minutes-long run are run. So the docs cannot rot."""

import shlex
from pathlib import Path

import pytest
import typer

from illusio.cli.main import app, expand

ROOT = Path(__file__).resolve().parents[2]
#: options whose value is a file the command writes
OUTPUTS = {"-o", "--output", "--out", "--video", "--record", "--reference", "--photograph"}
SUFFIXES = (".yaml", ".json", ".obj", ".ply", ".off", ".stl", ".glb", ".gltf", ".npz", ".npy", ".png", ".exr")


def pages() -> list[Path]:
    """README.md, then the documentation pages (not the built site nor sphinx-gallery's output)."""
    docs = sorted(
        p for p in (ROOT / "docs").rglob("*.md") if not {"_build", "gallery"} & set(p.relative_to(ROOT / "docs").parts)
    )
    return [ROOT / "README.md", *docs]


def page_commands(page: Path) -> list[list[str]]:
    """The ``illusio ...`` lines of an indented code block of ``page``, as argv lists."""
    lines = [line.strip() for line in page.read_text().splitlines() if line.startswith("    illusio ")]
    # an optional value written in brackets ([auto|HOST:PORT]) is the reader's choice: left out
    return [[w for w in shlex.split(line.split("  #")[0])[1:] if not w.startswith("[")] for line in lines]


#: (page, argv) of every documented command line, each distinct line once (its first page)
DOCUMENTED = []
for _page in pages():
    for _argv in page_commands(_page):
        if all(_argv != a for _, a in DOCUMENTED):
            DOCUMENTED.append((_page, _argv))


def _id(item) -> str:
    page, argv = item
    return f"{page.stem}: {' '.join(argv)}"[:70]


def resolve(argv):
    group = typer.main.get_command(app)
    command, name, rest = group.commands[argv[0]], argv[0], argv[1:]
    if getattr(command, "commands", None):  # a group (ibr): its command
        command, name, rest = command.commands[rest[0]], f"{name} {rest[0]}", rest[1:]
    return command, name, rest


def test_the_docs_list_commands():
    assert len(page_commands(ROOT / "docs" / "commands.md")) >= 25
    assert page_commands(ROOT / "README.md") == []  # README points to the command page instead
    assert len(DOCUMENTED) >= 40


#: commands whose first argument is a folder they write
FOLDER_WRITERS = (("relight", "example"),)


def folders_written(page, argv) -> set:
    """The folders earlier lines of ``page`` write as their first argument (FOLDER_WRITERS)."""
    out = set()
    for line in page_commands(page):
        if line == argv:
            break
        if tuple(line[:2]) in FOLDER_WRITERS:
            out.add(line[2])
    return out


@pytest.mark.parametrize("item", DOCUMENTED, ids=_id)
def test_documented_command_parses(item):
    page, argv = item
    command, name, rest = resolve(expand(argv))
    command.make_context(name, list(rest))  # raises on an option it does not take or a bad value
    written = set()
    for line in page_commands(page):
        if line == argv:
            break
        written |= {line[k + 1] for k, w in enumerate(line[:-1]) if w in OUTPUTS}
    words = expand(argv)
    for k, word in enumerate(words):
        inside_written = any(word.startswith(w.rstrip("/") + "/") for w in written | folders_written(page, argv))
        if (
            word.endswith(SUFFIXES)
            and not (k and words[k - 1] in OUTPUTS)
            and word not in written
            and not inside_written
        ):
            assert (ROOT / word).exists(), f"{page.name}: {' '.join(argv)}: {word} does not exist"


#: documented lines run as written here. Parsed above only: `view` (a window), `demo` (run by
#: test_cli.py at a small size), the dof scenario video (6½ minutes here), the batch job's reruns with
#: workers and on Ray (the same job as its first line)
RUN = ("info", "list", "render", "lines", "curvature", "dof", "radiosity", "relight", "batch")


def runs(argv) -> bool:
    line = " ".join(argv)
    return (
        line.startswith(RUN)
        and "--scenario" not in argv
        and not ("batch" in line and ("--workers" in argv or "--ray" in argv))
    )


@pytest.mark.parametrize("item", [i for i in DOCUMENTED if runs(i[1])], ids=_id)
def test_documented_command_runs_as_written(item, tmp_path, monkeypatch, capsys):
    from tests.conftest import call_cli

    page, argv = item
    if argv[0] == "relight" or "--reference" in argv:
        pytest.importorskip("mitsuba", reason="path-traced by Mitsuba (photo extra)")
    (tmp_path / "examples").symlink_to(ROOT / "examples")
    monkeypatch.chdir(tmp_path)
    for earlier in prerequisites(page, argv):  # the lines of its page that write what it reads, first
        code, out = call_cli(earlier, capsys)
        assert code == 0, (earlier, out.err)
    code, out = call_cli(argv, capsys)
    assert code == 0, out.err
    words = expand(argv)
    for k, word in enumerate(words[:-1]):
        if word in ("-o", "--output", "--out"):
            assert (tmp_path / words[k + 1]).exists()


def _writes(line) -> set:
    words = expand(line)
    out = {words[k + 1] for k, w in enumerate(words[:-1]) if w in OUTPUTS}
    return out | ({line[2]} if tuple(line[:2]) in FOLDER_WRITERS else set())


def prerequisites(page, argv) -> list:
    """The earlier lines of ``page`` whose outputs ``argv`` reads (and theirs), in the page's order."""
    lines = page_commands(page)
    before = lines[: lines.index(argv)]
    needed, wanted = [], set(expand(argv))
    for line in reversed(before):
        made = _writes(line)
        # a file it reads, one inside a folder it reads, or in a folder a line wrote
        if any(
            w == m or w.startswith(m.rstrip("/") + "/") or m.startswith(w.rstrip("/") + "/")
            for w in wanted
            for m in made
        ):
            needed.append(line)
            wanted |= set(expand(line))
    return needed[::-1]


def test_getting_started_names_the_system_packages_setup_installs():
    """The getting-started page's apt-get lines are setup.sh's list: every package setup may install
    is named there, and the page names none that setup does not install (python3-venv is in its
    prerequisites, and in README's)."""
    import re

    setup = set(re.findall(r"need\+=\(([\w.+-]+)\)", (ROOT / "scripts" / "setup.sh").read_text()))
    text = (ROOT / "docs" / "getting-started.md").read_text()
    section = text[text.index("## Two commands") : text.index("## Extras")]
    page = {
        w for line in re.findall(r"apt-get install -y --no-install-recommends ([^`]+)`", section) for w in line.split()
    }
    assert setup >= {"libegl1", "libgl1", "libgl1-mesa-dri", "libatomic1", "xvfb", "xauth", "chromium"}
    assert page == setup - {"python3-venv"}, (page, setup)
    assert "python3-venv" in section and "python3-venv" in (ROOT / "README.md").read_text()
