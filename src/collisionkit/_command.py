"""The ``collisionkit`` script: names the extra to install when the command line's packages are missing.

The core (numpy, numba, scipy) installs without them; importing
:mod:`collisionkit.cli` would then fail with a bare ``ModuleNotFoundError``.
A Ctrl-C while the command line loads (``import collisionkit`` itself
loads nothing heavy) is one line and exit code 130, not a traceback.
"""

from __future__ import annotations

import importlib.util
import sys

COMMAND_LINE_PACKAGES = ("typer", "rich", "pydantic")
MISSING_EXIT_CODE = 2
INTERRUPTED_EXIT_CODE = 130  # 128 + SIGINT, as the commands exit when interrupted


def main(argv: list[str] | None = None) -> None:
    """Run the command line, or say which extra to install and exit with 2."""
    missing = [name for name in COMMAND_LINE_PACKAGES if importlib.util.find_spec(name) is None]
    if missing:
        sys.stderr.write(
            f"collisionkit: the command line needs {', '.join(missing)}, not installed: "
            "pip install 'collisionkit[cli]' (or 'collisionkit[all]' for plots and trajectories too)\n"
        )
        raise SystemExit(MISSING_EXIT_CODE)
    try:  # numpy, numba, scipy, typer and rich load here, for a second or two
        from .cli import main as command_line
    except KeyboardInterrupt:
        sys.stderr.write("collisionkit: interrupted while starting\n")
        raise SystemExit(INTERRUPTED_EXIT_CODE) from None
    command_line(argv)
