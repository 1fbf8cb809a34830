"""The automatic choice of τ, λ and the ridge filter's threshold (issue 20: parameters that transfer):
never worse than where it starts, a local best on its grid, clearly better than a poor start, and
the CLI's --auto draws with what it chose."""

import re
from dataclasses import replace

import numpy as np
import pytest

from illusio.core.errors import InputError
from illusio.core.renderer import Frame
from illusio.lines.compare import line_mask, score
from illusio.lines.drawing import LineRenderer, framing_view
from illusio.lines.params import LineParams
from illusio.lines.tuning import AUTO_GRID, auto_parameters, edge_target
from illusio.scene.builtin import shape
from tests.conftest import call_cli

SIZE = (256, 256)


@pytest.fixture(scope="module")
def knot(ctx):
    mesh = shape("torus-knot")
    renderer = LineRenderer(ctx)
    renderer.prepare(mesh)
    view = framing_view(mesh, 30, 15)
    yield renderer, view, edge_target(renderer, mesh, view, SIZE)
    renderer.release()


def f1(renderer, view, target, params) -> float:
    return score(line_mask(renderer.render(Frame(view, SIZE), params)), target).f1


def test_auto_is_a_local_best_and_never_worse_than_its_start(knot):
    renderer, view, target = knot
    start = LineParams()
    result = auto_parameters(renderer, view, SIZE, target, start)
    assert result.converged and result.scores.f1 >= result.start.f1
    assert result.start.f1 == pytest.approx(f1(renderer, view, target, start))
    assert result.scores.f1 == pytest.approx(f1(renderer, view, target, result.params))
    for name, values in AUTO_GRID:  # no single parameter moved scores higher
        for value in values:
            assert f1(renderer, view, target, replace(result.params, **{name: value})) <= result.scores.f1 + 1e-9
    # only the three tuned fields changed
    assert replace(result.params, tau=start.tau, lam=start.lam, threshold=start.threshold) == start


def test_auto_recovers_from_a_poor_start(knot):
    """From a start that draws almost no ridges (a high threshold, small q), the choice finds a
    drawing that matches the edges much better."""
    renderer, view, target = knot
    poor = replace(LineParams(), tau=-4.0, threshold=0.8)
    result = auto_parameters(renderer, view, SIZE, target, poor)
    assert result.scores.f1 > result.start.f1 + 0.05
    assert (result.params.tau, result.params.threshold) != (poor.tau, poor.threshold)


def test_auto_refuses_what_it_cannot_tune(knot):
    renderer, view, target = knot
    with pytest.raises(InputError, match="hybrid"):
        auto_parameters(renderer, view, SIZE, target, replace(LineParams(), method="object"))
    with pytest.raises(InputError, match="apparent ridges"):
        auto_parameters(renderer, view, SIZE, target, replace(LineParams(), lines=("silhouettes",)))


def test_lines_cli_auto(tmp_path, capsys):
    """--auto prints what it chose and draws with it: the drawing scores what it printed, above the
    defaults' score from the same command without --auto."""
    out = tmp_path / "knot.png"
    code, printed = call_cli(
        [
            "lines",
            "torus-knot",
            "-o",
            str(out),
            "--size",
            "256x256",
            "--auto",
            "--compare",
            "canny",
            "--antialias",
            "1",
        ],
        capsys,
    )
    assert code == 0, printed.err
    chosen = re.search(
        r"auto against canny: tau (\S+), lambda (\S+), threshold (\S+): F1 ([\d.]+) \(from ([\d.]+)", printed.out
    )
    assert chosen, printed.out
    scored = float(re.search(r"against canny: precision .* F1 ([\d.]+)", printed.out.split("\n", 1)[1]).group(1))
    assert scored == pytest.approx(float(chosen.group(4)), abs=1e-3)
    assert float(chosen.group(4)) >= float(chosen.group(5))
    code, printed = call_cli(
        [
            "lines",
            "torus-knot",
            "-o",
            str(tmp_path / "default.png"),
            "--size",
            "256x256",
            "--compare",
            "canny",
            "--antialias",
            "1",
        ],
        capsys,
    )
    default = float(re.search(r"F1 ([\d.]+)", printed.out).group(1))
    assert default == pytest.approx(float(chosen.group(5)), abs=1e-3)
    code, printed = call_cli(
        ["lines", "torus-knot", "-o", str(tmp_path / "x.png"), "--auto", "--method", "object"], capsys
    )
    assert code == 2 and "hybrid" in printed.err


def test_registered_score_finds_the_shift(rng):
    """Random lines moved by a random whole-pixel shift: the registered score finds that shift and
    F1 1, where the plain score at tolerance 1 px falls."""
    from skimage.draw import line

    from illusio.lines.compare import registered_score, shift_mask

    a = np.zeros((120, 160), bool)
    for _ in range(6):
        r0, r1 = rng.integers(10, 110, 2)
        c0, c1 = rng.integers(10, 150, 2)
        a[line(r0, c0, r1, c1)] = True
    # 2 to 4 px on each axis: a shift within the tolerance (1 px) would not make the plain score fall
    shift = tuple(int(v) for v in rng.integers(2, 5, 2) * rng.choice([-1, 1], 2))
    b = shift_mask(a, *shift)
    found, (dx, dy) = registered_score(a, b, tolerance=1.0, max_shift=4)
    assert (dx, dy) == shift and found.f1 == pytest.approx(1.0)
    assert score(a, b, 1.0).f1 < 0.9


def test_photograph_misregistration_is_reported():
    """The path-traced stand-in for a photograph (painted albedo, soft shadows, noise), taken with the
    camera turned by (3, −2) px: the registered score of the drawing against its Canny edges finds
    that shift to a pixel and scores higher than without it; from the drawing's own camera it
    finds (about) none."""
    pytest.importorskip("mitsuba", reason="the photograph is path-traced (photo extra)")
    from illusio.core.context import default_context
    from illusio.lines.compare import image_edges, registered_score
    from illusio.lines.photograph import exposed, photograph

    mesh = shape("torus-knot")
    view = framing_view(mesh, 30, 15)
    renderer = default_context().kept(LineRenderer)
    renderer.prepare(mesh)
    ours = line_mask(renderer.render(Frame(view, SIZE), LineParams()))
    for applied in ((3, -2), (0, 0)):
        photo = photograph(mesh, view, SIZE, samples=16, misregistration=applied)
        edges = image_edges(exposed(photo), "canny")
        found, shift = registered_score(ours, edges, max_shift=5)
        assert abs(shift[0] - applied[0]) <= 1 and abs(shift[1] - applied[1]) <= 1, (applied, shift)
        if applied != (0, 0):
            assert found.f1 > score(ours, edges).f1 + 0.05


def test_lines_cli_compare_photo(tmp_path, capsys):
    """--compare photo: the photograph beside the drawing, the plain and the registered scores. The
    photograph is taken from the drawing's own camera, so the registered score finds (about) no
    shift, and it equals the plain score where it finds none."""
    pytest.importorskip("mitsuba", reason="the photograph is path-traced (photo extra)")
    out = tmp_path / "knot.png"
    code, printed = call_cli(["lines", "torus-knot", "-o", str(out), "--size", "192x192", "--compare", "photo"], capsys)
    assert code == 0, printed.err
    plain = float(re.search(r"against photo: .*F1 ([\d.]+)", printed.out).group(1))
    registered = re.search(r"registered \(shifted ([+-]\d+), ([+-]\d+) px\): .*F1 ([\d.]+)", printed.out)
    shift = (int(registered.group(1)), int(registered.group(2)))
    assert max(abs(shift[0]), abs(shift[1])) <= 1, shift
    if shift == (0, 0):
        assert float(registered.group(3)) == pytest.approx(plain, abs=1e-3)
    assert (tmp_path / "knot-photo.png").is_file() and (tmp_path / "knot-compare.png").is_file()
