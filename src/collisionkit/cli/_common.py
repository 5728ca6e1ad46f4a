"""Conventions shared by every ``collisionkit`` subcommand.

* options on the command line or in a TOML file (``--config``), with the
  same names (``packing-fraction`` or ``packing_fraction``); the command line
  wins; unknown keys and bad values are reported clearly and exit with 2;
* every path checked before any work (:mod:`._files`): inputs exist and are
  files, outputs can be written, no two name the same file, and no existing
  file is replaced without ``--overwrite``;
* ``--summary FILE.json`` writes the run's results atomically;
* a rich progress bar on stderr for anything longer than a second.
"""

from __future__ import annotations

import difflib
import importlib.util
import re
import tomllib
from collections.abc import Collection, Iterable, Mapping
from contextlib import contextmanager
from pathlib import Path
import types
from typing import Annotated, Any, ClassVar, Union, get_args, get_origin

import typer
from pydantic import BaseModel, ConfigDict, ValidationError, model_validator
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn, TimeRemainingColumn
from rich import box
from rich.table import Table

from ._files import (
    Deliveries, check_input_file, check_output_file, check_output_folder, refuse_clashes, refuse_folder,
    refuse_earlier_run, refuse_to_replace,
)
from ._messages import (
    BAD_INPUT_EXIT_CODE, INTERRUPTED_EXIT_CODE, RUN_FAILED_EXIT_CODE, console, error, error_console, fail, note,
    run_failed, say, warn,
)

__all__ = [
    "BAD_INPUT_EXIT_CODE", "INTERRUPTED_EXIT_CODE", "RUN_FAILED_EXIT_CODE", "Deliveries", "Options",
    "check_input_file", "check_paths",
    "check_output_file", "check_output_folder", "console", "error", "error_console", "fail", "fraction_reporter",
    "load_options", "note",
    "option_values", "OverwriteOption", "print_table", "refuse_folder", "progress_bar", "read_toml", "refuse_clashes", "refuse_to_replace", "require",
    "require_gsd", "require_plotting", "run_failed", "say", "validate_options", "warn", "write_summary",
]


OverwriteOption = Annotated[bool | None, typer.Option(
    "--overwrite", help="Let the outputs replace existing files; without it the command stops before any work.")]


def _dashed(name: str) -> str:
    return name.replace("_", "-")


def fail_for_option(error: Exception, model: type[Options], renamed: Mapping[str, str] | None = None) -> typer.Exit:
    """:func:`fail` with a library error, the parameter its message starts with named as its option.

    Examples
    --------
    >>> class Run(Options):
    ...     packing_fraction: float = 0.3
    >>> fail_for_option(ValueError("packing_fraction must lie in (0, 0.5]; got 0.6"), Run).exit_code
    2
    """
    return fail(named_as_option(str(error), model, renamed))


def named_as_option(message: str, model: type[Options], renamed: Mapping[str, str] | None = None) -> str:
    """``message`` with the library parameter it starts with (if an option of ``model``) written as the option.

    The library names its arguments (``packing_fraction must lie in ...``);
    the user gave an option (``--packing-fraction``). ``renamed`` maps a
    library name to the option's field where they differ (``v_inf``: ``vinf``).

    Examples
    --------
    >>> class Run(Options):
    ...     packing_fraction: float = 0.3
    >>> named_as_option("packing_fraction must lie in (0, 0.5]; got 0.6", Run)
    '--packing-fraction must lie in (0, 0.5]; got 0.6'
    >>> named_as_option("k must be finite", Run)
    'k must be finite'
    >>> named_as_option("these pick gases from LXCat files (packing_fraction)", Run)
    'these pick gases from LXCat files (--packing-fraction)'
    >>> class Gas(Options):
    ...     species: list[str] | None = None
    ...     fractions: list[float] | None = None
    >>> named_as_option("species and fractions pick gases", Gas)
    '--species and --fractions pick gases'
    >>> named_as_option("species and atoms differ", Gas)  # not all options: only the first word is one
    '--species and atoms differ'
    """

    def flag(name: str) -> str | None:
        name = (renamed or {}).get(name, name)
        return model.flags.get(name, f"--{_dashed(name)}") if name in model.model_fields else None

    # a library argument named alone in parentheses: "... from LXCat files (cross_sections)"
    message = re.sub(r"\(([A-Za-z_][A-Za-z0-9_]*)\)", lambda found: f"({flag(found.group(1)) or found.group(1)})",
                     message)
    # the arguments it starts with: "packing_fraction must ...", "species, fractions and database pick ..."
    word = r"[A-Za-z_][A-Za-z0-9_]*"
    listed = re.match(rf"{word}(?:, {word})*(?: and {word})?(?![A-Za-z0-9_])", message)
    names = re.findall(word, listed.group().replace(" and ", ", ")) if listed else []
    if not names or flag(names[0]) is None:
        return message
    if any(flag(name) is None for name in names):  # "k and c must ..." with c not an option: only the first
        listed = re.match(word, message)
    return re.sub(word, lambda found: flag(found.group()) or found.group(), listed.group()) + message[listed.end():]


class Options(BaseModel):
    """Base of every subcommand's options: strict, dashed keys allowed.

    ``output_files`` and ``output_folders`` name the options that are paths
    the command writes, ``input_files`` those it reads; :func:`load_options`
    checks them before any work. ``overwrite`` lets the outputs replace
    existing files.

    Examples
    --------
    >>> class Run(Options):
    ...     particles: int = 500
    >>> Run.model_validate({"particles": 100}).overwrite
    False
    """

    model_config = ConfigDict(extra="forbid", alias_generator=_dashed, populate_by_name=True, frozen=True)
    output_files: ClassVar[tuple[str, ...]] = ("summary",)
    output_folders: ClassVar[tuple[str, ...]] = ()
    input_files: ClassVar[tuple[str, ...]] = ()
    # the command-line spelling of options whose flag is not ``--`` and the dashed name (``--E-N`` for ``e_n``)
    flags: ClassVar[dict[str, str]] = {}
    # number options a config file may also give in the command line's text forms (``E-N = "1:1000:7:log"``)
    text_forms: ClassVar[tuple[str, ...]] = ()
    # (choices, group): when the command line gives any of the choices, the config file's whole group is dropped
    # (``--gas Ar`` replaces a config's ``model``, and its ``species`` and ``fractions`` with it)
    chosen_together: ClassVar[tuple[tuple[tuple[str, ...], tuple[str, ...]], ...]] = ()
    # options that qualify another in a config file: dropped with it (a config's ``species`` pick from its own
    # ``cross_sections``; with no ``cross_sections`` of its own they pick from the command line's files)
    goes_with: ClassVar[dict[str, tuple[str, ...]]] = {}

    overwrite: bool = False

    def folder_files(self, folder: str) -> tuple[str, ...]:
        """The names of the files this run may write in output folder ``folder`` (refused if there already).

        Examples
        --------
        >>> Options().folder_files("out")
        ()
        """
        return ()

    def unwritten(self) -> set[str]:
        """The output options this run will not write (``--out`` with ``--no-plots``): not checked.

        Examples
        --------
        >>> Options().unwritten()
        set()
        """
        return set()

    @model_validator(mode="before")
    @classmethod
    def _no_loose_types(cls, values: Any) -> Any:
        """Refuse what pydantic would coerce: a bool or a string for a number, a non-bool for a flag.

        (``seed = true`` became seed 1, ``packing-fraction = "0.3"`` 0.3, ``plots = "yes"`` True and
        ``E-N = ["5"]`` [5.0].) A single value of a list option (``E-N = 5``, ``species = "Ar"``) is a list of one.
        Options in ``text_forms`` take the command line's text forms too (``E-N = "1:1000:7:log"``): their own
        validators parse them.
        """
        if not isinstance(values, dict):
            return values
        values = dict(values)
        for key, value in values.items():
            field = cls.model_fields.get(key) or cls.model_fields.get(str(key).replace("-", "_"))
            if field is None or str(key).replace("-", "_") in cls.text_forms:
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


def read_toml(path: Path, option: str = "--config") -> dict[str, Any]:
    """Read a TOML options file; a missing, unreadable or malformed file is an input error (exit 2).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "run.toml"
    >>> _ = path.write_text("particles = 108\\n")
    >>> read_toml(path)
    {'particles': 108}
    """
    path = Path(path)
    if path.is_dir():
        raise fail(f"{option} {path} is a folder, not a file")
    try:
        with open(path, "rb") as stream:
            return tomllib.load(stream)
    except FileNotFoundError:
        raise fail(f"config file not found: {path}") from None
    except UnicodeDecodeError as failure:
        raise fail(f"config file {path} is not UTF-8 text ({failure.reason} at byte {failure.start})") from None
    except tomllib.TOMLDecodeError as failure:
        raise fail(f"config file {path} is not valid TOML: {failure}") from None
    except OSError as failure:
        raise fail(f"config file {path} cannot be read: {failure.strerror or failure}") from None


def _describe(error: Mapping[str, Any], model: type[Options] | None = None) -> str:
    """One line for one pydantic error; a rule between options speaks for itself (no echo of every value).

    An unknown option of ``model`` comes with the closest valid names and the list of them all.

    Examples
    --------
    >>> class Run(Options):
    ...     particles: int = 500
    ...     plots: bool = True
    >>> _describe({"loc": ("particle",), "type": "extra_forbidden", "msg": "", "input": 100}, Run)
    "unknown option 'particle'; did you mean 'particles'? (options: overwrite, particles, plots)"
    >>> _describe({"loc": ("particles",), "type": "greater_than", "msg": "Input should be greater than 0", "input": -1}, Run)
    '--particles: Input should be greater than 0 (got -1)'
    """
    where = ".".join(str(part) for part in error["loc"])
    if error["type"] != "extra_forbidden" and model is not None and where in model.model_fields:
        where = model.flags.get(where, f"--{_dashed(where)}")  # as the user wrote it (a TOML key drops the --)
    if error["type"] == "extra_forbidden":
        where = _dashed(where)  # as a config file may spell it (the command line's flags are checked by typer)
        if model is None:
            return f"unknown option {where!r}"
        names = sorted(_dashed(name) for name in model.model_fields)
        switched = where.removeprefix("no-").replace("-", "_")
        if where.startswith("no-") and model.model_fields.get(switched) is not None and \
                model.model_fields[switched].annotation is bool:  # --no-plots on the command line: plots = false
            return (f"unknown option {where!r}; did you mean '{_dashed(switched)} = false'? "
                    f"(options: {', '.join(names)})")
        close = difflib.get_close_matches(where, names, n=3)
        guess = f"; did you mean {' or '.join(repr(name) for name in close)}?" if close else ""
        return f"unknown option {where!r}{guess} (options: {', '.join(names)})"
    if error["type"] == "value_error":  # our own rules: their message without pydantic's "Value error, "
        message = str(error["ctx"]["error"])
        if where:
            return f"{where}: {message} (got {error.get('input')!r})"
        return message if model is None else named_as_option(message, model)
    bounded = _range_of(model, error["loc"]) if error["type"] in _BOUND_ERRORS else None
    if bounded is not None:
        return f"{where}: must be {bounded}; got {_number_text(error.get('input'))}"
    return f"{where or 'options'}: {error['msg']} (got {error.get('input')!r})"


_BOUND_ERRORS = ("greater_than", "greater_than_equal", "less_than", "less_than_equal")


def _number_text(value: Any) -> str:
    """An int as it is, a float as %g (1e+07, 0.5), anything else as its repr."""
    if isinstance(value, float):
        return f"{value:g}"
    return str(value) if isinstance(value, int) else repr(value)


def _range_of(model: type[Options] | None, loc: tuple) -> str | None:
    """The whole range of an option with a lower and an upper bound ("from 50 to 100000", "above 0 and at most
    0.5"), from the model's field constraints; None for an option with one bound or none.

    Examples
    --------
    >>> from pydantic import Field
    >>> class Run(Options):
    ...     cells: int = Field(default=1000, ge=50, le=100_000)
    ...     tolerance: float = Field(default=0.01, gt=0, le=0.5)
    ...     seed: int = Field(default=1, ge=0)
    >>> _range_of(Run, ("cells",)), _range_of(Run, ("tolerance",)), _range_of(Run, ("seed",))
    ('from 50 to 100000', 'above 0 and at most 0.5', None)
    """
    if model is None or len(loc) != 1 or loc[0] not in model.model_fields:
        return None
    bounds = {}
    for constraint in model.model_fields[loc[0]].metadata:
        for kind in ("ge", "gt", "le", "lt"):
            if getattr(constraint, kind, None) is not None:
                bounds[kind] = _number_text(getattr(constraint, kind))
    low = "ge" if "ge" in bounds else "gt" if "gt" in bounds else None
    high = "le" if "le" in bounds else "lt" if "lt" in bounds else None
    if low is None or high is None:
        return None
    if (low, high) == ("ge", "le"):
        return f"from {bounds['ge']} to {bounds['le']}"
    lower = f"at least {bounds['ge']}" if low == "ge" else f"above {bounds['gt']}"
    upper = f"at most {bounds['le']}" if high == "le" else f"below {bounds['lt']}"
    return f"{lower} and {upper}"


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
    """The options a TOML file and the command line set, by field name, not yet validated (the command line wins).

    A choice the command line makes replaces the config file's whole group
    (``model.chosen_together``): ``--gas Ar`` drops a config's ``model``,
    ``species`` and ``fractions`` instead of clashing with them. A config
    option dropped takes the options that qualify it along
    (``model.goes_with``): ``--cross-sections b.txt`` drops a config's
    ``cross_sections`` with the ``species`` that picked from them.

    Examples
    --------
    >>> from typing import ClassVar
    >>> class Run(Options):
    ...     model: str | None = None
    ...     gas: str | None = None
    ...     chosen_together: ClassVar = ((("model", "gas"), ("model", "gas")),)
    >>> import pathlib, tempfile
    >>> config = pathlib.Path(tempfile.mkdtemp()) / "run.toml"
    >>> _ = config.write_text('model = "reid"\\n')
    >>> option_values(Run, config, {"gas": "Ar", "model": None})
    {'gas': 'Ar'}
    >>> class Files(Options):
    ...     files: list[str] | None = None
    ...     species: list[str] | None = None
    ...     chosen_together: ClassVar = ((("files",), ("files",)),)
    ...     goes_with: ClassVar = {"files": ("species",)}
    >>> _ = config.write_text('files = ["a.txt"]\\nspecies = ["N2"]\\n')
    >>> option_values(Files, config, {"files": ["b.txt"]})
    {'files': ['b.txt']}
    >>> _ = config.write_text('species = ["N2"]\\n')  # for whatever files the command line names
    >>> option_values(Files, config, {"files": ["b.txt"]})
    {'species': ['N2'], 'files': ['b.txt']}
    """
    values: dict[str, Any] = {}
    if config is not None:
        spelled: dict[str, str] = {}
        for key, value in read_toml(config).items():
            name = _field_name(model, key)
            if name in spelled:
                raise fail(f"config file {config} sets {name!r} twice: as {spelled[name]!r} and as {key!r}")
            spelled[name] = key
            values[name] = value
    given = {key: value for key, value in given.items() if value is not None}
    for choices, group in model.chosen_together:
        if any(name in given for name in choices):
            for name in group:
                if name in values:
                    del values[name]
                    for qualifier in model.goes_with.get(name, ()):
                        values.pop(qualifier, None)
    values.update(given)
    return values


def validate_options(model: type[Options], values: Mapping[str, Any], keep: Collection[Path] = ()):
    """Validate option values (exit 2 naming each bad one) and check every path before any work.

    Inputs must be files; outputs must be writable, each its own file, and
    new unless ``--overwrite`` (or resolved in ``keep``: what a resumed run
    writes on).
    """
    try:
        options = model.model_validate(dict(values))
    except ValidationError as failure:
        details = "; ".join(_describe(item, model) for item in failure.errors())
        raise fail(f"invalid options: {details}") from None
    check_paths(options, keep)
    return options


def check_paths(options: Options, keep: Collection[Path] = ()) -> None:
    """Check the paths of validated options: inputs, outputs, clashes, existing files (exit 2 at the first problem).

    Examples
    --------
    >>> from typing import ClassVar
    >>> class Run(Options):
    ...     summary: Path | None = None
    ...     checkpoint: Path | None = None
    ...     output_files: ClassVar = ("summary", "checkpoint")
    >>> try:
    ...     check_paths(Run(summary="run.npz", checkpoint="run.npz"))
    ... except Exception as stop:
    ...     print(type(stop).__name__, stop.exit_code)
    Exit 2
    """
    model = type(options)
    for name in model.input_files:
        value = getattr(options, name)
        for path in value if isinstance(value, (list, tuple)) else [value]:  # a repeated option: each file
            check_input_file(path, f"--{_dashed(name)}")
    outputs = {f"--{_dashed(name)}": getattr(options, name) for name in model.output_files}
    folders = {f"--{_dashed(name)}": getattr(options, name) for name in model.output_folders
               if name not in options.unwritten()}
    for option, path in outputs.items():
        check_output_file(path, option)
    for option, path in folders.items():
        check_output_folder(path, option)
    refuse_clashes(outputs | folders)
    refuse_files_of_folders(options, outputs)
    keep = {Path(path).resolve() for path in keep}
    for option, path in outputs.items():
        refuse_to_replace(path, option, options.overwrite, keep)
    if not keep:  # a resumed run finishes what it started, in its folders
        for name in model.output_folders:
            if name not in options.unwritten():
                refuse_earlier_run(getattr(options, name), f"--{_dashed(name)}", options.folder_files(name),
                                   options.overwrite)


def refuse_files_of_folders(options: Options, outputs: Mapping[str, Path | None]) -> None:
    """Stop (exit 2) if an output file (``{"--summary": path}``) is one of the files an output folder's run writes.

    ``--out fresh --summary fresh/boltzmann.csv`` would have the table and
    the summary replace each other; no file is written before this check.

    Examples
    --------
    >>> from typing import ClassVar
    >>> class Run(Options):
    ...     out: Path | None = None
    ...     summary: Path | None = None
    ...     output_folders: ClassVar = ("out",)
    ...     def folder_files(self, folder):
    ...         return ("table.csv",)
    >>> refuse_files_of_folders(Run(out="plots", summary="plots/summary.json"), {"--summary": Path("plots/summary.json")})
    >>> try:
    ...     refuse_files_of_folders(Run(out="plots"), {"--summary": Path("plots/table.csv")})
    ... except Exception as stop:
    ...     print(type(stop).__name__, stop.exit_code)
    Exit 2
    """
    for name in type(options).output_folders:
        folder = getattr(options, name)
        if folder is None or name in options.unwritten():
            continue
        written = {(Path(folder) / file).resolve(): file for file in options.folder_files(name)}
        for option, path in outputs.items():
            if path is not None and Path(path).resolve() in written:
                raise fail(f"{option} {path} is the file {written[Path(path).resolve()]} that --{_dashed(name)} "
                           f"{folder} writes: one would replace the other; name another file for {option}")


def _field_name(model: type[Options], key: str) -> str:
    """The option a TOML key names: dashes or underscores, and the command line's case (E-N for e_n)."""
    name = key.replace("-", "_")
    return name.lower() if name not in model.model_fields and name.lower() in model.model_fields else name


def write_summary(path: Path | None, summary: Mapping[str, Any], command: str) -> None:
    """Write the run's summary as JSON (atomically) if a path was given; if that fails, rescue it and exit 1.

    Examples
    --------
    >>> write_summary(None, {"transmission": 0.5}, "slab")  # no --summary: nothing to write
    """
    Deliveries(command).finish(path, summary)


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


def fraction_reporter(advance, total: float):
    """A library ``progress(fraction)`` callback that advances a :func:`progress_bar` of ``total`` steps."""
    shown = [0.0]

    def report(fraction):
        advance(fraction * total - shown[0])
        shown[0] = fraction * total

    return report


def print_table(title: str, columns: Iterable[str], rows: Iterable[Iterable[Any]]) -> None:
    """Print a rich table with the given column headers and rows, every character of every cell shown.

    A console too narrow for the table (``COLUMNS=60``; stdout redirected
    to a file: 80 columns) wraps a cell at its spaces, each column at least
    as wide as its longest word; if even that does not fit in boxes, the
    table drops its borders and padding, and only if that does not fit
    either a word longer than its column folds onto the next line. No
    number is ever cut short with an ellipsis ("6.1541e…").

    Examples
    --------
    In 15 characters the two columns below get 5 and 10: "6.1541e+04" whole, the header wrapped at its
    space (the output itself depends on the terminal, so the example shows the widths):

    >>> _column_widths(["E/N (Td)", "W (m/s)"], [["10", "6.1541e+04"]], 15)
    [5, 10]
    """
    headers = [str(column) for column in columns]
    cells = [[str(cell) for cell in row] for row in rows]
    boxed = dict(box=box.HEAVY_HEAD), len(headers) + 1 + 2 * len(headers)  # the borders and a space each side
    compact = dict(box=box.SIMPLE_HEAD, show_edge=False, padding=0), len(headers) - 1  # a space between columns
    for (style, spacing) in (boxed, compact):
        widths = _column_widths(headers, cells, console.width - spacing)
        if widths is not None:
            break
    table = Table(title=title, **style)
    for header, width in zip(headers, widths or [None] * len(headers)):
        table.add_column(header, overflow="fold", width=width)
    for row in cells:
        table.add_row(*row)
    console.print(table)


def _column_widths(headers: list[str], rows: list[list[str]], room: int) -> list[int | None] | None:
    """Widths of the columns that keep every word whole in ``room`` characters: None each if every column fits as
    it is (rich lays it out), None if the longest words alone do not fit."""
    columns = list(zip(headers, *rows))
    natural = [max(len(text) for text in column) for column in columns]
    if sum(natural) <= room:
        return [None] * len(columns)
    widths = [max(len(word) for text in column for word in [*text.split(), ""]) for column in columns]
    if sum(widths) > room:
        return None
    spare = room - sum(widths)
    while spare > 0 and widths != natural:  # the room left, a character at a time to each column still wrapping
        for index, width in enumerate(widths):
            if spare > 0 and width < natural[index]:
                widths[index] += 1
                spare -= 1
    return widths
