"""Conventions shared by every ``collisionkit`` subcommand.

* options on the command line or in a TOML file (``--config``), with the
  same names (``packing-fraction`` or ``packing_fraction``); the command line
  wins; unknown keys and bad values are reported clearly and exit with 2;
* ``--summary FILE.json`` writes the run's results atomically;
* a rich progress bar on stderr for anything longer than a second.
"""

from __future__ import annotations

import difflib
import importlib.util
import os
import tomllib
from collections.abc import Iterable, Mapping
from contextlib import contextmanager
from pathlib import Path
import types
from typing import Any, ClassVar, Union, get_args, get_origin

import typer
from pydantic import BaseModel, ConfigDict, ValidationError, model_validator
from rich.console import Console
from rich.markup import escape
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn, TimeRemainingColumn
from rich.table import Table

from .._io import atomic_write_json

console = Console()
error_console = Console(stderr=True)

BAD_INPUT_EXIT_CODE = 2
INTERRUPTED_EXIT_CODE = 130  # as a shell reports a command stopped by Ctrl-C (128 + SIGINT)


def _dashed(name: str) -> str:
    return name.replace("_", "-")


class Options(BaseModel):
    """Base of every subcommand's options: strict, dashed keys allowed.

    ``output_files`` and ``output_folders`` name the options that are paths
    the command writes; :func:`load_options` checks them before any work.
    """

    model_config = ConfigDict(extra="forbid", alias_generator=_dashed, populate_by_name=True, frozen=True)
    output_files: ClassVar[tuple[str, ...]] = ("summary",)
    output_folders: ClassVar[tuple[str, ...]] = ()

    @model_validator(mode="before")
    @classmethod
    def _no_loose_types(cls, values: Any) -> Any:
        """Refuse what pydantic would coerce: a bool or a string for a number, a non-bool for a flag.

        (``seed = true`` became seed 1, ``packing-fraction = "0.3"`` 0.3, ``plots = "yes"`` True and
        ``E-N = ["5"]`` [5.0].) A single value of a list option (``E-N = 5``, ``species = "Ar"``) is a list of one.
        """
        if not isinstance(values, dict):
            return values
        values = dict(values)
        for key, value in values.items():
            field = cls.model_fields.get(key) or cls.model_fields.get(str(key).replace("-", "_"))
            if field is None:
                continue
            kinds, item = _plain_types(field.annotation), _list_item(field.annotation)
            single = (int, float) if item is float else item
            if item is not None and isinstance(value, single) and not isinstance(value, bool):
                value = values[key] = [value]
            entries = value if isinstance(value, list) else [value]
            if item in (int, float) and any(isinstance(entry, (bool, str)) for entry in entries):
                raise ValueError(f"{_dashed(str(key))} must be a number or a list of numbers, not {value!r}")
            if kinds & {int, float} and not kinds & {str, bool} and isinstance(value, (bool, str)):
                raise ValueError(f"{_dashed(str(key))} must be a number, not {value!r}")
            if kinds == {bool} and not isinstance(value, bool):
                raise ValueError(f"{_dashed(str(key))} must be true or false, not {value!r}")
        return values


def _plain_types(annotation: Any) -> set:
    """The plain types an annotation admits: {int} for int, {float} for float | None, ..."""
    if get_origin(annotation) in (Union, types.UnionType):
        return set().union(*(_plain_types(argument) for argument in get_args(annotation)))
    if get_origin(annotation) is not None:  # Annotated, list, Literal: look no further
        base = get_args(annotation)[0] if get_args(annotation) else None
        return {base} if get_origin(annotation) is not list and isinstance(base, type) else set()
    return {annotation} if isinstance(annotation, type) else set()


def _list_item(annotation: Any) -> type | None:
    """The item type of a list option: float for ``list[float] | None``; None for any other option."""
    if get_origin(annotation) in (Union, types.UnionType):
        items = {_list_item(argument) for argument in get_args(annotation)} - {None}
        return items.pop() if len(items) == 1 else None
    arguments = get_args(annotation)
    return arguments[0] if get_origin(annotation) is list and arguments and isinstance(arguments[0], type) else None


def warn(message: str) -> None:
    """Print ``message`` as a warning on stderr (the table and files on stdout stay clean), markup escaped.

    Examples
    --------
    >>> warn("E/N = 0 Td stopped at the collision budget [5e8]")
    """
    error_console.print(f"[bold yellow]warning:[/] {escape(message)}")


def fail(message: str) -> typer.Exit:
    """Print ``message`` as an input error and return the exit to raise (code 2).

    The message is printed as it is: brackets in it (``collisionkit[plot]``,
    a list the user gave) are not rich markup.
    """
    error_console.print(f"[bold red]error:[/] {escape(message)}")
    return typer.Exit(BAD_INPUT_EXIT_CODE)


def require(module: str, extra: str, purpose: str) -> None:
    """Stop with an input error (exit 2) before any work if ``module``, of the optional ``extra``, is missing.

    Examples
    --------
    >>> require("json", "io", "reading JSON")  # installed: nothing happens
    >>> try:
    ...     require("no_such_module_here", "plot", "plots")
    ... except Exception as stop:
    ...     print(type(stop).__name__, stop.exit_code)
    Exit 2
    """
    if importlib.util.find_spec(module) is None:
        raise fail(f"{purpose} needs {module}, which is not installed: pip install 'collisionkit[{extra}]'")


def require_plotting() -> None:
    """:func:`require` matplotlib (the ``plot`` extra), with a hint to turn plots off."""
    require("matplotlib", "plot", "plotting (pass --no-plots to skip it)")


def require_gsd() -> None:
    """:func:`require` gsd (the ``io`` extra) for GSD trajectories."""
    require("gsd", "io", "a GSD trajectory")


def read_toml(path: Path) -> dict[str, Any]:
    """Read a TOML options file; a missing or malformed file is an input error."""
    try:
        with open(path, "rb") as stream:
            return tomllib.load(stream)
    except FileNotFoundError:
        raise fail(f"config file not found: {path}") from None
    except tomllib.TOMLDecodeError as error:
        raise fail(f"config file {path} is not valid TOML: {error}") from None
    except UnicodeDecodeError as error:  # TOML is UTF-8 text
        raise fail(f"config file {path} is not UTF-8 text, as TOML must be (byte {error.start}: "
                   f"{error.reason})") from None


def _describe(error: Mapping[str, Any], model: type[Options] | None = None) -> str:
    """One line for one pydantic error; a rule between options speaks for itself (no echo of every value).

    An unknown option of ``model`` comes with the closest valid names and the list of them all.

    Examples
    --------
    >>> class Run(Options):
    ...     particles: int = 500
    ...     plots: bool = True
    >>> _describe({"loc": ("particle",), "type": "extra_forbidden", "msg": "", "input": 100}, Run)
    "unknown option 'particle'; did you mean 'particles'? (options: particles, plots)"
    """
    where = ".".join(str(part) for part in error["loc"])
    if error["type"] == "extra_forbidden":
        if model is None:
            return f"unknown option {where!r}"
        names = sorted(_dashed(name) for name in model.model_fields)
        close = difflib.get_close_matches(_dashed(where), names, n=3)
        guess = f"; did you mean {' or '.join(repr(name) for name in close)}?" if close else ""
        return f"unknown option {where!r}{guess} (options: {', '.join(names)})"
    if error["type"] == "value_error":  # our own rules: their message without pydantic's "Value error, "
        message = str(error["ctx"]["error"])
        return f"{where}: {message} (got {error.get('input')!r})" if where else message
    return f"{where or 'options'}: {error['msg']} (got {error.get('input')!r})"


def load_options(model: type[Options], config: Path | None, given: Mapping[str, Any]):
    """Merge a TOML file with command-line values and validate them.

    Parameters
    ----------
    model : subclass of Options
        The command's option schema.
    config : Path or None
        TOML file with option keys at the top level.
    given : mapping
        Command-line values; ``None`` means "not given on the command line".
    """
    return validate_options(model, option_values(model, config, given))


def option_values(model: type[Options], config: Path | None, given: Mapping[str, Any]) -> dict[str, Any]:
    """The options a TOML file and the command line set, by field name, not yet validated (the command line wins)."""
    values: dict[str, Any] = {}
    if config is not None:
        spelled: dict[str, str] = {}
        for key, value in read_toml(config).items():
            name = _field_name(model, key)
            if name in spelled:
                raise fail(f"config file {config} sets {name!r} twice: as {spelled[name]!r} and as {key!r}")
            spelled[name] = key
            values[name] = value
    values.update({key: value for key, value in given.items() if value is not None})
    return values


def validate_options(model: type[Options], values: Mapping[str, Any]):
    """Validate option values (exit 2 naming each bad one) and check that the outputs can be written."""
    try:
        options = model.model_validate(dict(values))
    except ValidationError as error:
        details = "; ".join(_describe(item, model) for item in error.errors())
        raise fail(f"invalid options: {details}") from None
    for name in model.output_files:
        check_output_file(getattr(options, name), f"--{_dashed(name)}")
    for name in model.output_folders:
        check_output_folder(getattr(options, name), f"--{_dashed(name)}")
    return options


def _field_name(model: type[Options], key: str) -> str:
    """The option a TOML key names: dashes or underscores, and the command line's case (E-N for e_n)."""
    name = key.replace("-", "_")
    return name.lower() if name not in model.model_fields and name.lower() in model.model_fields else name


def _unwritable(folder: Path) -> str | None:
    """Why files cannot be written in ``folder`` (the writers make its missing part), or None if they can."""
    while not folder.exists() and folder != folder.parent:
        folder = folder.parent
    if not folder.is_dir():
        return f"{folder} is a file, not a folder"
    return None if os.access(folder, os.W_OK | os.X_OK) else f"{folder} is read-only"


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


def refuse_to_overwrite_checkpoint(path: Path | None) -> None:
    """Stop (exit 2) before a new run would overwrite an existing checkpoint: the work in it would be lost.

    Examples
    --------
    >>> refuse_to_overwrite_checkpoint(None)  # no checkpoint asked for
    >>> import tempfile
    >>> existing = Path(tempfile.mkdtemp()) / "run.npz"
    >>> _ = existing.write_bytes(b"saved work")
    >>> try:
    ...     refuse_to_overwrite_checkpoint(existing)
    ... except Exception as stop:
    ...     print(type(stop).__name__, stop.exit_code)
    Exit 2
    """
    if path is not None and Path(path).exists():
        raise fail(f"{path} exists: continue the run it holds with --resume {path}, or remove it (or name another "
                   "--checkpoint) to start a new run")


def write_summary(path: Path | None, summary: Mapping[str, Any]) -> None:
    """Write the run's summary as JSON (atomically) if a path was given."""
    if path is not None:
        atomic_write_json(path, dict(summary))
        console.print(f"summary written to [bold]{path}[/]")


@contextmanager
def progress_bar(description: str, total: float):
    """A rich progress bar on stderr; yields a function ``advance(amount)``."""
    columns = (
        TextColumn("[progress.description]{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TimeElapsedColumn(),
        TimeRemainingColumn(),
    )
    with Progress(*columns, console=error_console, transient=False) as progress:
        task = progress.add_task(description, total=total)
        yield lambda amount=1: progress.advance(task, amount)


def print_table(title: str, columns: Iterable[str], rows: Iterable[Iterable[Any]]) -> None:
    """Print a rich table with the given column headers and rows."""
    table = Table(title=title)
    for column in columns:
        table.add_column(column)
    for row in rows:
        table.add_row(*(str(cell) for cell in row))
    console.print(table)
