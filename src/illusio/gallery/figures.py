"""Matplotlib for the gallery's plots: the headless backend, and a figure written atomically."""

from __future__ import annotations

from pathlib import Path

from ..core.images import atomic_output

__all__ = ["pyplot", "save_figure"]


def pyplot():
    """matplotlib.pyplot on the Agg backend (no display needed)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def save_figure(fig, path: Path, tight: bool = False) -> None:
    """Write ``fig`` as a PNG at ``path`` (atomically) and close it. ``tight``: crop to the drawn
    content (bbox_inches="tight") rather than laying the axes out in the figure."""
    import matplotlib.pyplot as plt

    if not tight:
        fig.tight_layout()
    with atomic_output(path) as tmp:
        fig.savefig(tmp, format="png", **({"bbox_inches": "tight"} if tight else {}))
    plt.close(fig)
