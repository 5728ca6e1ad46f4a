"""The ``collisionkit`` group of commands: one-line usage errors, run failures without tracebacks, ``--version``.

click and typer print a usage error (an unknown option, ``--particles abc``)
as a framed panel under the usage line; here it is one line on stderr, as
every other input error, naming the command's ``--help``, with exit code 2.
An ``OSError`` that escapes a command (a disk that fills during the run) is
one line and exit code 1, not a traceback.
"""

from __future__ import annotations

import errno
import sys
from typing import Any

import typer
import typer.core
from typer.core import TyperGroup

from ._messages import BAD_INPUT_EXIT_CODE, RUN_FAILED_EXIT_CODE, console, error

# the click that typer runs on: typer >= 0.25 carries its own copy, whose exceptions are not the click package's
click = getattr(typer.core, "_click", None) or __import__("click")


def _usage_message(failure) -> str:
    """A usage error as one line, pointing at the command's --help.

    Examples
    --------
    >>> _usage_message(click.exceptions.UsageError("No such option: --particle"))
    'no such option: --particle'
    """
    message = " ".join(failure.format_message().split())
    message = message[:1].lower() + message[1:]
    ctx = getattr(failure, "ctx", None)
    if ctx is not None:
        message += f" (see {ctx.command_path} --help)"
    return message


class CommandLine(TyperGroup):
    """The commands' group: errors before and after the work are one line each, with their exit codes.

    Examples
    --------
    >>> from typer.testing import CliRunner
    >>> from collisionkit.cli import app
    >>> result = CliRunner().invoke(app, ["edmd", "--particles", "many"])
    >>> result.exit_code, len(result.output.strip().splitlines())
    (2, 1)
    """

    def main(self, args=None, prog_name=None, complete_var=None, standalone_mode: bool = True, **extra: Any):
        """Run the command line (as :meth:`click.Group.main`) with one-line errors."""
        if not standalone_mode:
            return super().main(args, prog_name, complete_var, standalone_mode=False, **extra)
        try:
            code = super().main(args, prog_name, complete_var, standalone_mode=False, **extra)
        except click.exceptions.NoArgsIsHelpError as failure:  # typer printed the help while making it
            sys.exit(failure.exit_code)
        except click.exceptions.ClickException as failure:
            error(_usage_message(failure))
            sys.exit(failure.exit_code if isinstance(failure, click.exceptions.UsageError) else BAD_INPUT_EXIT_CODE)
        except typer.Abort:
            error("aborted")
            sys.exit(RUN_FAILED_EXIT_CODE)
        except ArithmeticError as failure:  # an input range no check foresaw: one line, not a traceback
            error(f"the run failed: a number left the floating-point range ({type(failure).__name__}: {failure}); "
                  "some input is far outside the range this command handles (very large or small values): bring "
                  "it nearer 1 in the units used, and please report the command line")
            sys.exit(RUN_FAILED_EXIT_CODE)
        except OSError as failure:
            if failure.errno == errno.EPIPE:  # the reader of our output went away (``| head``): nothing to say
                sys.exit(RUN_FAILED_EXIT_CODE)
            error(f"the run failed: {failure}")
            sys.exit(RUN_FAILED_EXIT_CODE)
        sys.exit(code if isinstance(code, int) else 0)


def show_version(value: bool) -> None:
    """Print ``collisionkit VERSION`` and stop (the ``--version`` option's callback).

    Examples
    --------
    >>> show_version(False)  # not asked for: nothing happens
    """
    if not value:
        return
    from .. import __version__

    console.print(f"collisionkit {__version__}", markup=False, highlight=False)
    raise typer.Exit()
