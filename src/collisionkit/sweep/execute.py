"""Running a study's points: in this process, on any executor or on a Dask cluster, with checkpoint and resume.

Every point's ``result.json`` is written atomically as soon as it
finishes; the study's checkpoint (``OUT/checkpoint.npz``, the format every
collisionkit run uses) holds the study and the finished points, so
:func:`resume_study` (``collisionkit sweep --resume OUT/checkpoint.npz``)
skips them and reruns the others (the failed ones too), and
``run_study(..., overwrite=True)`` (``sweep --overwrite``) starts a study
again in a folder that holds one, removing only the files its sweep wrote.
"""

from __future__ import annotations

import concurrent.futures
import contextlib
import json
import math
import os
import time
import traceback
from collections.abc import Callable, Iterable, Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from .._io import (
    CheckpointError, FileLockedError, atomic_write_json, atomic_write_text, exclusive, read_checkpoint,
    remove_stale_temporaries, write_checkpoint,
)
from .clients import local_client
from .commands import POINT_CHECKPOINT, sweep_command
from .study import Study, load_study, study_from_dict
from .table import OUTPUT_FILES, results_table, write_outputs
from .tasks import POINTS_FOLDER, RESULT_FILE, PointTask, _split_options, point_tasks

__all__ = ["OutputsNotWritten", "StudyResults", "check_folder", "resume_study", "run_point", "run_study"]

RESULT_FORMAT = 2
CHECKPOINT_FILE = "checkpoint.npz"
CHECKPOINT_KIND = "sweep"
SUMMARY_FILE, LOG_FILE = "summary.json", "output.log"
POINT_FILES = (RESULT_FILE, SUMMARY_FILE, LOG_FILE, POINT_CHECKPOINT)  # what the sweep writes in a point's folder
LOCK_WAIT_SECONDS = 24 * 3600.0  # a point still run by an earlier client's worker: wait for it this long at most


# ------------------------------------------------------------------ running one point


def run_point(task: PointTask) -> dict[str, Any]:
    """Run one point's replica in this process (a library call) and write its ``result.json`` atomically.

    Never raises for a failing run: an exception gives a record with
    ``status = "failed"`` and the error; its traceback goes to
    ``output.log`` in the point's folder.

    Returns
    -------
    dict
        The record written to ``result.json``: ``status``, ``error``,
        ``elapsed`` (wall, s), ``cpu_time`` (of the process, s),
        ``summary`` (the command's summary, also in ``summary.json``) and
        the task's fields.

    Examples
    --------
    >>> import tempfile
    >>> study = Study("encounter", seed=0, vary={"vinf": [0.5]})
    >>> task = point_tasks(study, tempfile.mkdtemp())[0]
    >>> record = run_point(task)
    >>> record["status"], round(record["summary"]["orbit"]["eccentricity"], 6)
    ('ok', 1.125)
    >>> task.result_path.exists()
    True
    """
    task.directory.mkdir(parents=True, exist_ok=True)
    started, cpu_started = time.perf_counter(), time.process_time()
    summary, error = None, None
    try:
        command = sweep_command(task.command)
        parameters, outputs = _split_options(command, task.options)
        try:
            summary = command.run(parameters, task.directory, outputs)
        except FileLockedError:
            # a worker of an earlier client (killed, then the study resumed) still runs this point: let it finish
            _wait_until_free(task.directory / POINT_CHECKPOINT)
            finished = _is_complete(task)
            if finished is not None:
                return finished
            summary = command.run(parameters, task.directory, outputs)
        atomic_write_json(task.directory / SUMMARY_FILE, summary)
        summary = json.loads((task.directory / SUMMARY_FILE).read_text())  # as a reader sees it (NaN as null)
    except Exception as exception:  # the run's failure is the point's result
        error = f"{type(exception).__name__}: {exception}"
        atomic_write_text(task.directory / LOG_FILE, traceback.format_exc())
    elapsed, cpu_time = time.perf_counter() - started, time.process_time() - cpu_started
    record = _record(task, "ok" if error is None else "failed", error, elapsed, summary)
    record["cpu_time"] = cpu_time
    atomic_write_json(task.result_path, record)
    return record


def _wait_until_free(path: Path, timeout: float = LOCK_WAIT_SECONDS) -> None:
    """Wait until no other process holds the lock of ``path`` (FileLockedError after ``timeout`` seconds)."""
    deadline = time.monotonic() + timeout
    while True:
        try:
            with exclusive(path):
                return
        except FileLockedError:
            if time.monotonic() > deadline:
                raise
            time.sleep(0.2)


def _read_json(path: Path) -> dict | None:
    try:
        data = json.loads(path.read_text())
    except (OSError, ValueError):
        return None
    return data if isinstance(data, dict) else None


def _record(task: PointTask, status, error, elapsed, summary) -> dict[str, Any]:
    return {
        "format": RESULT_FORMAT,
        "command": task.command,
        "point": task.index,
        "replica": task.replica,
        "name": task.name,
        "parameters": dict(task.parameters),
        "options": dict(task.options),
        "seed": task.seed,
        "spawn_key": list(task.spawn_key),
        "status": status,
        "error": error,
        "elapsed": elapsed,
        "summary": summary,
    }


def _is_complete(task: PointTask) -> dict | None:
    """The point's saved record if it finished successfully with this task's parameters and seed."""
    record = _read_json(task.result_path)
    if record is None or record.get("status") != "ok" or record.get("format") != RESULT_FORMAT:
        return None
    same = record.get("seed") == task.seed and record.get("parameters") == json.loads(json.dumps(dict(task.parameters)))
    return record if same and isinstance(record.get("summary"), dict) else None


# ------------------------------------------------------------------ executors


def _is_dask_client(executor) -> bool:
    return type(executor).__module__.split(".")[0] == "distributed"


def _submit(executor, tasks: list[PointTask]) -> tuple[dict, Iterator]:
    """Submit every task; return {future: task} and an iterator over the futures as they finish."""
    if _is_dask_client(executor):
        from distributed import as_completed

        futures = {executor.submit(run_point, task, pure=False): task for task in tasks}
        return futures, iter(as_completed(list(futures)))
    futures = {executor.submit(run_point, task): task for task in tasks}
    return futures, concurrent.futures.as_completed(list(futures))


def _cancel(executor, futures: Iterable) -> None:
    futures = list(futures)
    if _is_dask_client(executor):
        executor.cancel(futures)
        return
    for future in futures:
        future.cancel()


def _collect(future, task: PointTask) -> dict[str, Any]:
    """The finished point's record; a future that failed (worker lost, ...) gives a failed record."""
    try:
        record = future.result()
    except Exception as exception:
        record = _record(task, "failed", f"{type(exception).__name__}: {exception}", math.nan, None)
    if not task.result_path.exists() or record["status"] != "ok":
        atomic_write_json(task.result_path, record)  # a worker on another file system, or a lost point
    return record


# ------------------------------------------------------------------ the study


@dataclass
class StudyResults:
    """What :func:`run_study` produced.

    Attributes
    ----------
    study : Study
    records : list of dict
        One record per point and replica, in point then replica order.
    table : list of dict
        The rows of ``results.csv``.
    files : list of Path
        The study-level files written (table, plot, study description).
    skipped : int
        Points found complete and not rerun (``resume=True``).

    Examples
    --------
    >>> import tempfile
    >>> from concurrent.futures import ThreadPoolExecutor
    >>> study = {"command": "encounter", "seed": 2, "vary": {"vinf": [0.5, 2.0]}}
    >>> with ThreadPoolExecutor(1) as pool:
    ...     results = run_study(study, tempfile.mkdtemp(), executor=pool)
    >>> len(results.records), results.failed, results.skipped
    (2, [], 0)
    """

    study: Study
    records: list[dict[str, Any]]
    table: list[dict[str, Any]]
    files: list[Path]
    skipped: int = 0

    @property
    def failed(self) -> list[dict[str, Any]]:
        """The records of the failed points."""
        return [record for record in self.records if record["status"] != "ok"]


def _as_study(study) -> Study:
    if isinstance(study, Study):
        return study
    if isinstance(study, Mapping):
        return study_from_dict(study)
    if isinstance(study, (str, os.PathLike)):
        return load_study(study)
    raise TypeError(f"study must be a Study, a mapping or a TOML path; got {type(study).__name__}")


def check_folder(study: Study, out, resume: bool = False, overwrite: bool = False) -> None:
    """Check that ``out`` can take the study: no study, the same one (to resume) or any (to overwrite).

    Parameters
    ----------
    study : Study
    out : path
        The study's folder.
    resume : bool
        The study continues in ``out``: a study there must be this one.
    overwrite : bool
        The study starts again in ``out``: a study there must be readable
        (its files are then replaced, see :func:`run_study`).

    Raises
    ------
    ValueError
        If ``out`` is a file, holds a study and neither ``resume`` nor
        ``overwrite`` is given, holds another study (``resume``), or holds
        a ``checkpoint.npz`` that is not a readable study (``overwrite``).

    Examples
    --------
    >>> import tempfile
    >>> check_folder(Study("encounter", seed=0, vary={"vinf": [1.0]}), tempfile.mkdtemp())
    """
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise ValueError(f"out {out} is a file, not a folder")
    path = out / CHECKPOINT_FILE
    if not path.exists():
        return
    if overwrite:
        _saved_tasks(path)
        return
    if not resume:
        raise ValueError(f"out {out} already holds a study; resume it (resume_study({str(path)!r}), "
                         f"--resume {path}), start it again there (overwrite=True, --overwrite) or use another folder")
    saved = read_checkpoint(path, CHECKPOINT_KIND)
    if saved.state.get("fingerprint") != study.fingerprint():
        raise ValueError(f"out {out} holds a different study ({path}); resume it with the same study or use another folder")


def _saved_tasks(checkpoint: Path) -> list[PointTask]:
    """The runs of the study saved in ``checkpoint``, in its folder (ValueError if it holds no valid study)."""
    try:
        saved = read_checkpoint(checkpoint, CHECKPOINT_KIND)
        return point_tasks(study_from_dict(saved.parameters), checkpoint.parent)
    except (TypeError, ValueError) as error:
        raise ValueError(f"{checkpoint} holds no study that can be replaced ({error}); nothing there is removed: "
                         "use another folder") from None


def _point_files(task: PointTask) -> list[Path]:
    """The files a run of ``task`` may write in its folder: the sweep's own, the command's (named or fixed)."""
    command = sweep_command(task.command)
    named = [task.options.get(key) for key, kind in command.outputs.items() if kind is Path]
    names = [*POINT_FILES, *command.files, *(str(name) for name in named if name is not None)]
    return [task.directory / name for name in names if Path(name).name == name]  # never a path out of the folder


def _remove_study(out: Path) -> None:
    """Remove the files the sweep of the study saved in ``out`` wrote there, and the points' folders left empty.

    The study's checkpoint stays, to be replaced (atomically) by the next
    one; a file the sweep did not write (a note in a point's folder) stays,
    and so does its folder. What a killed run left beside the sweep's
    files goes too (:func:`_remove_written`).
    """
    for task in _saved_tasks(out / CHECKPOINT_FILE):
        if not task.directory.is_dir():
            continue
        for path in _point_files(task):
            _remove_written(path)
        with contextlib.suppress(OSError):
            task.directory.rmdir()
    with contextlib.suppress(OSError):
        (out / POINTS_FOLDER).rmdir()
    for name in OUTPUT_FILES:
        _remove_written(out / name)


def _remove_written(path: Path) -> None:
    """Remove ``path`` with what killed writers of it left: its hidden lock file and temporary files.

    Taking the file's lock refuses (:class:`~collisionkit._io.FileLockedError`)
    while a live process writes it (a worker of an earlier client still in
    its point); leaving the block removes the lock file, and a temporary
    file is removed only when its writer is gone
    (:func:`~collisionkit._io.remove_stale_temporaries`).
    """
    with exclusive(path):
        path.unlink(missing_ok=True)
        remove_stale_temporaries(path)


class OutputsNotWritten(OSError):
    """The study ran, but its tables could not be written in its folder; ``results`` holds them all.

    Raised by :func:`run_study` after the work, so that a caller can save
    ``results.table`` elsewhere (the command line writes it to a rescue
    file and says where).

    Examples
    --------
    >>> failure = OutputsNotWritten("sweep-output", OSError(28, "No space left on device"), results=None)
    >>> str(failure)
    "[Errno 28] the study's tables could not be written in sweep-output: No space left on device"
    """

    def __init__(self, out, failure: OSError, results: StudyResults | None):
        super().__init__(failure.errno, f"the study's tables could not be written in {out}: "
                                        f"{failure.strerror or failure}")
        self.results = results


def _saver(study: Study, out: Path, done: Mapping[str, dict]) -> Callable[[], None]:
    """Save the study's checkpoint after a point; a failure (the folder unwritable now) does not stop the study.

    The work goes on: the finished points are in memory, and the tables
    written at the end (or rescued) hold them; only a resume would miss them.
    """

    def save() -> None:
        with contextlib.suppress(OSError):
            _save_checkpoint(study, out, done)

    return save


def _save_checkpoint(study: Study, out: Path, records: Mapping[str, dict]) -> Path:
    finished = sorted(name for name, record in records.items() if record["status"] == "ok")
    state = {"fingerprint": study.fingerprint(), "finished": finished}
    return write_checkpoint(out / CHECKPOINT_FILE, CHECKPOINT_KIND, study.to_dict(), state)


def run_study(study, out, executor=None, workers: int | None = None, resume: bool = False,
              progress: Callable[[float], Any] | None = None,
              on_point: Callable[[dict], Any] | None = None, overwrite: bool = False) -> StudyResults:  # fmt: skip
    """Run every point and replica of a study and write the table and the plot.

    Every point is checked by the command's own rules before any runs.

    Parameters
    ----------
    study : Study, mapping or path
        The study (a TOML path is read with :func:`load_study`).
    out : path
        The study's folder.
    executor : concurrent.futures.Executor or distributed.Client, optional
        Where the points run; default: an embedded ``LocalCluster`` of
        ``workers`` processes (:func:`local_client`).
    workers : int, optional
        Worker processes of the embedded cluster (>= 1; default: the cores);
        only without ``executor``.
    resume : bool
        Continue the study in ``out`` (as :func:`resume_study`): skip the
        points whose ``result.json`` is complete, rerun the others. Without
        it, ``out`` must not hold a study (unless ``overwrite``). The study's
        checkpoint is locked while it runs: a second sweep of the folder
        raises :class:`~collisionkit._io.FileLockedError`.
    progress : callable, optional
        Called as ``progress(fraction)`` with the fraction of runs done.
    on_point : callable, optional
        Called with each point's record as it finishes (skipped ones first).
    overwrite : bool
        Start the study again in ``out`` if it holds one (this study or
        another): every point runs. The files written there by the sweep of
        the study found there (its tables, its points' files) are removed
        first and its checkpoint is replaced atomically; no other file is
        touched. Not with ``resume``.

    Returns
    -------
    StudyResults

    Examples
    --------
    >>> import tempfile
    >>> from concurrent.futures import ThreadPoolExecutor
    >>> study = {"command": "encounter", "seed": 1, "replicas": 2, "vary": {"vinf": [0.5, 1.0]}}
    >>> with ThreadPoolExecutor(1) as pool:
    ...     results = run_study(study, tempfile.mkdtemp(), executor=pool)
    >>> len(results.table), results.failed
    (4, [])
    >>> sorted({row["vinf"] for row in results.table})
    [0.5, 1.0]
    """
    study = _as_study(study)
    if executor is not None and workers is not None:
        raise ValueError("workers sets the size of the embedded cluster; it cannot be used with executor")
    if resume and overwrite:
        raise ValueError("resume continues the study in out, overwrite starts it again: give one of them")
    out = Path(out)
    tasks = point_tasks(study, out)
    check_folder(study, out, resume, overwrite)
    with exclusive(out / CHECKPOINT_FILE):  # a second sweep (or --resume) of this folder is refused meanwhile
        check_folder(study, out, resume, overwrite)  # again, now that no other sweep can start one here
        if overwrite and (out / CHECKPOINT_FILE).exists():
            _remove_study(out)
        done = {task.name: record for task in tasks if resume and (record := _is_complete(task)) is not None}
        files = [_save_checkpoint(study, out, done)]
        report = _Reporter(len(tasks), progress, on_point)
        for record in done.values():
            report(record)
        pending = [task for task in tasks if task.name not in done]
        if pending:
            with contextlib.ExitStack() as stack:
                if executor is None:
                    executor = stack.enter_context(local_client(workers))
                save = _saver(study, out, done)
                _execute(executor, pending, done, lambda record: (report(record), save()))
        records = [done[task.name] for task in tasks]
        table = results_table(study, records)
        results = StudyResults(study, records, table, files, skipped=len(tasks) - len(pending))
        try:
            files += write_outputs(study, out, table)
        except OSError as failure:
            raise OutputsNotWritten(out, failure, results) from failure
    return results


def resume_study(checkpoint, executor=None, workers: int | None = None,
                 progress: Callable[[float], Any] | None = None,
                 on_point: Callable[[dict], Any] | None = None) -> StudyResults:  # fmt: skip
    """Continue the study saved in ``checkpoint`` (``OUT/checkpoint.npz``), in its folder.

    Raises
    ------
    ValueError
        If the file is not a sweep checkpoint (:class:`~collisionkit._io.CheckpointError`).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from concurrent.futures import ThreadPoolExecutor
    >>> out = pathlib.Path(tempfile.mkdtemp())
    >>> study = {"command": "encounter", "seed": 1, "vary": {"vinf": [0.5, 1.0]}}
    >>> with ThreadPoolExecutor(1) as pool:
    ...     first = run_study(study, out, executor=pool)
    ...     again = resume_study(out / "checkpoint.npz", executor=pool)
    >>> again.skipped, len(again.table)
    (2, 2)
    """
    saved = read_checkpoint(checkpoint, CHECKPOINT_KIND)
    try:
        study = study_from_dict(saved.parameters)
    except (TypeError, ValueError) as error:
        raise CheckpointError(f"{checkpoint} holds a study that is not valid now: {error}") from None
    return run_study(study, Path(checkpoint).parent, executor=executor, workers=workers, resume=True,
                     progress=progress, on_point=on_point)


class _Reporter:
    """Calls ``progress(fraction)`` and ``on_point(record)`` as runs finish."""

    def __init__(self, total: int, progress, on_point):
        self.total, self.done, self.progress, self.on_point = total, 0, progress, on_point

    def __call__(self, record: dict) -> None:
        self.done += 1
        if self.on_point is not None:
            self.on_point(record)
        if self.progress is not None:
            self.progress(self.done / self.total)


def _execute(executor, tasks: list[PointTask], records: dict[str, dict], finished) -> None:
    futures, completed = _submit(executor, tasks)
    try:
        for future in completed:
            task = futures[future]
            records[task.name] = _collect(future, task)
            finished(records[task.name])
    finally:
        _cancel(executor, [future for future, task in futures.items() if task.name not in records])
