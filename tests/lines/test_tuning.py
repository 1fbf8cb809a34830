"""The automatic choice of τ, λ and the ridge filter's threshold (issue 20: parameters that transfer):
never worse than where it starts, a local best on its grid, clearly better than a poor start, and
the CLI's --auto draws with what it chose."""

import re
from dataclasses import replace

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
    for name, values in AUTO_GRID:                   # no single parameter moved scores higher
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
    code, printed = call_cli(["lines", "torus-knot", "-o", str(out), "--size", "256x256", "--auto", "--compare", "canny",
                              "--antialias", "1"], capsys)
    assert code == 0, printed.err
    chosen = re.search(r"auto against canny: tau (\S+), lambda (\S+), threshold (\S+): F1 ([\d.]+) \(from ([\d.]+)",
                       printed.out)
    assert chosen, printed.out
    scored = float(re.search(r"against canny: precision .* F1 ([\d.]+)", printed.out.split("\n", 1)[1]).group(1))
    assert scored == pytest.approx(float(chosen.group(4)), abs=1e-3)
    assert float(chosen.group(4)) >= float(chosen.group(5))
    code, printed = call_cli(["lines", "torus-knot", "-o", str(tmp_path / "default.png"), "--size", "256x256",
                              "--compare", "canny", "--antialias", "1"], capsys)
    default = float(re.search(r"F1 ([\d.]+)", printed.out).group(1))
    assert default == pytest.approx(float(chosen.group(5)), abs=1e-3)
    code, printed = call_cli(["lines", "torus-knot", "-o", str(tmp_path / "x.png"), "--auto", "--method", "object"], capsys)
    assert code == 2 and "hybrid" in printed.err
