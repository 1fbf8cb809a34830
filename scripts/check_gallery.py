#!/usr/bin/env python3
"""Check a demo page (demo-out/index.html) the way a reader would: every section has at least one
image or video that exists on disk, and none says that something it needed was missing.

Usage: check_gallery.py PAGE [--sections N]
Prints one line a section (its title, how many media, what is wrong), then one a fault; exits 1 on any.
Standard library only: it runs with the host's python3, outside the virtual environment."""

from __future__ import annotations

import argparse
import html.parser
import sys
from pathlib import Path

#: words a section's text uses when it could not show its part (the relighting section without
#: Mitsuba said "Mitsuba is not installed ...: nothing to show")
MISSING = ("not installed", "nothing to show", "no reference")


class _Page(html.parser.HTMLParser):
    """Sections as [title, text, media sources]; a section starts at each <h2>."""

    def __init__(self) -> None:
        super().__init__()
        self.sections: list[list] = []
        self._in_h2 = False

    def handle_starttag(self, tag, attrs):
        if tag == "h2":
            self._in_h2 = True
            self.sections.append(["", "", []])
        elif tag in ("img", "video") and self.sections:
            src = dict(attrs).get("src")
            if src:
                self.sections[-1][2].append(src)

    def handle_endtag(self, tag):
        if tag == "h2":
            self._in_h2 = False

    def handle_data(self, data):
        if not self.sections:
            return
        self.sections[-1][0 if self._in_h2 else 1] += data


def check(page: Path, sections: int | None) -> list[str]:
    parser = _Page()
    parser.feed(page.read_text(encoding="utf-8"))
    faults = []
    for title, text, media in parser.sections:
        missing_files = [m for m in media if not (page.parent / m).is_file()]
        said = [w for w in MISSING if w in text.lower()]
        wrong = []
        if not media:
            wrong.append("no image")
        if missing_files:
            wrong.append(f"{len(missing_files)} missing file(s), e.g. {missing_files[0]}")
        if said:
            wrong.append(f"says '{said[0]}'")
        print(f"  {title.strip()}: {len(media)} media" + (f" — {'; '.join(wrong)}" if wrong else ""))
        faults += [f"{title.strip()}: {w}" for w in wrong]
    if sections is not None and len(parser.sections) != sections:
        faults.append(f"{len(parser.sections)} sections, expected {sections}")
    return faults


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("page", type=Path)
    ap.add_argument("--sections", type=int, default=None, help="how many sections the page must have")
    args = ap.parse_args()
    if not args.page.is_file():
        print(f"check_gallery: {args.page}: no such page", file=sys.stderr)
        return 1
    faults = check(args.page, args.sections)
    for f in faults:
        print(f"check_gallery: {f}", flush=True)
    return 1 if faults else 0


if __name__ == "__main__":
    sys.exit(main())
