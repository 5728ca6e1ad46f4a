"""The files a command reads and writes: checked before any work, and the results never lost after it.

Before any work, every command checks

* each input file (``--config``, ``--resume``, ``--cross-sections`` ...):
  it exists and is a file, not a folder;
* each output: its folder can take a file (a temporary file is made and
  removed there: ``os.access`` says yes to root in ``/proc``), it is not a
  folder or a device, no two options name the same file, and no existing
  file is replaced without ``--overwrite`` (a command refreshes the files in
  its own ``--out`` folder freely).

If writing fails at the end anyway (a full disk, a folder removed during the
run), :class:`Deliveries` saves the results in a new file of the current
folder, or of the temporary folder, says where, and exits with 1.
"""

from __future__ import annotations

import json
import os
import stat
import tempfile
from collections.abc import Callable, Collection, Iterable, Mapping
from pathlib import Path
from typing import Any

import typer

from .._io import atomic_write_json
from ._messages import RUN_FAILED_EXIT_CODE, console, error, fail, say

PROBE_PREFIX = ".collisionkit-probe-"


def _reason(failure: OSError) -> str:
    """An OSError as a short phrase: its message and the file it names."""
    where = f": {failure.filename}" if failure.filename else ""
    return f"{failure.strerror or failure}{where}"


def refuse_folder(path: Path | None, option: str) -> None:
    """Stop with an input error (exit 2) if ``path``, which should name a file, is a folder.

    Examples
    --------
    >>> import tempfile
    >>> refuse_folder(Path("run.npz"), "--resume")  # a file, or nothing yet: fine here
    >>> try:
    ...     refuse_folder(Path(tempfile.mkdtemp()), "--resume")
    ... except Exception as stop:
    ...     print(type(stop).__name__, stop.exit_code)
    Exit 2
    """
    if path is not None and Path(path).is_dir():
        raise fail(f"{option} {path} is a folder, not a file")


def check_input_file(path: Path | None, option: str) -> None:
    """Stop with an input error (exit 2) unless ``path`` is an existing file (None: not given, nothing to check).

    Examples
    --------
    >>> import tempfile
    >>> check_input_file(None, "--config")
    >>> try:
    ...     check_input_file(Path(tempfile.mkdtemp()), "--config")
    ... except Exception as stop:
    ...     print(type(stop).__name__, stop.exit_code)
    Exit 2
    """
    if path is None:
        return
    path = Path(path)
    refuse_folder(path, option)
    if not path.exists():
        raise fail(f"{option} {path}: file not found")
    if not os.access(path, os.R_OK):
        raise fail(f"{option} {path} cannot be read (permission denied)")


def _unwritable(folder: Path) -> str | None:
    """Why files cannot be made in ``folder`` (the writers make its missing part), or None if they can.

    The nearest existing folder is probed: a temporary file (a temporary
    folder when the rest must be made) is created and removed there.
    """
    missing = False
    while not folder.exists() and folder != folder.parent:
        folder, missing = folder.parent, True
    if not folder.is_dir():
        return f"{folder} is a file, not a folder"
    try:
        if missing:
            os.rmdir(tempfile.mkdtemp(prefix=PROBE_PREFIX, dir=folder))
        else:
            handle, probe = tempfile.mkstemp(prefix=PROBE_PREFIX, dir=folder)
            os.close(handle)
            os.unlink(probe)
    except OSError as failure:
        return f"nothing can be written in {folder} ({failure.strerror or failure})"
    return None


def check_output_file(path: Path | None, option: str) -> None:
    """Stop with an input error (exit 2) before any work if ``path`` cannot be written as a file.

    Examples
    --------
    >>> import tempfile
    >>> check_output_file(None, "--summary")  # not asked for: nothing to check
    >>> try:
    ...     check_output_file(Path(tempfile.mkdtemp()), "--summary")  # a folder
    ... except Exception as stop:
    ...     print(type(stop).__name__, stop.exit_code)
    Exit 2
    """
    if path is None:
        return
    path = Path(path)
    if path.is_dir():
        raise fail(f"{option} {path} is a folder: give a file name")
    if path.exists() and not stat.S_ISREG(path.stat().st_mode):
        raise fail(f"{option} {path} is not a regular file (a device or a pipe): give a file name")
    reason = _unwritable(path.parent)
    if reason is not None:
        raise fail(f"{option} {path} cannot be written: {reason}")


def check_output_folder(path: Path | None, option: str) -> None:
    """Stop with an input error (exit 2) before any work if ``path`` cannot be used as an output folder.

    Examples
    --------
    >>> import tempfile
    >>> file = Path(tempfile.mkdtemp()) / "taken"
    >>> _ = file.write_text("x")
    >>> try:
    ...     check_output_folder(file, "--out")  # a file is in the way
    ... except Exception as stop:
    ...     print(type(stop).__name__, stop.exit_code)
    Exit 2
    """
    if path is None:
        return
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise fail(f"{option} {path} is a file, not a folder")
    reason = _unwritable(path)
    if reason is not None:
        raise fail(f"{option} {path} cannot be written: {reason}")


def refuse_clashes(paths: Mapping[str, Path | None]) -> None:
    """Stop (exit 2) if two options (``{"--summary": path, ...}``) name the same file: one would replace the other.

    Examples
    --------
    >>> refuse_clashes({"--summary": Path("a.json"), "--checkpoint": Path("b.npz"), "--xyz": None})
    >>> try:
    ...     refuse_clashes({"--summary": Path("a.npz"), "--checkpoint": Path("./a.npz")})
    ... except Exception as stop:
    ...     print(type(stop).__name__, stop.exit_code)
    Exit 2
    """
    seen: dict[Path, str] = {}
    for option, path in paths.items():
        if path is None:
            continue
        where = Path(path).resolve()
        if where in seen:
            raise fail(f"{seen[where]} and {option} name the same file ({path}): one would replace the other; "
                       "give each its own")
        seen[where] = option


def refuse_to_replace(path: Path | None, option: str, overwrite: bool, keep: Collection[Path] = ()) -> None:
    """Stop (exit 2) before an existing file a user made would be replaced, unless ``overwrite``.

    ``keep`` holds the resolved paths the command may write on (a resumed
    run's own checkpoint and trajectory).

    Examples
    --------
    >>> import tempfile
    >>> existing = Path(tempfile.mkdtemp()) / "s.json"
    >>> _ = existing.write_text("{}")
    >>> refuse_to_replace(existing, "--summary", overwrite=True)  # asked for
    >>> try:
    ...     refuse_to_replace(existing, "--summary", overwrite=False)
    ... except Exception as stop:
    ...     print(type(stop).__name__, stop.exit_code)
    Exit 2
    """
    if path is None or overwrite or not Path(path).exists() or Path(path).resolve() in keep:
        return
    if option == "--checkpoint":
        raise fail(f"{path} exists: continue the run it holds with --resume {path}, or remove it, name another "
                   "--checkpoint or pass --overwrite to start a new run over it")
    raise fail(f"{option} {path} exists: pass --overwrite to replace it, or name another file")


def refuse_earlier_run(folder: Path | None, option: str, names: Collection[str], overwrite: bool) -> None:
    """Stop (exit 2) before files of an earlier run in an output folder would be replaced, unless ``overwrite``.

    ``names`` are the files the command writes in the folder; other files
    in it are none of its business (``--out .`` is fine).

    Examples
    --------
    >>> import tempfile
    >>> folder = Path(tempfile.mkdtemp())
    >>> _ = (folder / "encounter.png").write_bytes(b"")
    >>> refuse_earlier_run(folder, "--out", ["snapshot.png"], overwrite=False)  # not one of ours: no matter
    >>> try:
    ...     refuse_earlier_run(folder, "--out", ["encounter.png"], overwrite=False)
    ... except Exception as stop:
    ...     print(type(stop).__name__, stop.exit_code)
    Exit 2
    """
    if folder is None or overwrite or not Path(folder).is_dir():
        return
    earlier = [name for name in names if (Path(folder) / name).exists()]
    if earlier:
        more = f" and {len(earlier) - 1} more of its files" if len(earlier) > 1 else ""
        raise fail(f"{option} {folder} already holds {earlier[0]}{more} from an earlier run: pass --overwrite to "
                   "replace them, or name another folder")


def _rescue_folders() -> Iterable[Path]:
    yield Path.cwd()
    yield Path(tempfile.gettempdir())


def rescue_path(command: str, suffix: str) -> Path | None:
    """A new, empty file to save results in when their own place failed: in the current folder, else the temporary one.

    Never an existing file; None if neither folder takes one.

    Examples
    --------
    >>> path = rescue_path("demo", ".json")
    >>> path.name.startswith("collisionkit-demo-results-"), path.suffix, path.stat().st_size
    (True, '.json', 0)
    >>> path.unlink()
    """
    for folder in _rescue_folders():
        try:
            handle, name = tempfile.mkstemp(prefix=f"collisionkit-{command}-results-", suffix=suffix, dir=folder)
        except OSError:
            continue
        os.close(handle)
        return Path(name)
    return None


class Deliveries:
    """The files a command writes once its work is done; none of the results is lost if one fails.

    Each :meth:`write` runs a writer; an ``OSError`` is recorded, not
    raised, so the other files are still written. :meth:`finish` writes the
    summary; after any failure it saves the summary in a rescue file (the
    current folder, else the temporary one; printed on stdout if neither
    takes it), says where, and exits with 1.

    Examples
    --------
    >>> import tempfile
    >>> folder = Path(tempfile.mkdtemp())
    >>> deliveries = Deliveries("slab")
    >>> deliveries.write("a note", lambda: (folder / "note.txt").write_text("hi") and folder / "note.txt")
    >>> deliveries.files == [folder / "note.txt"], deliveries.failures
    (True, [])
    >>> deliveries.finish(None, {"transmission": 0.5})  # nothing failed: nothing more to do
    """

    def __init__(self, command: str):
        self.command = command
        self.files: list[Path] = []
        self.failures: list[str] = []

    def write(self, what: str, writer: Callable[[], Path | Iterable[Path] | None]) -> None:
        """Run ``writer`` (it returns the file or files it wrote); an OSError is kept for :meth:`finish`.

        Examples
        --------
        >>> deliveries = Deliveries("slab")
        >>> deliveries.write("the plot", lambda: open("/no/such/folder/plot.png", "w"))
        >>> deliveries.failures
        ['the plot (No such file or directory: /no/such/folder/plot.png)']
        """
        try:
            written = writer()
        except OSError as failure:
            self.failures.append(f"{what} ({_reason(failure)})")
            return
        if isinstance(written, (str, Path)):
            self.files.append(Path(written))
        elif written is not None:
            self.files.extend(Path(path) for path in written)

    def finish(self, summary: Path | None, result: Mapping[str, Any]) -> None:
        """Write the summary to ``summary``; after any failure rescue ``result`` and exit with 1.

        Examples
        --------
        >>> import os, tempfile
        >>> here = os.getcwd()
        >>> os.chdir(tempfile.mkdtemp())  # the rescue file goes to the current folder
        >>> deliveries = Deliveries("slab")
        >>> deliveries.failures.append("the plot (disk full)")
        >>> try:
        ...     deliveries.finish(None, {"transmission": 0.5})
        ... except Exception as stop:
        ...     print(type(stop).__name__, stop.exit_code)
        Exit 1
        >>> [path.name.startswith("collisionkit-slab-results-") for path in Path.cwd().iterdir()]
        [True]
        >>> os.chdir(here)
        """
        if summary is not None:
            try:
                atomic_write_json(summary, dict(result))
                say(f"summary written to {summary}")
            except OSError as failure:
                self.failures.append(f"the summary {summary} ({_reason(failure)})")
        if not self.failures:
            return
        rescued = rescue_path(self.command, ".json")
        written = None
        if rescued is not None:
            try:
                written = atomic_write_json(rescued, dict(result))
            except OSError:
                rescued.unlink(missing_ok=True)
        if written is None:
            console.print(json.dumps(dict(result), indent=2, default=str), markup=False, highlight=False, soft_wrap=True)
            where = "nowhere could take them, so they are printed above"
        else:
            where = f"the results are saved in {written}"
        error(f"the work is done, but writing failed: {'; '.join(self.failures)}; {where}")
        raise typer.Exit(RUN_FAILED_EXIT_CODE)
