"""Progress bars on stderr: one per stage (solve, plan, render, scenes, variants), with the
rate and the time left."""

from __future__ import annotations

from rich.console import Console
from rich.progress import (
    BarColumn,
    MofNCompleteColumn,
    Progress,
    ProgressColumn,
    TaskID,
    TextColumn,
    TimeRemainingColumn,
)
from rich.text import Text

from armanim.cli.app import err


class Bars:
    """A rich progress bar per stage, called as the API's ``progress`` callbacks are.

    Draws only when ``enabled`` (the commands enable it on a terminal, without --quiet).
    """

    def __init__(self, enabled: bool, console: Console | None = None):
        self.enabled = enabled
        self.console = console or err
        self.progress: Progress | None = None
        self.tasks: dict[str, TaskID] = {}
        self.done: dict[str, int] = {}

    def __enter__(self):
        if self.enabled:
            self.progress = Progress(
                TextColumn("{task.description}"),
                BarColumn(),
                MofNCompleteColumn(),
                RateColumn(),
                TimeRemainingColumn(),
                console=self.console,
                transient=True,
            )
            self.progress.__enter__()
        return self

    def __exit__(self, *exc):
        if self.progress is not None:
            self.progress.__exit__(*exc)

    def __call__(self, stage: str, done: int, total: int, running: tuple[str, ...] = ()) -> None:
        if self.progress is None:
            return
        stage_label = LABELS.get(stage, stage)
        if stage not in self.tasks:
            self.tasks[stage] = self.progress.add_task(f"{stage_label:>6}", total=total)
        task = self.tasks[stage]
        if done < self.done.get(stage, 0):  # the stage starts over (the next plan): its rate and time left too
            self.progress.reset(task, total=total)
        self.done[stage] = done
        label = f"{stage_label:>6} " + ", ".join(running) if running else f"{stage_label:>6}"
        self.progress.update(task, completed=done, total=max(total, done), description=label)


LABELS = {"solve": "solver steps", "plan": "plan search", "path": "path (per mille)", "warm": "solves"}
"""What each stage counts, as its bar says: the solver's steps at the scene's own rate are not the
run's frames (notes-arm: 338 steps, then 135 frames on the clock), a plan counts its search's
iterations, a path goal its thousandths."""


def bars(quiet: bool) -> Bars:
    """The bars of a command: drawn on a terminal unless ``--quiet``."""
    return Bars(enabled=not quiet and err.is_terminal)


class RateColumn(ProgressColumn):
    """Items per second of a progress task ("--" until rich has measured a speed)."""

    def render(self, task) -> Text:
        speed = task.finished_speed or task.speed
        return Text(f"{speed:7.1f}/s" if speed else "     --/s", style="progress.data.speed")
