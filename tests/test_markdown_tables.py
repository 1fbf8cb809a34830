"""Every Markdown table of the repository's pages renders as written (issue 43): each row has as many
cells as its header, counted as GitHub counts them (a `|` splits a cell even inside a code span
unless it is escaped as `\\|`)."""

from __future__ import annotations

import re

import pytest

from tests.conftest import REPO

PAGES = sorted(
    p.relative_to(REPO).as_posix()
    for p in [REPO / "README.md", *(REPO / "docs").rglob("*.md"), *(REPO / "benchmarks").glob("*.md")]
)


def cells(row: str) -> int:
    body = row.strip()
    body = body[1:] if body.startswith("|") else body
    body = body[:-1] if body.endswith("|") and not body.endswith("\\|") else body
    return len(re.split(r"(?<!\\)\|", body))


def tables(text: str):
    """(first line number, rows) of each table: a header, a |---| line, then its rows."""
    lines = text.splitlines()
    k = 0
    while k < len(lines) - 1:
        if lines[k].lstrip().startswith("|") and re.fullmatch(
            r"\s*\|?\s*:?-+:?\s*(\|\s*:?-+:?\s*)*\|?\s*", lines[k + 1]
        ):
            start, rows = k, [lines[k]]
            k += 2
            while k < len(lines) and lines[k].lstrip().startswith("|"):
                rows.append(lines[k])
                k += 1
            yield start + 1, rows
        else:
            k += 1


def test_a_row_with_a_stray_pipe_is_found():
    text = "| a | b |\n|---|---|\n| `x | y` | z |\n"
    ((_, rows),) = tables(text)
    assert [cells(r) for r in rows] == [2, 3]


@pytest.mark.parametrize("page", PAGES)
def test_every_table_row_has_its_headers_cells(page):
    text = (REPO / page).read_text(encoding="utf-8")
    for line, rows in tables(text):
        expected = cells(rows[0])
        wrong = [(line + (2 if i else 0) + max(i - 1, 0), cells(r)) for i, r in enumerate(rows) if cells(r) != expected]
        assert not wrong, f"{page}: table at line {line} has {expected} columns; rows (line, cells): {wrong}"
