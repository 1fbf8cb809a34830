"""Job files: what ``illusio batch`` runs, validated before anything runs.

A job is YAML with a list of ``tasks``; each entry expands to one or more concrete tasks:

    tasks:
      - command: lines                  # any illusio command that writes one file or folder (-o);
                                        # a group's by its two words: "ibr capture"
        inputs: ["meshes/*.ply"]        # optional globs, relative to the job file: each match is the first argument
        arguments: [torus-knot, gear]   # or: first arguments as given (built-in scenes and shapes)
        options: {size: 512x512}        # options as on the command line, without --
        sweep: {tau: [0.5, 1.0, 2.0]}   # optional: the cartesian product of every key's values
        output: "{input_stem}-tau{tau}.png"   # relative to --out; {input_stem}, {frame} and sweep keys
      - command: sis-scene
        frames: [0, 299]                # optional inclusive range: one task per frame (--frame N)
        output: "tv/{frame:05d}.png"
        video: tv.mp4                   # optional: the frames in order, once all are done

Errors name the entry (``task 2``) and the field, so a 1000-task job fails before the first runs.
"""

from __future__ import annotations

import glob
import hashlib
import itertools
import json
import string
from dataclasses import dataclass, field
from pathlib import Path

from ..core.errors import InputError
from ..core.files import read_yaml
from ..core.lazy import load

__all__ = ["Task", "Job", "load_job", "command_table"]

_FIELDS = {"command", "inputs", "arguments", "options", "sweep", "output", "frames", "video", "fps"}


@dataclass(frozen=True)
class Task:
    """One command run: ``argv`` for the illusio app (the output option included), ``output``
    relative to the job's out folder, ``entry`` the job entry it came from, ``frame`` or None."""

    entry: int
    argv: tuple[str, ...]
    output: str
    frame: int | None = None

    @property
    def key(self) -> str:
        """What the manifest knows the task by: its command line (the output included)."""
        return hashlib.sha1(json.dumps(self.argv).encode(), usedforsecurity=False).hexdigest()[:16]


@dataclass
class Job:
    path: Path
    tasks: list[Task]
    #: (entry, video path relative to out, fps, the frame tasks' outputs in order)
    videos: list[tuple[int, str, float, list[str]]] = field(default_factory=list)


#: the application whose commands tasks run, and its two-word aliases: named, not imported, because
#: the command line is the layer above batch (``illusio batch`` is one of its commands)
APP, ALIASES = "illusio.cli.main:app", "illusio.cli.main:ALIASES"


def command_table() -> dict:
    """illusio command name → its click command (those that take -o/--output)."""
    import typer

    group = typer.main.get_command(load(APP))
    out = {}
    for name, command in group.commands.items():
        subcommands = getattr(command, "commands", None)
        pairs = [(f"{name} {sub}", c) for sub, c in subcommands.items()] if subcommands else [(name, command)]
        for full, c in pairs:  # "ibr capture", "ibr render": a group's commands by their two words
            if any("--output" in p.opts for p in c.params if hasattr(p, "opts")):
                out[full] = c
    for words, target in load(ALIASES).items():  # "relight prepare" for the hidden "relight-prepare"
        if target in out:
            out[" ".join(words)] = out.pop(target)
    return out


def _option_args(entry: int, command, name: str, value) -> list[str]:
    """The command-line words for option ``name`` = ``value`` of ``command`` (validated)."""
    flag = "--" + str(name).replace("_", "-")
    for p in command.params:
        if flag in getattr(p, "opts", ()):
            if p.name == "output":
                raise InputError(f"task {entry}: options: give the output as the task's 'output', not as an option")
            if getattr(p, "is_flag", False) and getattr(p, "secondary_opts", None):
                if not isinstance(value, bool):
                    raise InputError(f"task {entry}: options: {name} is a switch: true or false, got {value!r}")
                return [flag if value else p.secondary_opts[0]]
            if getattr(p, "is_flag", False):
                if not isinstance(value, bool):
                    raise InputError(f"task {entry}: options: {name} is a switch: true or false, got {value!r}")
                return [flag] if value else []
            if getattr(p, "multiple", False) and isinstance(value, list):
                return [w for v in value for w in (flag, str(v))]
            if isinstance(value, (list, dict)):
                raise InputError(f"task {entry}: options: {name} takes one value, got {value!r}")
            return [flag, str(value)]
    known = sorted(
        o[2:] for p in command.params for o in getattr(p, "opts", ()) if o.startswith("--") and o != "--output"
    )
    raise InputError(f"task {entry}: options: {command.name} has no option {name!r}; it has: {', '.join(known)}")


def _fields_of(pattern: str) -> set[str]:
    try:
        return {name.split(".")[0].split("[")[0] for _, name, _, _ in string.Formatter().parse(pattern) if name}
    except ValueError as exc:
        raise InputError(f"output pattern {pattern!r}: {exc}") from None


def load_job(path) -> Job:
    """Read and validate the job file at ``path``; expand it into tasks. Raises InputError."""
    path = Path(path)
    doc = read_yaml(path, "job")
    if not isinstance(doc, dict) or not isinstance(doc.get("tasks"), list) or not doc["tasks"]:
        raise InputError(f"job file {path}: needs a non-empty list 'tasks'")
    commands = command_table()
    job = Job(path, [])
    seen: dict[str, int] = {}
    for entry, spec in enumerate(doc["tasks"], 1):
        if not isinstance(spec, dict):
            raise InputError(f"task {entry}: must be a mapping with at least 'command' and 'output'")
        unknown = set(spec) - _FIELDS
        if unknown:
            raise InputError(
                f"task {entry}: unknown field(s) {', '.join(sorted(unknown))}; fields: {', '.join(sorted(_FIELDS))}"
            )
        name = spec.get("command")
        if name not in commands:
            raise InputError(
                f"task {entry}: command: {name!r} is not an illusio command that writes a file; "
                f"choose one of {', '.join(sorted(commands))}"
            )
        command = commands[name]
        pattern = spec.get("output")
        if not isinstance(pattern, str) or not pattern:
            raise InputError(f"task {entry}: output: a file name pattern is required")
        options = spec.get("options") or {}
        sweep = spec.get("sweep") or {}
        if not isinstance(options, dict) or not isinstance(sweep, dict):
            raise InputError(f"task {entry}: options and sweep must be mappings")
        for key, values in sweep.items():
            if not isinstance(values, list) or not values:
                raise InputError(f"task {entry}: sweep: {key} needs a non-empty list of values")
            if key in options:
                raise InputError(f"task {entry}: sweep: {key} is also a fixed option")
        fixed = [w for k, v in options.items() for w in _option_args(entry, command, k, v)]
        inputs = [None]
        if "inputs" in spec:
            patterns = spec["inputs"] if isinstance(spec["inputs"], list) else [spec["inputs"]]
            inputs = []
            for pat in patterns:
                found = sorted(glob.glob(str(path.parent / str(pat)), recursive=True))
                if not found:
                    raise InputError(f"task {entry}: inputs: {pat!r} matches no file (relative to {path.parent})")
                inputs += found
        if "arguments" in spec:
            if "inputs" in spec:
                raise InputError(f"task {entry}: give inputs or arguments, not both")
            given = spec["arguments"]
            if not isinstance(given, list) or not given or not all(isinstance(a, (str, int, float)) for a in given):
                raise InputError(f"task {entry}: arguments: a non-empty list of names, got {given!r}")
            inputs = [str(a) for a in given]
        frames = [None]
        if "frames" in spec:
            rng = spec["frames"]
            if (
                not isinstance(rng, list)
                or len(rng) != 2
                or not all(isinstance(v, int) for v in rng)
                or rng[0] < 0
                or rng[1] < rng[0]
            ):
                raise InputError(
                    f"task {entry}: frames: an inclusive range [first, last] of frame numbers ≥ 0, got {rng!r}"
                )
            if not any("--frame" in getattr(p, "opts", ()) for p in command.params):
                raise InputError(f"task {entry}: frames: {name} has no --frame option")
            frames = list(range(rng[0], rng[1] + 1))
        allowed = set(sweep) | {"input_stem", "input_name", "frame"}
        missing = _fields_of(pattern) - allowed
        if missing:
            raise InputError(
                f"task {entry}: output: {pattern!r} uses {', '.join(sorted(missing))}; "
                f"it may use {', '.join(sorted(allowed))}"
            )
        keys = list(sweep)
        frame_outputs = []
        for source, frame, values in itertools.product(inputs, frames, itertools.product(*(sweep[k] for k in keys))):
            fields = dict(zip(keys, values))
            fields.update(
                input_stem=Path(source).stem if source else "",
                input_name=Path(source).name if source else "",
                frame=frame if frame is not None else 0,
            )
            try:
                output = pattern.format(**fields)
            except (ValueError, KeyError, IndexError) as exc:
                raise InputError(f"task {entry}: output: {pattern!r} cannot be filled ({exc})") from None
            if Path(output).is_absolute() or ".." in Path(output).parts:
                raise InputError(f"task {entry}: output: {output!r} must stay inside the out folder")
            if output in seen:
                raise InputError(
                    f"task {entry}: output: {output!r} is also the output of task {seen[output]}; "
                    "add a sweep key, {input_stem} or {frame} to the pattern"
                )
            seen[output] = entry
            argv = name.split() + ([source] if source else []) + fixed
            argv += [w for k, v in fields.items() if k in sweep for w in _option_args(entry, command, k, v)]
            if frame is not None:
                argv += ["--frame", str(frame)]
            job.tasks.append(Task(entry, tuple(argv), output, frame))
            frame_outputs.append(output)
        if "video" in spec:
            if frames == [None]:
                raise InputError(f"task {entry}: video: needs frames")
            fps = spec.get("fps", 24)
            if not isinstance(fps, (int, float)) or not 0 < fps <= 240:
                raise InputError(f"task {entry}: fps: a number in (0, 240], got {fps!r}")
            job.videos.append((entry, str(spec["video"]), float(fps), frame_outputs))
    return job
