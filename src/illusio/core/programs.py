"""GLSL programs from ``.glsl`` files.

One file holds every stage of a program, each stage between ``#if defined(VERTEX_SHADER)``-style
guards (``VERTEX_SHADER``, ``GEOMETRY_SHADER``, ``FRAGMENT_SHADER``, ``COMPUTE_SHADER``); the loader
compiles each stage the file mentions with that name defined. Rules of a file:

- ``#version`` on line 1;
- ``#include "common/x.glsl"`` is replaced by that file, searched beside the including file, then in
  ``illusio/shaders/``; each file is included once per program;
- a program's own path is absolute, or relative to ``illusio/shaders/`` or to the ``illusio`` package
  (``"passes/shaders/gbuffer.glsl"``);
- ``#define NAME default`` lines are the program's knobs: ``ProgramCache.get(path, NAME=value)``
  replaces the default. Overriding a name the source does not define is an error (a typo would
  otherwise pass silently).

Compiled programs are cached by (resolved paths, stages, defines). Compile errors raise
:class:`ShaderError` with the driver's line numbers mapped back to ``file:line``.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import moderngl

from .errors import ShaderError

__all__ = ["ProgramCache", "preprocess", "SHADER_ROOT", "STAGES"]

PACKAGE_ROOT = Path(__file__).resolve().parent.parent
SHADER_ROOT = PACKAGE_ROOT / "shaders"
STAGES = ("VERTEX_SHADER", "GEOMETRY_SHADER", "FRAGMENT_SHADER", "COMPUTE_SHADER")
_STAGE_ARGS = {
    "VERTEX_SHADER": "vertex_shader",
    "GEOMETRY_SHADER": "geometry_shader",
    "FRAGMENT_SHADER": "fragment_shader",
}
_INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"\s*$')
_DEFINE = re.compile(r"^(\s*#\s*define\s+)([A-Za-z_]\w*)(\s+.*)?$")


def _format_define(value: Any) -> str:
    if isinstance(value, bool):
        return "1" if value else "0"
    if isinstance(value, float):
        return repr(value) if "." in repr(value) or "e" in repr(value) else f"{value}.0"
    return str(value)


def _resolve(name: str, including: Path | None) -> Path:
    candidates = ([including.parent / name] if including else []) + [SHADER_ROOT / name, PACKAGE_ROOT / name]
    for c in candidates:
        if c.is_file():
            return c.resolve()
    where = f" (included from {including})" if including else ""
    raise ShaderError(f"shader file {name!r} not found{where}")


def preprocess(
    path: str | Path, defines: dict[str, Any] | None = None, stage: str | None = None
) -> tuple[str, list[Path]]:
    """Expand includes and apply define overrides; return (source, files by source-string number).

    ``#line`` directives tag each expanded file with its index in the returned list so that driver
    messages can be mapped back to files.
    """
    root = _resolve(str(path), None) if not Path(path).is_absolute() else Path(path).resolve()
    overrides = {k: _format_define(v) for k, v in (defines or {}).items()}
    used: set[str] = set()
    files: list[Path] = []
    out: list[str] = []

    def expand(file: Path) -> None:
        if file in files:
            return
        files.append(file)
        index = len(files) - 1
        lines = file.read_text().splitlines()
        first = 0
        if index == 0:
            if not lines or not lines[0].startswith("#version"):
                raise ShaderError(f"{file}: line 1 must be the #version directive")
            out.append(lines[0])
            if stage:
                out.append(f"#define {stage}")
            first = 1
        out.append(f"#line {first + 1} {index}")
        for number, line in enumerate(lines[first:], start=first + 1):
            inc = _INCLUDE.match(line)
            if inc:
                expand(_resolve(inc.group(1), file))
                out.append(f"#line {number + 1} {index}")
                continue
            dm = _DEFINE.match(line)
            if dm and dm.group(2) in overrides:
                used.add(dm.group(2))
                line = f"{dm.group(1)}{dm.group(2)} {overrides[dm.group(2)]}"
            out.append(line)

    expand(root)
    unknown = set(overrides) - used
    if unknown:
        raise ShaderError(f"{root.name}: no #define for {', '.join(sorted(unknown))} (can only override defined names)")
    return "\n".join(out) + "\n", files


_DRIVER_LINE = re.compile(r"\b(\d+)(?::|\()(\d+)\)?")


def _map_errors(message: str, files: list[Path]) -> str:
    """Rewrite '0:12(3)' (Mesa) or '0(12)' (NVIDIA) as 'file.glsl:12'."""

    def repl(m: re.Match) -> str:
        i = int(m.group(1))
        return f"{files[i].name}:{m.group(2)}" if i < len(files) else m.group(0)

    return "\n".join(_DRIVER_LINE.sub(repl, line, count=1) for line in message.splitlines())


class ProgramCache:
    """Compiles ``.glsl`` programs once per (paths, defines) for one moderngl context."""

    def __init__(self, gl: moderngl.Context):
        self.gl = gl
        self._programs: dict[tuple, moderngl.Program | moderngl.ComputeShader] = {}

    def __len__(self) -> int:
        return len(self._programs)

    def get(
        self, path: str | Path, varyings: tuple[str, ...] = (), **defines: Any
    ) -> moderngl.Program | moderngl.ComputeShader:
        """The program in ``path`` (relative to ``illusio/shaders`` or absolute) with ``defines``;
        ``varyings``: vertex outputs to capture by transform feedback (checks of a vertex stage)."""
        resolved = _resolve(str(path), None) if not Path(path).is_absolute() else Path(path).resolve()
        key = (resolved, tuple(sorted((k, _format_define(v)) for k, v in defines.items())), tuple(varyings))
        program = self._programs.get(key)
        if program is None:
            program = self._compile(resolved, defines, tuple(varyings))
            self._programs[key] = program
        return program

    def _compile(self, path: Path, defines: dict[str, Any], varyings: tuple[str, ...] = ()):
        text, _ = preprocess(path, defines)  # stages may be named in included files only
        stages = [s for s in STAGES if re.search(rf"\b{s}\b", text)]
        if not stages:
            raise ShaderError(f"{path}: names none of {', '.join(STAGES)}")
        sources, files = {}, []
        for stage in stages:
            sources[stage], files = preprocess(path, defines, stage)
        try:
            if "COMPUTE_SHADER" in sources:
                return self.gl.compute_shader(sources["COMPUTE_SHADER"])
            if varyings:  # vertex stage alone, its outputs captured
                return self.gl.program(vertex_shader=sources["VERTEX_SHADER"], varyings=varyings)
            return self.gl.program(**{_STAGE_ARGS[s]: src for s, src in sources.items()})
        except moderngl.Error as exc:
            raise ShaderError(f"{path.name}: GLSL compile/link failed:\n{_map_errors(str(exc), files)}") from None
