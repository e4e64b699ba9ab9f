"""What the command line shows of long work on standard error: rich progress on a terminal,
plain lines on a pipe or in a log."""

from __future__ import annotations

import sys
import time
from pathlib import Path

import typer


class Progress:
    """Progress of long work: a rich bar on a terminal; on a pipe or a log, a plain line at
    every `LOG_STEP` of the work (nothing for work that ends within `LOG_AFTER` seconds)."""

    def __init__(self, label: str):
        self.label, self.bar, self.task = label, None, None
        self.start, self.logged = time.monotonic(), -1.0

    def __enter__(self):
        if sys.stderr.isatty():
            from rich.progress import Progress

            self.bar = Progress(transient=True)
            self.bar.start()
            self.task = self.bar.add_task(self.label, total=None)
        return self.update

    def update(self, done: int, total: int) -> None:
        if self.bar is not None:
            self.bar.update(self.task, completed=done, total=total)
            return
        share = done / max(total, 1)
        if time.monotonic() - self.start >= LOG_AFTER and share - self.logged >= LOG_STEP:
            self.logged = share
            typer.echo(f"{self.label}: {done}/{total}", err=True)

    def __exit__(self, *exc) -> None:
        if self.bar is not None:
            self.bar.stop()


#: Plain progress lines: one per this share of the work, once it has run this many seconds.
LOG_STEP = 0.1
LOG_AFTER = 2.0
#: Files at least this large (bytes) say that they are being read (a spinner or a line).
BIG_FILE = 20 * 2**20


class Reading:
    """'reading FILE (size)' while a big file is read: a spinner on a terminal, else a line."""

    def __init__(self, path: Path):
        self.path, self.status = path, None
        size = path.stat().st_size if path.is_file() else 0
        self.text = f"reading {path} ({size / 2**20:.0f} MB)" if size >= BIG_FILE else None

    def __enter__(self):
        if self.text and sys.stderr.isatty():
            from rich.console import Console

            self.status = Console(stderr=True).status(self.text)
            self.status.start()
        elif self.text:
            typer.echo(self.text, err=True)
        return self

    def __exit__(self, *exc) -> None:
        if self.status is not None:
            self.status.stop()
