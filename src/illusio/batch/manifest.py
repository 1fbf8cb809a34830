"""The manifest: one JSON line per finished task in OUT/manifest.jsonl (task key, output, SHA-256 of
the output's bytes, seconds, worker, time). A rerun skips a task whose line is there and whose output
still has that hash; a line cut by a crash is ignored. Only the coordinating process writes it."""

from __future__ import annotations

import hashlib
import json
import os
from datetime import datetime, timezone
from pathlib import Path

__all__ = ["Manifest", "file_hash"]


def file_hash(path: Path) -> str:
    """SHA-256 of a file's bytes; of a folder, of its files' relative paths and bytes in order."""
    path = Path(path)
    h = hashlib.sha256()
    files = sorted(p for p in path.rglob("*") if p.is_file()) if path.is_dir() else [path]
    for p in files:
        if path.is_dir():
            h.update(str(p.relative_to(path)).encode() + b"\0")
        with open(p, "rb") as f:
            for block in iter(lambda: f.read(1 << 20), b""):
                h.update(block)
    return h.hexdigest()


class Manifest:
    def __init__(self, out_dir: Path):
        self.path = Path(out_dir) / "manifest.jsonl"
        self.entries: dict[str, dict] = {}
        if self.path.exists():
            for line in self.path.read_text().splitlines():
                try:
                    row = json.loads(line)
                    self.entries[row["task"]] = row
                except (ValueError, KeyError, TypeError):
                    continue  # a line cut short by a crash: that task runs again

    def done(self, key: str, output: Path) -> bool:
        """Is the task finished: recorded, its output present with the recorded bytes?"""
        row = self.entries.get(key)
        return row is not None and output.exists() and file_hash(output) == row["sha256"]

    def record(self, key: str, output: Path, rel: str, seconds: float, worker: str) -> None:
        row = {
            "task": key,
            "output": rel,
            "sha256": file_hash(output),
            "seconds": round(seconds, 4),
            "worker": worker,
            "time": datetime.now(timezone.utc).isoformat(timespec="seconds"),
        }
        self.entries[key] = row
        self.path.parent.mkdir(parents=True, exist_ok=True)
        with open(self.path, "a") as f:
            f.write(json.dumps(row) + "\n")
            f.flush()
            os.fsync(f.fileno())
