"""The demo page in a real headless browser (Chromium): every image and video loads, the page logs
nothing on its console, and a screenshot of it is drawn. The page checks its own media after
loading (gallery/html.py) and records the counts on <body>; a broken link is caught (tested)."""

import os
import re
import shutil
import subprocess

import pytest

from illusio.core import read_image


def chromium() -> str:
    for name in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(name)
        if path:
            return path
    if os.environ.get("CI"):
        pytest.fail("Chromium is not installed: scripts/setup.sh test installs it")
    pytest.skip("no Chromium for the gallery's browser test (apt-get install chromium)")


def browse(page, *flags) -> subprocess.CompletedProcess:
    return subprocess.run(
        [
            chromium(),
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--hide-scrollbars",
            "--virtual-time-budget=20000",
            "--enable-logging=stderr",
            "--v=0",
            *flags,
            page.as_uri(),
        ],
        capture_output=True,
        text=True,
        timeout=180,
    )


def body_counts(dom: str) -> tuple[int, int]:
    body = re.search(r"<body[^>]*>", dom).group(0)
    media = re.search(r'data-media="(\d+)"', body)
    ok = re.search(r'data-media-ok="(\d+)"', body)
    assert media and ok, f"the page's media check did not finish: {body}"
    return int(ok.group(1)), int(media.group(1))


@pytest.fixture(scope="module")
def gallery(tmp_path_factory):
    out = tmp_path_factory.mktemp("demo")
    from illusio.cli.main import run

    try:
        run(["demo", "--out", str(out), "--only", "viewer,shapes", "--size", "320x200"])
    except SystemExit as exc:
        assert not exc.code
    return out


def test_every_image_and_video_of_the_demo_page_loads_without_console_messages(gallery, tmp_path):
    page = gallery / "index.html"
    items = len(re.findall(r"<(?:img|video) ", page.read_text()))
    assert items >= 8 and page.read_text().count("<video ") == 4  # the viewer's camera-path videos
    result = browse(page, "--dump-dom")
    assert result.returncode == 0, result.stderr[-2000:]
    assert body_counts(result.stdout) == (items, items)
    console = [line for line in result.stderr.splitlines() if ":CONSOLE" in line]
    assert not console, console
    shot = tmp_path / "page.png"
    result = browse(page, f"--screenshot={shot}", "--window-size=1400,1800")
    assert result.returncode == 0 and shot.exists(), result.stderr[-2000:]
    image = read_image(shot)
    assert image.shape[:2] == (1800, 1400) and image.std() > 0.05  # a page was drawn, not a blank


def test_a_broken_link_is_reported_by_the_page(gallery):
    page = gallery / "broken.html"
    text = (gallery / "index.html").read_text()
    first_video = re.search(r"<video src='([^']+)'", text).group(1)
    page.write_text(text.replace(f"src='{first_video}'", "src='viewer/missing.mp4'", 1))
    result = browse(page, "--dump-dom")
    ok, total = body_counts(result.stdout)
    assert ok == total - 1
    assert any("cannot load viewer/missing.mp4" in line for line in result.stderr.splitlines())
    assert "broken" in re.search(r"<video[^>]*missing[^>]*>", result.stdout).group(0)  # outlined in red
