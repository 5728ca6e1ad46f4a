"""What the commands say and how they end: the consoles, one-line messages and the exit codes.

Results (tables, "wrote FILE") go to stdout; errors, warnings and notes go to
stderr, each as one line whatever the terminal's width (``soft_wrap``: the
terminal folds a long line, rich does not break it). Exit codes:

==== =====================================================
0    the work is done and every file is written
1    the run failed (or some sweep points did; or writing at the end failed,
     and the results were saved elsewhere)
2    bad input: nothing was run
130  interrupted (Ctrl-C), as a shell reports it
==== =====================================================

A reader that goes away (``collisionkit edmd ... | head -3``) stops what
the command shows, not its work: the files and the summary are still
written (:class:`_PipeSafeConsole`).
"""

from __future__ import annotations

import os
import sys

import typer
from rich.console import Console
from rich.markup import escape

# messages and paths never wrap (a script, or a test, reads them whole), and text such as "Ar:0.9,N2:0.1" or a
# path with ":x:" in it is printed as written, never as an emoji
class _PipeSafeConsole(Console):
    """A console whose reader may go away: on a broken pipe its stream goes to /dev/null and the command goes on.

    rich's own answer ends the process with exit code 1: ``collisionkit edmd ... | head -3`` stopped with no
    message and no summary written, at the table's first line after head left.
    """

    def on_broken_pipe(self) -> None:
        stream = sys.stderr if self.stderr else sys.stdout
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, stream.fileno())  # the stream stays open for whatever writes next, and for its flush at exit
        os.close(devnull)


console = _PipeSafeConsole(soft_wrap=True, emoji=False)
error_console = _PipeSafeConsole(stderr=True, soft_wrap=True, emoji=False)

OK_EXIT_CODE = 0
RUN_FAILED_EXIT_CODE = 1
BAD_INPUT_EXIT_CODE = 2
INTERRUPTED_EXIT_CODE = 130  # as a shell reports a command stopped by Ctrl-C (128 + SIGINT)


def say(message: str) -> None:
    """Print ``message`` on stdout on one line (a path in it stays whole to copy), markup escaped.

    Examples
    --------
    >>> say("wrote demo-output/summary.json")
    wrote demo-output/summary.json
    """
    console.print(escape(message), soft_wrap=True)


def error(message: str) -> None:
    """Print ``message`` as an error on stderr, on one line, markup escaped.

    Examples
    --------
    >>> error("writing failed: [Errno 28] No space left on device")
    """
    error_console.print(f"[bold red]error:[/] {escape(message)}", soft_wrap=True)


def warn(message: str) -> None:
    """Print ``message`` as a warning on stderr (the table and files on stdout stay clean), markup escaped.

    Examples
    --------
    >>> warn("E/N = 0 Td stopped at the collision budget [5e8]")
    """
    error_console.print(f"[bold yellow]warning:[/] {escape(message)}", soft_wrap=True)


def note(message: str) -> None:
    """Print ``message`` as a note on stderr (what the run does: its seed, a rounded frame interval).

    Examples
    --------
    >>> note("seed 2026 (--seed 2026 repeats this run)")
    """
    error_console.print(f"[bold]note:[/] {escape(message)}", soft_wrap=True)


def fail(message: str) -> typer.Exit:
    """Print ``message`` as an input error and return the exit to raise (code 2).

    The message is printed as it is: brackets in it (``collisionkit[plot]``,
    a list the user gave) are not rich markup.

    Examples
    --------
    >>> stop = fail("--particles must be >= 2; got 1")
    >>> stop.exit_code
    2
    """
    error(message)
    return typer.Exit(BAD_INPUT_EXIT_CODE)


def run_failed(message: str) -> typer.Exit:
    """Print ``message`` as the reason a run failed and return the exit to raise (code 1).

    Examples
    --------
    >>> run_failed("the system stopped colliding during equilibration").exit_code
    1
    """
    error(message)
    return typer.Exit(RUN_FAILED_EXIT_CODE)
