"""One progress bar for long runs (rich), a no-op when disabled."""

from __future__ import annotations


class ProgressBar:
    """``ProgressBar(total, label, enabled, transient, unit)``: ``update(done,
    status)``, ``advance()``, ``close()``; nothing is drawn when disabled or
    total is 0.  With ``unit`` ("steps") the bar shows the rate in units per
    second; ``status`` is a short text shown after it (a time stepper's
    largest certificate error so far)."""

    def __init__(self, total: int, label: str, enabled: bool = True, transient: bool = False,
                 unit: str | None = None):
        self._p = None
        if enabled and total:
            from rich.progress import (BarColumn, MofNCompleteColumn, Progress, ProgressColumn,
                                       TextColumn, TimeRemainingColumn)
            from rich.text import Text

            class _Rate(ProgressColumn):
                def render(self, task):
                    return Text(f"{task.speed:,.0f} {unit}/s" if task.speed else "")

            columns = [TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn()]
            if unit:
                columns.append(_Rate())
            columns += [TimeRemainingColumn(), TextColumn("{task.fields[status]}")]
            self._p = Progress(*columns, transient=transient)
            self._p.start()
            self._task = self._p.add_task(label, total=total, status="")

    def update(self, done: int, status: str | None = None) -> None:
        if self._p is not None:
            if status is None:
                self._p.update(self._task, completed=done)
            else:
                self._p.update(self._task, completed=done, status=status)

    def advance(self) -> None:
        if self._p is not None:
            self._p.advance(self._task)

    def close(self) -> None:
        if self._p is not None:
            self._p.stop()


class StepReporter:
    """What a time stepper does after each step and at its end: the progress
    bar (every 1 % of the steps, with the largest certificate error so far)
    and the checkpoints (``checkpoint(partial(n))`` every
    ``checkpoint_seconds``, and the final result)."""

    def __init__(self, steps: int, label: str, progress: bool, checkpoint=None,
                 checkpoint_seconds: float = 5.0):
        import time

        self._clock = time.perf_counter
        self.steps = steps
        self.bar = ProgressBar(steps, label, progress, transient=True, unit="steps")
        self.checkpoint, self.every = checkpoint, checkpoint_seconds
        self._last = self._clock()

    def after(self, n: int, errors, partial) -> None:
        """After step n: ``errors`` the per-step certificate errors (index 1..n
        filled), ``partial(n)`` the result so far (called only to checkpoint)."""
        if n % max(1, self.steps // 100) == 0:
            import numpy as np

            self.bar.update(n, f"worst certificate {np.max(errors[1:n + 1], initial=0.0):.1e}")
        if self.checkpoint is not None and self._clock() - self._last >= self.every:
            self.checkpoint(partial(n))
            self._last = self._clock()

    def finish(self, result):
        self.bar.close()
        if self.checkpoint is not None:
            self.checkpoint(result)
        return result
