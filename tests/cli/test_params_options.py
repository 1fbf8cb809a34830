"""Command-line options come from the Params' declared fields (cli.params_options): one statement of
each parameter reaches the CLI, the viewer's panel and batch jobs. The test that matters adds a
field no code knows to DofParams and finds it in all three, with no other edit."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap
from dataclasses import dataclass

import pytest

from illusio.cli.params_options import option_specs, params_options
from illusio.core.errors import InputError
from illusio.core.params import check_ranges, param

THROWAWAY = textwrap.dedent("""
    import dataclasses, json, sys
    from pathlib import Path
    import illusio.dof.params as dof_params
    from illusio.core.params import param

    # a field nobody wrote code for, added before anything imports DofParams
    dof_params.DofParams = dataclasses.make_dataclass(
        "DofParams",
        [("throwaway_knob", float, param(0.25, range=(0.0, 1.0), unit="m", help="a field only this test knows"))],
        bases=(dof_params.DofParams,), frozen=True, namespace={"__module__": dof_params.__name__})

    import typer.testing
    from illusio.cli.main import app
    from illusio.core.context import Context
    from illusio.core.params import describe
    from illusio.dof.renderer import DofRenderer
    from illusio.viewer.viewer import Viewer
    from illusio.batch import load_job, run_job

    found = {}
    runner = typer.testing.CliRunner()
    found["help"] = runner.invoke(app, ["dof", "--help"]).output
    refused = runner.invoke(app, ["dof", "cornell-box", "-o", "x.png", "--throwaway-knob", "3"])
    found["refused"] = str(refused.exception)

    ctx = Context()
    viewer = Viewer(ctx, "dof", "cornell-box", size=(48, 32))
    found["panel"] = [i.name for i in describe(viewer.mode.params)]
    viewer.set_param("throwaway_knob", 0.5)
    found["panel_value"] = viewer.mode.params.throwaway_knob

    seen = []
    render = DofRenderer.render_texture
    def spy(self, frame, params=None):
        seen.append(params.throwaway_knob)
        return render(self, frame, params)
    DofRenderer.render_texture = spy
    folder = Path(sys.argv[1])
    (folder / "job.yaml").write_text(
        "tasks:\\n  - command: dof\\n    arguments: [cornell-box]\\n"
        "    options: {throwaway-knob: 0.75, size: 32x24}\\n    output: knob.png\\n")
    job = load_job(folder / "job.yaml")
    found["argv"] = list(job.tasks[0].argv)
    report = run_job(job, folder / "out")
    found["batch"] = {"ran": report.ran, "failed": report.failed, "seen": seen,
                      "written": (folder / "out" / "knob.png").exists()}
    print(json.dumps(found))
""")


def test_a_new_params_field_reaches_the_cli_the_panel_and_batch_jobs(tmp_path):
    import os

    env = {**os.environ, "COLUMNS": "240", "TERMINAL_WIDTH": "240"}  # the help on one line per option
    done = subprocess.run(
        [sys.executable, "-c", THROWAWAY, str(tmp_path)],
        capture_output=True,
        text=True,
        timeout=600,
        cwd=tmp_path,
        env=env,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    found = json.loads(done.stdout.strip().splitlines()[-1])
    assert "--throwaway-knob" in found["help"] and "a field only this test knows (m; 0 to 1)" in found["help"]
    assert "--throwaway-knob = 3 m is out of range [0, 1]" in found["refused"]
    assert "throwaway_knob" in found["panel"] and found["panel_value"] == 0.5
    assert found["argv"][-2:] == ["--throwaway-knob", "0.75"] or "--throwaway-knob" in found["argv"]
    assert found["batch"] == {"ran": 1, "failed": {}, "seen": [0.75], "written": True}


@dataclass(frozen=True)
class _Inner:
    depth: int = param(3, range=(1, 9), step=1, help="how deep")
    __post_init__ = check_ranges


@dataclass(frozen=True)
class _Outer:
    speed: float = param(1.5, range=(0.0, 10.0), unit="m/s", flag="velocity")
    kinds: tuple = param(("a", "b"), choices=("a", "b", "c"), multiple=True)
    on: bool = param(True, flag="on/off")
    name: str = param("x", panel=False, cli=True)
    hidden: float = param(2.0, panel=False)
    inner: _Inner = param(default_factory=_Inner)
    __post_init__ = check_ranges


def test_option_specs_follow_the_metadata():
    specs = {s.path: s for s in option_specs(_Outer)}
    assert set(specs) == {"speed", "kinds", "on", "name", "inner.depth"}  # panel=False stays out unless cli=True
    assert specs["speed"].flag == "--velocity" and specs["on"].flag == "--on/--off"
    assert specs["inner.depth"].flag == "--depth" and specs["kinds"].kind == "multi"


def test_generated_command_builds_the_params_and_refuses_by_flag():
    import typer
    import typer.testing

    got = []

    @params_options(params=_Outer)
    def command(count: int = typer.Option(1, "--count"), *, params: _Outer) -> None:
        got.append((count, params))

    app = typer.Typer()
    app.command()(command)
    runner = typer.testing.CliRunner()
    result = runner.invoke(app, ["--count", "2", "--velocity", "3", "--kinds", "c,a", "--off", "--depth", "5"])
    assert result.exit_code == 0, result.output
    assert got == [(2, _Outer(speed=3.0, kinds=("c", "a"), on=False, inner=_Inner(5)))]
    result = runner.invoke(app, ["--depth", "12"])
    assert isinstance(result.exception, InputError) and "--depth = 12 is out of range [1, 9]" in str(result.exception)
    result = runner.invoke(app, ["--kinds", "a,z"])
    assert isinstance(result.exception, InputError) and "--kinds: 'z' is not one of a, b, c" in str(result.exception)


def test_two_fields_making_one_flag_are_refused_at_import():
    @dataclass(frozen=True)
    class Clash:
        depth: int = param(1)
        inner: _Inner = param(default_factory=_Inner)

    with pytest.raises(TypeError, match="both make --depth"):
        option_specs(Clash)


def _technique_commands():
    """(name, click command, callback) of every command the registry's techniques name, groups opened."""
    import typer

    from illusio.cli.main import app
    from illusio.core.technique import load, techniques

    group = typer.main.get_command(app)
    out = []
    for t in techniques().values():
        for name, target in t.command_targets().items():
            runs = load(target)
            if isinstance(runs, typer.Typer):
                for c in runs.registered_commands:
                    out.append((f"{name} {c.name}", group.commands[name].commands[c.name], c.callback))
            else:
                out.append((name, group.commands[name], runs))
    return out


def test_every_technique_command_offers_every_declared_field():
    """Each command's options hold its Params' shown fields, and its defaults are the Params'; every
    technique with Params has at least one command made from them."""
    with_specs = set()
    for name, click_command, callback in _technique_commands():
        specs = getattr(callback, "option_specs", None)
        if not specs:
            continue
        with_specs.add(name.split()[0])
        opts = {o: p for p in click_command.params for o in getattr(p, "opts", ())}
        for _key, group in specs.items():
            for spec in group:
                option = opts[spec.long]
                default = ",".join(spec.default) if spec.kind == "multi" else spec.default
                assert option.default == default, (name, spec.long)
    assert {"sis", "sis-scene", "lines", "curvature", "dof", "ibr", "radiosity", "relight"} <= with_specs


def test_view_names_the_viewer_modes_the_registry_gives():
    from illusio.cli.view import _VIEWABLE
    from illusio.viewer.modes import MODES

    assert list(MODES) == _VIEWABLE


def test_help_groups_each_commands_options_by_the_params_they_set_and_their_group():
    """--help lists the command's own options apart from its Params' (issue 46: 36 options in one
    panel): every generated option sits in its Params' panel for its group (param(group=)), the
    panels in GROUPS' order (method, the paper's parameters, output, advanced), and a nested Params'
    fields take the group of the field that nests them unless they declare their own."""
    from illusio.cli.params_options import help_panel
    from illusio.core.params import GROUPS

    for name, click_command, callback in _technique_commands():
        specs = getattr(callback, "option_specs", None)
        if not specs:
            continue
        opts = {o: p for p in click_command.params for o in getattr(p, "opts", ())}
        panels = []
        for key, group in specs.items():
            for spec in group:
                panel = opts[spec.long].rich_help_panel
                assert panel == help_panel(callback.params_classes[key], spec.info.group), (name, spec.long)
            order = [
                p.rich_help_panel
                for p in click_command.params
                if p.rich_help_panel in {help_panel(callback.params_classes[key], g) for g in GROUPS}
            ]
            groups = [next(g for g in GROUPS if help_panel(callback.params_classes[key], g) == p) for p in order]
            assert groups == sorted(groups, key=list(GROUPS).index), (name, key, groups)
            panels += order
        own = [p for p in click_command.params if getattr(p, "rich_help_panel", None) is None]
        assert own and panels, name
    from illusio.core.options import option_specs
    from illusio.radiosity.params import RadiosityParams

    specs = {s.path: s.info.group for s in option_specs(RadiosityParams)}
    assert specs["hierarchy.epsilon"] == "paper" and specs["hierarchy.criterion"] == "method"
    assert specs["tolerance"] == "advanced" and specs["exposure"] == "output"
    assert help_panel(RadiosityParams, "method") == "Radiosity: method"
    from illusio.lines.params import CurvatureParams, LineParams

    nested = {s.path: s.info.group for s in option_specs(LineParams)}
    assert nested["curvature.rings"] == "advanced"  # LineParams files its curvature under advanced
    assert {s.path: s.info.group for s in option_specs(CurvatureParams)}["rings"] == "paper"
    with pytest.raises(ValueError, match="group"):
        param(1.0, group="misc")
