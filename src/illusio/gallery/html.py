"""Write the gallery page: a static index.html next to the images (relative links only)."""

from __future__ import annotations

import dataclasses
import html
import json
import shlex
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..core.images import atomic_output
from ..core.options import option_words

__all__ = ["Item", "Section", "Table", "write_gallery"]


@dataclass
class Item:
    """One image or video (.mp4, .webm: shown as a looping video): its path relative to the gallery
    folder, a caption, optional details, the paper figure it answers and the command that makes it
    again.

    ``params``: the Params instance that made the image, if one did: its fields that differ from the
    defaults are written as options at the end of ``command`` (the last command where ``&&`` chains
    several), so the caption cannot drift from the image. ``derived``: dotted fields the command's own
    options set instead (``--focus-object`` sets the focus distance), left out of the words."""

    image: str
    caption: str
    details: str = ""
    figure: str = ""
    command: str = ""
    files: tuple[str, ...] = ()  # other files it comes with (a camera path), linked
    params: Any = None
    derived: tuple[str, ...] = ()

    @property
    def command_line(self) -> str:
        """``command`` with the options that make ``params`` appended."""
        if self.params is None or not self.command:
            return self.command
        return " ".join([self.command, *map(shlex.quote, option_words(self.params, self.derived))])

    def record(self) -> dict:
        """The item as data (``gallery.json``): image, command line, and the Params that made it."""
        out: dict[str, Any] = {"image": self.image, "command": self.command_line}
        if self.params is not None:
            cls = type(self.params)
            out["params"] = {
                "class": f"{cls.__module__}:{cls.__qualname__}",
                "values": dataclasses.asdict(self.params),
                "derived": list(self.derived),
            }
        return out


@dataclass
class Table:
    """Scores or timings as a table (from the same run as the images): a caption, the header row and
    the rows (cells as text)."""

    caption: str
    header: list[str]
    rows: list[list[str]]


@dataclass
class Section:
    title: str
    text: str = ""
    items: list[Item] = field(default_factory=list)
    tables: list[Table] = field(default_factory=list)


_STYLE = """
body { font-family: system-ui, sans-serif; margin: 2em auto; max-width: 1400px; background: #111; color: #ddd; }
h1 { font-weight: 600; } h2 { border-bottom: 1px solid #444; padding-bottom: .3em; margin-top: 2em; }
.grid { display: grid; grid-template-columns: repeat(auto-fill, minmax(420px, 1fr)); gap: 1.2em; }
figure { margin: 0; background: #1b1b1b; padding: .6em; border-radius: 6px; }
figure img, figure video { width: 100%; display: block; image-rendering: auto; }
.broken { outline: 3px solid #c33; }
figcaption { margin-top: .4em; } .details { color: #999; font-size: .85em; }
code { color: #9cf; font-size: .85em; } table { border-collapse: collapse; margin: 1em 0; }
td, th { border: 1px solid #444; padding: .25em .6em; text-align: right; } th { background: #222; }
td:first-child, th:first-child { text-align: left; } caption { caption-side: top; text-align: left; color: #bbb; }
"""


VIDEO_SUFFIXES = (".mp4", ".webm")

# After loading, every image and video is checked: one that did not load is outlined in red and
# reported on the console, and <body> records the counts (data-media, data-media-ok) so that a
# headless browser can tell whether the page is whole.
_CHECK = """
(function () {
  const media = Array.from(document.querySelectorAll('img, video'));
  let pending = media.length, ok = 0;
  function done(el, good) {
    if (el.dataset.checked) return;
    el.dataset.checked = good ? 'ok' : 'broken';
    if (good) ok++; else { el.classList.add('broken');
    console.error('illusio gallery: cannot load ' + el.getAttribute('src')); }
    if (--pending === 0) { document.body.dataset.mediaOk = ok; document.body.dataset.media = media.length; }
  }
  for (const el of media) {
    if (el.tagName === 'IMG') {
      if (el.complete) done(el, el.naturalWidth > 0);
      else { el.addEventListener('load', () => done(el, el.naturalWidth > 0));
      el.addEventListener('error', () => done(el, false)); }
    } else {
      if (el.readyState >= 1) done(el, el.videoWidth > 0);
      else { el.addEventListener('loadedmetadata', () => done(el, el.videoWidth > 0));
      el.addEventListener('error', () => done(el, false)); }
    }
  }
  if (media.length === 0) { document.body.dataset.mediaOk = 0; document.body.dataset.media = 0; }
})();
"""


def write_gallery(out_dir: str | Path, title: str, sections: list[Section], footer: str = "") -> Path:
    """Write ``out_dir/index.html`` and ``out_dir/gallery.json`` (every item as data: its image, its
    command and the Params that made it) atomically and return the page's path."""
    out = Path(out_dir)
    parts = [
        f"<!doctype html><html><head><meta charset='utf-8'><title>{html.escape(title)}</title>",
        f"<style>{_STYLE}</style></head><body><h1>{html.escape(title)}</h1>",
    ]
    for s in sections:
        parts.append(f"<h2>{html.escape(s.title)}</h2>")
        if s.text:
            parts.append(f"<p>{html.escape(s.text)}</p>")
        for t in s.tables:
            head = "".join(f"<th>{html.escape(c)}</th>" for c in t.header)
            body = "".join("<tr>" + "".join(f"<td>{html.escape(c)}</td>" for c in row) + "</tr>" for row in t.rows)
            parts.append(f"<table><caption>{html.escape(t.caption)}</caption><tr>{head}</tr>{body}</table>")
        parts.append("<div class='grid'>")
        for it in s.items:
            src = html.escape(it.image, quote=True)
            if Path(it.image).suffix.lower() in VIDEO_SUFFIXES:
                media = f"<video src='{src}' controls muted loop autoplay playsinline preload='auto'></video>"
            else:
                media = f"<a href='{src}'><img src='{src}' alt='{html.escape(it.caption, quote=True)}'></a>"
            parts.append(
                f"<figure>{media}"
                f"<figcaption>{html.escape(it.caption)}"
                + (f" <span class='details'>({html.escape(it.figure)})</span>" if it.figure else "")
                + (f"<div class='details'>{html.escape(it.details)}</div>" if it.details else "")
                + (f"<div><code>{html.escape(it.command_line)}</code></div>" if it.command else "")
                + (
                    "".join(
                        f"<div class='details'><a href='{html.escape(f, quote=True)}'>{html.escape(f)}</a></div>"
                        for f in it.files
                    )
                )
                + "</figcaption></figure>"
            )
        parts.append("</div>")
    if footer:
        parts.append(f"<p class='details'>{html.escape(footer)}</p>")
    parts.append(f"<script>{_CHECK}</script></body></html>\n")
    records = [it.record() for s in sections for it in s.items]
    with atomic_output(out / "gallery.json") as tmp:
        tmp.write_text(json.dumps(records, indent=1, default=repr))
    path = out / "index.html"
    with atomic_output(path) as tmp:
        tmp.write_text("\n".join(parts))
    return path
