"""One progress bar for long runs (rich), a no-op when disabled."""

from __future__ import annotations


class ProgressBar:
    """``ProgressBar(total, label, enabled, transient)``: ``update(done)``,
    ``advance()``, ``close()``; nothing is drawn when disabled or total is 0."""

    def __init__(self, total: int, label: str, enabled: bool = True, transient: bool = False):
        self._p = None
        if enabled and total:
            from rich.progress import Progress

            self._p = Progress(transient=transient)
            self._p.start()
            self._task = self._p.add_task(label, total=total)

    def update(self, done: int) -> None:
        if self._p is not None:
            self._p.update(self._task, completed=done)

    def advance(self) -> None:
        if self._p is not None:
            self._p.advance(self._task)

    def close(self) -> None:
        if self._p is not None:
            self._p.stop()
