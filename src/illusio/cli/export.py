"""illusio export: a scene (built-in or loaded) written as glTF, for Blender and other tools."""

from __future__ import annotations

from pathlib import Path

import typer

from ..core.images import check_output_path
from .common import SCENE_HELP, on_turntable_option, resolve_scene, scene_inputs


def export(
    scene: str = typer.Argument(..., help=SCENE_HELP),
    output: Path = typer.Option(..., "-o", "--output", help="the glTF file to write: .glb (binary) or .gltf (JSON)"),
    on_turntable: bool = on_turntable_option(),
) -> None:
    """Write SCENE as glTF 2.0 with its materials, textures, lights and cameras (area lights as
    emissive panels, illusio's exact lamps and Phong terms in extras: read back the same)."""
    from ..scene.export import export_gltf

    out = check_output_path(output, scene_inputs(scene))
    sc = resolve_scene(scene, on_turntable)
    export_gltf(sc, out)
    typer.echo(f"wrote {out} ({len(sc.nodes)} nodes, {len(sc.lights)} lights, {len(sc.cameras)} cameras)")
