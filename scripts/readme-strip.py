"""README's strip of pictures, made from a demo's output: one picture per system, side by side.

.venv/bin/illusio demo --out demo-out && .venv/bin/python scripts/readme-strip.py demo-out
"""

import sys
from pathlib import Path

from PIL import Image

#: one picture of each system, in README's order of the systems: (file, the panels of it kept as
#: (first, last) fractions of its width: the ibr and relight pictures are rows of panels)
PICTURES = (
    ("sis/tv-tv.png", (0, 1)),
    ("dof/museum-gather.png", (0, 1)),
    ("lines/knot-apparent-ridges.png", (0, 1)),
    ("ibr/office-middle.png", (0, 1 / 3)),  # the view rendered from references
    ("relight/office-back-lamps-off.png", (0, 2 / 5)),  # the photograph, then relit
)
HEIGHT, GAP = 200, 6


def strip(demo: Path, out: Path) -> None:
    tiles = []
    for name, (first, last) in PICTURES:
        image = Image.open(demo / name).convert("RGB")
        image = image.crop((round(first * image.width), 0, round(last * image.width), image.height))
        tiles.append(image.resize((round(image.width * HEIGHT / image.height), HEIGHT), Image.LANCZOS))
    width = sum(t.width for t in tiles) + GAP * (len(tiles) - 1)
    canvas = Image.new("RGB", (width, HEIGHT), "white")
    x = 0
    for tile in tiles:
        canvas.paste(tile, (x, 0))
        x += tile.width + GAP
    canvas.save(out, quality=85, optimize=True)


if __name__ == "__main__":
    strip(Path(sys.argv[1]), Path(__file__).resolve().parents[1] / "docs" / "_static" / "strip.jpg")
