"""The ``collisionkit`` script: names the extra to install when the command line's packages are missing.

The core (numpy, numba, scipy) installs without them; importing
:mod:`collisionkit.cli` would then fail with a bare ``ModuleNotFoundError``.
"""

from __future__ import annotations

import importlib.util
import sys

COMMAND_LINE_PACKAGES = ("typer", "rich", "pydantic")
MISSING_EXIT_CODE = 2


def main(argv: list[str] | None = None) -> None:
    """Run the command line, or say which extra to install and exit with 2."""
    missing = [name for name in COMMAND_LINE_PACKAGES if importlib.util.find_spec(name) is None]
    if missing:
        sys.stderr.write(
            f"collisionkit: the command line needs {', '.join(missing)}, not installed: "
            "pip install 'collisionkit[cli]' (or 'collisionkit[all]' for plots and trajectories too)\n"
        )
        raise SystemExit(MISSING_EXIT_CODE)
    from .cli import main as command_line

    command_line(argv)
