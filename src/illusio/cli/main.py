"""The ``illusio`` command: one typer app, one module per command.

Errors a user can cause (IllusioError) print one line on stderr and exit with status 2, without a
traceback; mesh repair warnings print one line each.
"""

from __future__ import annotations

import inspect
import os
import signal
import sys
import threading
import warnings

import typer

from ..core.errors import IllusioError
from ..core.lazy import load
from ..core.technique import techniques
from . import batch, compile_kernels, demo, export, info, listing, view

app = typer.Typer(
    add_completion=False,
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    help="illusio: perception-driven rendering on a headless OpenGL core.",
)


def _version(value: bool) -> None:
    if value:
        from .. import __version__

        typer.echo(f"illusio {__version__}")
        raise typer.Exit()


@app.callback()
def _main(
    version: bool = typer.Option(
        False, "--version", callback=_version, is_eager=True, help="print illusio's version and exit"
    ),
    quiet: bool = typer.Option(
        False, "--quiet/--progress", "-q", help="no progress (bars on a terminal, a line per long phase elsewhere)"
    ),
) -> None:
    """illusio: perception-driven rendering on a headless OpenGL core."""
    from ..core.progress import install
    from .reporter import reporter

    install(reporter(quiet))


app.command("info")(info.info)
app.command("compile")(compile_kernels.compile_kernels)
app.command("list")(listing.listing)
app.command("demo")(demo.demo)
app.command("export")(export.export)


def _technique_commands() -> dict[str, str]:
    """Every technique's commands from the registry (core.technique: ``commands``), in its order."""
    out: dict[str, str] = {}
    for t in techniques().values():
        for name, target in t.command_targets().items():
            if name in out:
                raise TypeError(f"technique {t.name!r}: command {name!r} is another technique's already")
            out[name] = target
    return out


#: two-word commands that are not groups: ``illusio relight prepare`` runs the command registered
#: as "relight prepare" (one word to click, hidden from the command list; its usage line reads right)
ALIASES: dict[tuple[str, str], str] = {}
for _name, _target in _technique_commands().items():
    _runs = load(_target)
    if isinstance(_runs, typer.Typer):
        app.add_typer(_runs, name=_name)
    elif " " in _name:
        ALIASES[tuple(_name.split(" ", 1))] = _name
        app.command(_name, hidden=True)(_runs)
    else:
        app.command(_name)(_runs)
app.command("view")(view.view)
app.command("batch")(batch.batch)


def _flowed(text: str | None) -> str | None:
    """Docstring paragraphs as one line each: the command list shows the first without its line breaks."""
    if not text:
        return text
    return "\n\n".join(" ".join(p.split()) for p in inspect.cleandoc(text).split("\n\n"))


def _switches_untyped(command, ctx) -> None:
    """A switch takes no value: no <bool> beside it in the help (typer shows the Python type)."""
    for p in command.get_params(ctx):
        if getattr(p, "is_flag", False):
            p.metavar = ""


class _Command(typer.core.TyperCommand):
    def format_help(self, ctx, formatter):
        _switches_untyped(self, ctx)
        return super().format_help(ctx, formatter)


class _Group(typer.core.TyperGroup):
    def format_help(self, ctx, formatter):
        _switches_untyped(self, ctx)
        return super().format_help(ctx, formatter)


def _tidy(typer_app: typer.Typer) -> None:
    typer_app.info.cls = _Group
    for command in typer_app.registered_commands:
        command.cls = _Command
        command.help = _flowed(command.help or inspect.getdoc(command.callback))
    for group in typer_app.registered_groups:
        group.typer_instance.info.help = _flowed(group.typer_instance.info.help)
        _tidy(group.typer_instance)


_tidy(app)


def expand(argv: list[str]) -> list[str]:
    """The command line as the app reads it: two-word aliases joined, options with an optional value
    given their default (``--ray`` alone)."""
    argv = list(argv)
    if len(argv) >= 2 and (argv[0], argv[1]) in ALIASES:
        argv = [ALIASES[(argv[0], argv[1])]] + argv[2:]
    return batch.optional_values(argv)


def _show_warning(message, category, filename, lineno, file=None, line=None):
    print(f"illusio: warning: {' '.join(str(message).split())}", file=sys.stderr)


class Interrupted(BaseException):
    """Ctrl-C or SIGTERM: a BaseException that click's handlers let through (they answer
    KeyboardInterrupt with "Aborted!" and exit 1) and ``except Exception`` does not swallow, so every
    ``finally`` runs (atomic outputs remove their temporary files) on its way to :func:`run`."""


def _interrupted(signum, frame):
    raise Interrupted


def run(argv: list[str] | None = None) -> None:
    """Console-script entry point."""
    warnings.showwarning = _show_warning
    previous = {}
    if threading.current_thread() is threading.main_thread():
        # Ctrl-C and SIGTERM unwind: atomic outputs remove their temporary files, nothing partial stays
        previous = {sig: signal.signal(sig, _interrupted) for sig in (signal.SIGINT, signal.SIGTERM)}
    argv = expand(sys.argv[1:] if argv is None else argv)
    try:
        app(args=argv, standalone_mode=True)
    except IllusioError as exc:
        print(f"illusio: error: {exc.one_line()}", file=sys.stderr)
        sys.exit(2)
    except (Interrupted, KeyboardInterrupt):
        print("illusio: interrupted: nothing written", file=sys.stderr)
        if "mitsuba" in sys.modules:  # its render threads, wound down or not, crash a normal exit
            sys.stdout.flush()
            sys.stderr.flush()
            os._exit(130)
        sys.exit(130)
    finally:
        from ..core.progress import install

        install(None)  # the command's listener ends with it
        for sig, handler in previous.items():
            signal.signal(sig, handler)


if __name__ == "__main__":
    run()
