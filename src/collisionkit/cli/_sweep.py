"""The ``sweep`` subcommand: run a study (parameter sweep with replicas) on a Dask cluster.

The study file names a subcommand, its fixed and varied options, the
replicas and a root seed (see :mod:`collisionkit.sweep`). By default the
points run on an embedded local cluster of ``--workers`` processes;
``--scheduler ADDRESS`` sends them to an existing Dask cluster instead.
"""

from __future__ import annotations

import contextlib
import importlib.util
import math
from pathlib import Path
from typing import Annotated, Any

import typer

from rich.markup import escape

from .._io import FileLockedError, write_csv
from ._common import (
    INTERRUPTED_EXIT_CODE, RUN_FAILED_EXIT_CODE, check_output_file, check_output_folder, error,
    error_console, fail, note, print_table, progress_bar, refuse_clashes, refuse_folder, refuse_to_replace, run_failed,
    say, warn, write_summary,
)
from ._files import rescue_path
from ._warmup import warm_up

FAILED_POINTS_EXIT_CODE = RUN_FAILED_EXIT_CODE
SHOWN_FAILURES = 10
CONNECT_TIMEOUT = "15s"


def _load(path: Path, out: Path, overwrite: bool):
    """The validated study, every point checked by its command's rules; any problem is an input error (exit 2)."""
    from .. import sweep as core

    refuse_folder(path, "STUDY.toml")
    try:
        study = core.load_study(path)
        core.check_command(study)
        core.check_folder(study, out, overwrite=overwrite)
    except (ValueError, TypeError) as error:
        raise fail(f"invalid study {path}: {error}") from None
    except OSError as error:
        raise fail(f"cannot read the study {path}: {error.strerror or error}") from None
    return study


def _resumed(checkpoint: Path):
    """The study saved in a sweep checkpoint and its folder (exit 2 if the file is not one)."""
    from .. import sweep as core
    from .._io import read_checkpoint

    refuse_folder(checkpoint, "--resume")
    try:
        saved = read_checkpoint(checkpoint, "sweep")
        study = core.study_from_dict(saved.parameters)
        core.check_command(study)
    except (ValueError, TypeError) as error:
        raise fail(f"cannot resume from {checkpoint}: {error}") from None
    return study, checkpoint.parent


def _check_executor(workers: int | None, scheduler: str | None) -> None:
    """Stop (exit 2) before any work if the cluster options do not go together or dask.distributed is missing."""
    if workers is not None and scheduler is not None:
        raise fail("--workers sets the size of the embedded cluster; it cannot be used with --scheduler")
    if workers is not None and workers < 1:
        raise fail(f"--workers must be >= 1; got {workers}")
    if importlib.util.find_spec("distributed") is None:
        raise fail("sweep runs on dask.distributed: pip install 'collisionkit[cluster]'")


@contextlib.contextmanager
def _executor(workers: int | None, scheduler: str | None):
    """A client of the given scheduler, or of an embedded cluster of ``workers`` processes."""
    from .. import sweep as core

    if scheduler is None:
        with core.local_client(workers) as client:
            yield client
        return
    try:
        with core.remote_client(scheduler, timeout=CONNECT_TIMEOUT) as client:
            yield client
    except ConnectionError as error:
        raise fail(str(error)) from None


def _format(value: float, error: float) -> str:
    if math.isnan(error):
        return f"{value:.6g}"
    return f"{value:.6g} ± {error:.2g}"


def _point_rows(results) -> list[tuple]:
    from .. import sweep as core

    study = results.study
    names = list(study.vary)
    means = {}
    if study.main is not None:
        means = {core.group_key(row, names): row for row in core.aggregate(results.table, study.main, names)}
    rows = []
    for parameters in core.expand(study):
        ok = sum(1 for row in results.table if row["status"] == "ok" and all(row[n] == v for n, v in parameters.items()))
        mean = means.get(core.group_key(parameters, names))
        shown = _format(mean["mean"], mean["error"]) if mean else "-"
        if mean and mean["disagree"]:
            shown += " (replicas disagree)"
        rows.append((*(parameters[name] for name in names), f"{ok}/{study.replicas}", shown))
    return rows


def _warn_unknown_main(results) -> None:
    """Warn if the study's main key is a number in no successful run's results (misspelled, or a list: its
    elements are ``name[0]`` ...), with the closest results' names."""
    import difflib

    main = results.study.main
    ok = [row for row in results.table if row["status"] == "ok"]
    if main is None or not ok or any(isinstance(row.get(main), (int, float)) for row in ok):
        return
    columns = [column for column in dict.fromkeys(key for row in ok for key in row)
               if isinstance(ok[0].get(column), (int, float))]  # (booleans too: their fraction)
    close = difflib.get_close_matches(main, columns, n=3, cutoff=0.6) or [
        column for column in columns if column.startswith(f"{main}[")][:3]
    hint = f"; did you mean {' or '.join(repr(name) for name in close)}?" if close else ""
    warn(f"main {main!r} is not a number in the results of collisionkit {results.study.command}, so there is no "
         f"main_result.png and the table shows '-'{hint}")


def _report(results, summary: Path | None) -> dict[str, Any]:
    """Print the table and the failures; write the summary (rescued if that fails: exit 1)."""
    study = results.study
    print_table(
        f"sweep of collisionkit {study.command}: {len(results.records)} runs",
        (*study.vary, "ok", f"{study.main or '-'} (replicas combined ± error)"),
        _point_rows(results),
    )
    _warn_unknown_main(results)
    failures = [{"name": record["name"], "error": record["error"]} for record in results.failed]
    for failure in failures[:SHOWN_FAILURES]:
        error_console.print(f"[bold red]failed[/] {escape(failure['name'])}: {escape(str(failure['error']))}", soft_wrap=True)
    combined = {
        "study": study.to_dict(),
        "seed": study.seed,
        "runs": len(results.records),
        "ok": len(results.records) - len(failures),
        "failed": len(failures),
        "skipped": results.skipped,
        "failures": failures,
        "files": [str(path) for path in results.files],
    }
    for path in results.files:
        say(f"wrote {path}")
    write_summary(summary, combined, "sweep")
    return combined


def _rescue_table(unwritten, summary: Path | None) -> None:
    """The study ran but its folder took no table: save ``results.csv`` elsewhere, say where, exit 1."""
    results = unwritten.results
    rescued = rescue_path("sweep", ".csv")
    if rescued is not None:
        try:
            write_csv(rescued, results.table)
        except OSError:
            rescued.unlink(missing_ok=True)
            rescued = None
    _report(results, summary)
    where = f"every run's results are saved in {rescued}" if rescued is not None else \
        "no folder took a rescue copy either: each point's result.json is in its own folder"
    raise run_failed(f"{unwritten.strerror}; {where}")


def sweep(
    study: Annotated[
        Path | None,
        typer.Argument(metavar="[STUDY.toml]",
                       help="TOML file of the study: command, seed, replicas, main (the result to tabulate and plot, "
                            "e.g. \"compressibility_factor\"; a list's element as \"temperature_species[0]\"), "
                            "\\[fixed], \\[vary] (not with --resume)."),
    ] = None,
    out: Annotated[
        Path | None, typer.Option(help="Folder for the points, results.csv and the plot.  \\[default: sweep-output]")
    ] = None,
    workers: Annotated[
        int | None, typer.Option(help="Worker processes of the embedded cluster (>= 1).  \\[default: the cores]")
    ] = None,
    scheduler: Annotated[
        str | None, typer.Option(
            help="Run on the existing Dask cluster at this address (e.g. tcp://host:8786); "
            "its workers need collisionkit installed and must see --out at the same path."
        )
    ] = None,
    resume: Annotated[
        Path | None, typer.Option(help="Continue the study saved in this checkpoint (OUT/checkpoint.npz), in its "
                                       "folder: skip finished points, rerun the rest.")
    ] = None,
    summary: Annotated[Path | None, typer.Option("--summary", help="Write the results as JSON to this file.")] = None,
    overwrite: Annotated[bool | None, typer.Option(
        "--overwrite", help="Start the study again in --out if it holds one (the files that study's sweep wrote there "
        "are replaced, no other), and let --summary replace an existing file; with --resume, only the latter.")] = None,
):
    """Run a parameter sweep with replicas of a collisionkit command, on a local or remote Dask cluster.

    Exit code 1 if some points failed (each is recorded with its error in
    results.csv); rerun them with --resume OUT/checkpoint.npz.
    """
    from .. import sweep as core

    _check_executor(workers, scheduler)
    if resume is not None:
        if study is not None or out is not None:
            raise fail("--resume continues the study saved in its checkpoint, in the checkpoint's folder: give "
                       "neither STUDY.toml nor --out with it")
        parsed, out = _resumed(resume)
    else:
        if study is None:
            raise fail("give a STUDY.toml file (or --resume OUT/checkpoint.npz to continue a study)")
        out = out if out is not None else Path("sweep-output")
        check_output_folder(out, "--out")
    check_output_file(summary, "--summary")
    refuse_clashes({"--summary": summary, "--out": out})
    refuse_to_replace(summary, "--summary", bool(overwrite))
    if resume is None:
        parsed = _load(study, out, bool(overwrite))
    total = len(core.expand(parsed)) * parsed.replicas
    note(f"seed {parsed.seed} (the study's root seed: each run's own seed derives from it and its point)")
    warm_up([parsed.command])  # compiled once here, the workers load the kernels from the cache
    try:
        with _executor(workers, scheduler) as client, progress_bar("points", total=total) as advance:
            results = core.run_study(parsed, out, executor=client, resume=resume is not None,
                                     overwrite=bool(overwrite) and resume is None, on_point=lambda record: advance())
    except FileLockedError as locked:
        raise fail(f"{locked}: another collisionkit sweep is running this study; wait for it or use another --out") \
            from None
    except KeyboardInterrupt:
        checkpoint = out / "checkpoint.npz"
        warn(f"interrupted: finished points are saved; continue with --resume {checkpoint}")
        raise typer.Exit(INTERRUPTED_EXIT_CODE) from None
    except core.OutputsNotWritten as unwritten:
        _rescue_table(unwritten, summary)
    combined = _report(results, summary)
    if combined["failed"]:
        error(f"{combined['failed']} of {combined['runs']} runs failed; rerun them with --resume "
              f"{out / 'checkpoint.npz'}")
        raise typer.Exit(FAILED_POINTS_EXIT_CODE)


def register(app: typer.Typer) -> None:
    """Add the ``sweep`` command to the ``collisionkit`` app."""
    app.command("sweep")(sweep)
