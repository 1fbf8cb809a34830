"""illusio info: the GL driver in use and the versions of illusio and its dependencies."""

from __future__ import annotations

import platform
from importlib import metadata

import typer

PACKAGES = (
    "illusio",
    "moderngl",
    "glcontext",
    "numpy",
    "trimesh",
    "pillow",
    "pypng",
    "imageio",
    "openexr",
    "typer",
    "rich",
    "pyyaml",
)


def info() -> None:
    """Print the OpenGL renderer and version, and package versions."""
    from ..core.context import Context

    typer.echo(f"python      {platform.python_version()} ({platform.system()} {platform.machine()})")
    for name in PACKAGES:
        try:
            version = metadata.version(name)
        except metadata.PackageNotFoundError:
            version = "not installed"
        typer.echo(f"{name:<11} {version}")
    ctx = Context()  # raises GLUnavailable with the install hint
    i = ctx.info()
    typer.echo(f"GL renderer {i['renderer']}")
    typer.echo(f"GL vendor   {i['vendor']}")
    typer.echo(f"GL version  {i['version']}")
    typer.echo(f"GL max tex  {i['max_texture_size']}")
