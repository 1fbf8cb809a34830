from pathlib import Path

import typer

from illusio.cli.params_options import params_options

from .params import ToyParams


@params_options(params=ToyParams)
def toy(
    offset: str = typer.Argument("0.5"),
    output: Path = typer.Option(..., "-o", "--output"),
    size: str = typer.Option("32x16", "--size"),
    *,
    params: ToyParams,
) -> None:
    """Write the toy's gradient."""
    from illusio.cli.common import parse_size
    from illusio.core.context import default_context
    from illusio.core.images import write_image
    from illusio.core.renderer import Frame

    from .renderer import ToyRenderer

    renderer = default_context().kept(ToyRenderer)
    renderer.prepare(float(offset))
    write_image(output, renderer.render(Frame(None, parse_size(size)), params))
    typer.echo(f"wrote {output}")
