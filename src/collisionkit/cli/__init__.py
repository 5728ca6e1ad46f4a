"""The ``collisionkit`` command line (typer + rich)."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Annotated, ClassVar

import typer
from pydantic import Field

from .._io import atomic_write_json

from ._app import CommandLine, show_version
from ._common import (
    Deliveries, Options, OverwriteOption, load_options, note, print_table, progress_bar, require_plotting, say,
)
from ._warmup import warm_up

app = typer.Typer(
    name="collisionkit",
    help="Exact binary-collision physics: two-body collisions and more. Exit codes: 0 done, 1 the run failed "
         "(results that could not be written are saved elsewhere, and the message says where), 2 bad input "
         "(nothing was run), 130 interrupted.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    cls=CommandLine,
)

ConfigOption = Annotated[Path | None, typer.Option("--config", help="TOML file with these options (command line wins).")]


@app.callback()
def _root(
    version: Annotated[bool, typer.Option("--version", callback=show_version, is_eager=True,
                                          help="Print the version of collisionkit and exit.")] = False,
) -> None:
    """collisionkit: exact binary-collision physics."""


SummaryOption = Annotated[Path | None, typer.Option("--summary", help="Write the results as JSON to this file.")]


class DemoOptions(Options):
    """Options of ``collisionkit demo`` (validated; TOML keys may use dashes).

    Examples
    --------
    >>> from collisionkit.cli import DemoOptions
    >>> DemoOptions.model_validate({"pairs": 5000, "out": "here"}).pairs
    5000
    """

    out: Path = Path("demo-output")
    pairs: int = Field(default=200_000, ge=1_000, le=50_000_000)
    seed: int = Field(default=2026, ge=0)
    plots: bool = True
    summary: Path | None = None

    output_folders: ClassVar[tuple[str, ...]] = ("out",)


@app.command()
def demo(
    out: Annotated[Path | None, typer.Option(help="Folder for the summary and plots.  \\[default: demo-output]")] = None,
    pairs: Annotated[int | None, typer.Option(help="Pairs per batch check (1000 to 5e7).  \\[default: 200000]")] = None,
    seed: Annotated[int | None, typer.Option(help="Random seed (>= 0).  \\[default: 2026]")] = None,
    plots: Annotated[bool | None, typer.Option("--plots/--no-plots", help="Write plots.  \\[default: plots]")] = None,
    summary: SummaryOption = None,
    config: ConfigOption = None,
    overwrite: OverwriteOption = None,
):
    """Run every capability at small size: a summary table, plots and summary.json.\f

    Examples
    --------
    >>> import tempfile
    >>> from typer.testing import CliRunner
    >>> from collisionkit.cli import app
    >>> result = CliRunner().invoke(app, ["demo", "--pairs", "2000", "--no-plots", "--out", tempfile.mkdtemp()])
    >>> result.exit_code
    0
    """
    options = load_options(DemoOptions, config, dict(out=out, pairs=pairs, seed=seed, plots=plots, summary=summary,
                                                     overwrite=overwrite))
    from . import _demo

    deliveries = Deliveries("demo")
    plotting = None
    if options.plots:
        require_plotting()
        import matplotlib

        matplotlib.use("Agg")
        from .. import plotting

        plotting = _demo.DeliveredPlots(plotting, deliveries)
    note(f"seed {options.seed} (--seed {options.seed} repeats this run)")
    warm_up(["core", "encounter", "edmd", "swarm", "slab"], always=["edmd"])  # the speeds time no compiling
    deliveries.write(f"the folder {options.out}", lambda: options.out.mkdir(parents=True, exist_ok=True))
    results = []
    section_list = _demo.sections()
    with progress_bar("demo", total=len(section_list)) as advance:
        for _, run in section_list:
            results.append(run(options.pairs, options.seed, options.out, plotting))
            advance()
    rows = [(result.name, *row) for result in results for row in result.rows]
    print_table("collisionkit demo", ("capability", "check", "value", "expected"), rows)
    combined = {"sections": {result.name: result.summary for result in results}, "seed": options.seed}
    combined["files"] = [str(path) for result in results for path in result.files if path in deliveries.files]
    deliveries.write(f"the summary {options.out / 'summary.json'}",
                     lambda: atomic_write_json(options.out / "summary.json", combined))
    for path in combined["files"]:
        say(f"wrote {path}")
    deliveries.finish(options.summary, combined)


def main(argv: list[str] | None = None) -> None:
    """Entry point of the ``collisionkit`` script.

    Examples
    --------
    >>> from collisionkit.cli import main
    >>> try:
    ...     main(["demo", "--pairs", "5"])  # below the allowed 1000: bad input
    ... except SystemExit as stop:
    ...     print("exit code", stop.code)
    exit code 2
    """
    app(args=argv if argv is not None else sys.argv[1:], prog_name="collisionkit")


from . import _encounter  # noqa: E402

_encounter.register(app)

from . import _star  # noqa: E402

_star.register(app)

from . import _edmd  # noqa: E402

_edmd.register(app)

from . import _sweep  # noqa: E402

_sweep.register(app)

from . import _transport  # noqa: E402

_transport.register(app)

from . import _slab  # noqa: E402

_slab.register(app)

from . import _boltzmann  # noqa: E402

_boltzmann.register(app)

from . import _track  # noqa: E402

_track.register(app)

from . import _animate  # noqa: E402

_animate.register(app)

from . import _gases  # noqa: E402

_gases.register(app)
