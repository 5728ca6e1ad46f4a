"""Parameter sweeps and ensembles of ``collisionkit`` subcommands.

A *study* names a subcommand (``edmd``, ``encounter``, ``swarm``, ``slab``,
...), its fixed options, the options to vary and the number of replicas::

    command = "edmd"
    replicas = 2
    seed = 1
    [fixed]
    dim = 3
    particles = 500
    collisions = 20000
    [vary]
    packing-fraction = [0.1, 0.2, 0.3]              # a list
    # restitution = {start = 0.8, stop = 1.0, num = 3}   # num values, both ends included
    # particles = {start = 100, stop = 400, step = 100}  # start, start + step, ... <= stop
    # zip = [["a", "b"]] at the top level varies a and b together instead of crosswise

The points are the cartesian product of the varied options (keys of a
``zip`` group advance together). Every point and replica runs the
subcommand in-process with ``--summary`` (and ``--out``, ``--no-plots``
where the command has them) in its own folder ``OUT/points/pNNNN-rNN``, with
its own seed from :class:`numpy.random.SeedSequence` (spawn key
``(point, replica)`` under the study's root seed), so the numbers do not
depend on the number of workers or the order of execution.

Each point's ``result.json`` is written atomically as soon as it finishes;
:func:`run_study` with ``resume=True`` skips the points that finished and
reruns the others (the failed ones too). At the end the study folder gets
``results.csv`` (one row per point and replica), ``results.parquet`` when
``pyarrow`` is installed, and ``main_result.png`` (the main result against
the first varied option, error bars across replicas) when matplotlib is.

Points run on any :class:`concurrent.futures.Executor` or on a
``dask.distributed.Client``; by default on an embedded ``LocalCluster``
(``pip install 'collisionkit[cluster]'``). Within one process points run
one at a time (the subcommands share the process's consoles): use worker
processes for parallelism.
"""

from __future__ import annotations

import concurrent.futures
import contextlib
import csv
import hashlib
import io
import json
import math
import os
import threading
import time
import tomllib
import traceback
from collections.abc import Callable, Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ._io import atomic_write_bytes, atomic_write_json, atomic_write_text

__all__ = [
    "MAIN_RESULTS",
    "PointTask",
    "Study",
    "StudyResults",
    "aggregate",
    "check_command",
    "check_folder",
    "command_options",
    "expand",
    "load_study",
    "local_client",
    "point_name",
    "point_seed",
    "point_tasks",
    "run_point",
    "run_study",
    "results_table",
    "study_from_dict",
    "write_csv",
    "write_outputs",
    "write_parquet",
]

RESULT_FORMAT = 1
STUDY_KEYS = ("command", "replicas", "seed", "fixed", "vary", "zip", "main")
RANGE_KEYS = {"start", "stop", "num", "step", "log"}
MAX_REPLICAS = 100_000
MAX_RANGE_VALUES = 100_000  # values of one range: more is a typo (a step of 1e-9), and would take minutes to list
SIGNIFICANT_DIGITS = 12
MAIN_RESULTS = {
    "edmd": "compressibility_factor",
    "swarm": "mean_energy",
    "slab": "transmission",
    "encounter": "orbit.deflection_angle",
}
NOT_SWEPT = ("sweep",)
SET_BY_THE_SWEEP = ("summary", "out", "config", "resume", "help")
TABLE_COLUMNS = ("point", "replica", "seed", "spawn_key", "status", "error", "elapsed")
RESULT_FILE = "result.json"
STUDY_FILE = "study.json"


# ------------------------------------------------------------------ the study


def _dashed(key: str) -> str:
    return key.replace("_", "-")


@dataclass(frozen=True)
class Study:
    """A validated study: a subcommand, fixed and varied options, replicas and a root seed.

    Option names are stored dashed (``packing-fraction``); varied values
    are stored expanded (ranges become tuples of values).

    Parameters
    ----------
    command : str
        Name of a ``collisionkit`` subcommand.
    seed : int
        Root seed (>= 0) of the study's :class:`numpy.random.SeedSequence`.
    vary : mapping of str to sequence
        Options to vary and their values (at least one option, no empty list).
    fixed : mapping of str to value, optional
        Options shared by every point.
    replicas : int, optional
        Independent runs per point (1 to 100000), each with its own seed.
    zip : sequence of sequences of str, optional
        Groups of varied options that advance together (same lengths).
    main : str, optional
        Summary key plotted against the varied option (dotted for nested
        keys); default from :data:`MAIN_RESULTS`.

    Examples
    --------
    >>> study = Study("edmd", seed=1, vary={"packing_fraction": [0.1, 0.2]}, replicas=2)
    >>> study.vary
    {'packing-fraction': (0.1, 0.2)}
    >>> study.main, len(expand(study))
    ('compressibility_factor', 2)
    """

    command: str
    seed: int
    vary: Mapping[str, Any]
    fixed: Mapping[str, Any] = field(default_factory=dict)
    replicas: int = 1
    zip: tuple[tuple[str, ...], ...] = ()
    main: str | None = None

    def __post_init__(self):
        _check_name("command", self.command)
        _check_integer("seed", self.seed, 0, None)
        _check_integer("replicas", self.replicas, 1, MAX_REPLICAS)
        fixed = _dashed_mapping("fixed", self.fixed)
        vary = {key: _expand_values(key, values) for key, values in _dashed_mapping("vary", self.vary).items()}
        if not vary:
            raise ValueError("vary must name at least one option to vary (e.g. packing-fraction = [0.1, 0.2])")
        for key, value in fixed.items():
            _check_scalar(f"fixed.{key}", value)
        both = sorted(set(fixed) & set(vary))
        if both:
            raise ValueError(f"options {both} are both fixed and varied; keep each in one table")
        groups = _check_zip(self.zip, vary)
        main = self.main if self.main is not None else MAIN_RESULTS.get(self.command)
        if main is not None:
            _check_name("main", main)
        object.__setattr__(self, "fixed", fixed)
        object.__setattr__(self, "vary", vary)
        object.__setattr__(self, "zip", groups)
        object.__setattr__(self, "main", main)

    def to_dict(self) -> dict[str, Any]:
        """The study as plain data (TOML/JSON shaped, ranges expanded).

        Examples
        --------
        >>> Study("encounter", seed=0, vary={"vinf": [0.5, 1.0]}).to_dict()["vary"]
        {'vinf': [0.5, 1.0]}
        """
        return {
            "command": self.command,
            "replicas": self.replicas,
            "seed": self.seed,
            "fixed": dict(self.fixed),
            "vary": {key: list(values) for key, values in self.vary.items()},
            "zip": [list(group) for group in self.zip],
            "main": self.main,
        }

    def fingerprint(self) -> str:
        """A short hash of the study, identical for identical studies.

        Examples
        --------
        >>> a = Study("encounter", seed=0, vary={"vinf": [0.5, 1.0]})
        >>> a.fingerprint() == Study("encounter", seed=0, vary={"vinf": {"start": 0.5, "stop": 1, "num": 2}}).fingerprint()
        True
        >>> a.fingerprint() == Study("encounter", seed=1, vary={"vinf": [0.5, 1.0]}).fingerprint()
        False
        """
        text = json.dumps(self.to_dict(), sort_keys=True)
        return hashlib.sha256(text.encode("utf-8")).hexdigest()[:16]


def _check_name(name: str, value: Any) -> None:
    if not isinstance(value, str) or not value:
        raise TypeError(f"{name} must be a non-empty string; got {value!r}")


def _check_integer(name: str, value: Any, low: int, high: int | None) -> None:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be an integer; got {value!r}")
    if value < low or (high is not None and value > high):
        allowed = f">= {low}" if high is None else f"in [{low}, {high}]"
        raise ValueError(f"{name} must be {allowed}; got {value}")


def _check_scalar(name: str, value: Any) -> None:
    if isinstance(value, float) and not math.isfinite(value):
        raise ValueError(f"{name} must be finite; got {value}")
    if not isinstance(value, (bool, int, float, str)):
        raise TypeError(f"{name} must be a number, a string or a boolean; got {value!r}")


def _dashed_mapping(name: str, values: Any) -> dict[str, Any]:
    if not isinstance(values, Mapping):
        raise TypeError(f"{name} must be a table of option = value; got {values!r}")
    result: dict[str, Any] = {}
    for key, value in values.items():
        _check_name(f"a key of {name}", key)
        dashed = _dashed(key)
        if dashed in result:
            raise ValueError(f"{name} names {dashed!r} twice (dashes and underscores are the same)")
        result[dashed] = value
    return result


def _tidy(value: float) -> float:
    """Round to 12 significant digits, so that 0.1 + 2 * 0.1 is 0.3."""
    return float(f"{value:.{SIGNIFICANT_DIGITS}g}")


def _range_by_count(name: str, start: float, stop: float, num: Any, log: bool) -> tuple:
    _check_integer(f"vary.{name}.num", num, 1, MAX_RANGE_VALUES)
    if log:
        if start <= 0 or stop <= 0:
            raise ValueError(f"vary.{name}: a log range needs start > 0 and stop > 0; got {start}, {stop}")
        values = np.geomspace(start, stop, num)
    else:
        values = np.linspace(start, stop, num)
    return tuple(_tidy(value) for value in values)


def _range_by_step(name: str, start: float, stop: float, step: Any) -> tuple:
    _check_number(f"vary.{name}.step", step)
    if step == 0 or (stop - start) * step < 0:
        raise ValueError(f"vary.{name}.step must be non-zero and lead from start to stop; got {step}")
    count = math.floor((stop - start) / step * (1 + 1e-12) + 1e-9) + 1
    if count > MAX_RANGE_VALUES:
        raise ValueError(f"vary.{name}: step {step} gives {count} values from {start} to {stop}; "
                         f"at most {MAX_RANGE_VALUES}")
    if all(isinstance(value, int) for value in (start, stop, step)):
        return tuple(start + k * step for k in range(count))
    return tuple(_tidy(start + k * step) for k in range(count))


def _check_number(name: str, value: Any) -> None:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise TypeError(f"{name} must be a finite number; got {value!r}")


def _expand_range(name: str, spec: Mapping[str, Any]) -> tuple:
    unknown = sorted(set(spec) - RANGE_KEYS)
    if unknown:
        raise ValueError(f"vary.{name}: unknown range keys {unknown}; use start, stop and num (or step), log")
    if "start" not in spec or "stop" not in spec or ("num" in spec) == ("step" in spec):
        raise ValueError(f"vary.{name}: a range needs start, stop and exactly one of num or step")
    start, stop = spec["start"], spec["stop"]
    _check_number(f"vary.{name}.start", start)
    _check_number(f"vary.{name}.stop", stop)
    log = spec.get("log", False)
    if not isinstance(log, bool):
        raise TypeError(f"vary.{name}.log must be true or false; got {log!r}")
    if "num" in spec:
        return _range_by_count(name, start, stop, spec["num"], log)
    if log:
        raise ValueError(f"vary.{name}: log = true needs num, not step")
    return _range_by_step(name, start, stop, spec["step"])


def _expand_values(name: str, values: Any) -> tuple:
    if isinstance(values, Mapping):
        return _expand_range(name, values)
    if isinstance(values, (list, tuple)):
        if not values:
            raise ValueError(f"vary.{name} is an empty list; give at least one value")
        for value in values:
            _check_scalar(f"vary.{name}", value)
        return tuple(values)
    raise TypeError(f"vary.{name} must be a list or a range {{start, stop, num or step}}; got {values!r}")


def _check_zip(groups: Any, vary: Mapping[str, tuple]) -> tuple[tuple[str, ...], ...]:
    if not isinstance(groups, (list, tuple)):
        raise TypeError(f"zip must be a list of lists of varied options; got {groups!r}")
    seen: set[str] = set()
    result = []
    for group in groups:
        if not isinstance(group, (list, tuple)) or len(group) < 2:
            raise ValueError(f"each zip group must list at least two varied options; got {group!r}")
        names = tuple(_dashed(str(name)) for name in group)
        for name in names:
            if name not in vary:
                raise ValueError(f"zip names {name!r}, which is not in vary")
            if name in seen:
                raise ValueError(f"zip names {name!r} in more than one group (or twice)")
            seen.add(name)
        lengths = {name: len(vary[name]) for name in names}
        if len(set(lengths.values())) != 1:
            raise ValueError(f"the options of a zip group need the same number of values; got {lengths}")
        result.append(names)
    return tuple(result)


def study_from_dict(data: Mapping[str, Any]) -> Study:
    """Build a :class:`Study` from TOML-shaped data, rejecting unknown keys.

    Parameters
    ----------
    data : mapping
        Keys ``command``, ``seed``, ``vary`` (required), ``replicas``,
        ``fixed``, ``zip``, ``main`` (optional).

    Examples
    --------
    >>> study = study_from_dict({"command": "edmd", "seed": 3, "vary": {"dim": [2, 3]}})
    >>> study.replicas
    1
    >>> study_from_dict({"command": "edmd", "seed": 3, "vary": {"dim": [2]}, "replica": 2})
    Traceback (most recent call last):
    ...
    ValueError: unknown study key 'replica'; allowed: command, replicas, seed, fixed, vary, zip, main
    """
    if not isinstance(data, Mapping):
        raise TypeError(f"a study must be a table; got {type(data).__name__}")
    for key in data:
        if key not in STUDY_KEYS:
            raise ValueError(f"unknown study key {key!r}; allowed: {', '.join(STUDY_KEYS)}")
    for key in ("command", "seed", "vary"):
        if key not in data:
            raise ValueError(f"the study needs {key!r} (e.g. command = \"edmd\", seed = 1, [vary] ...)")
    return Study(**{key: data[key] for key in STUDY_KEYS if key in data})


def load_study(path) -> Study:
    """Read a study from a TOML file (see the module's documentation for the format).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "study.toml"
    >>> _ = path.write_text('command = "encounter"\\nseed = 1\\n[vary]\\nvinf = {start = 0.5, stop = 1.5, step = 0.5}\\n')
    >>> load_study(path).vary
    {'vinf': (0.5, 1.0, 1.5)}
    """
    path = Path(path)
    try:
        with open(path, "rb") as stream:
            data = tomllib.load(stream)
    except FileNotFoundError:
        raise ValueError(f"study file not found: {path}") from None
    except tomllib.TOMLDecodeError as error:
        raise ValueError(f"study file {path} is not valid TOML: {error}") from None
    return study_from_dict(data)


# ------------------------------------------------------------------ points and seeds


def expand(study: Study) -> list[dict[str, Any]]:
    """The study's points: one dict of varied option values per point, in a fixed order.

    The cartesian product over the varied options (in the order of
    ``vary``), where the options of a ``zip`` group advance together; the
    last option varies fastest.

    Examples
    --------
    >>> study = Study("edmd", seed=0, vary={"dim": [2, 3], "packing-fraction": [0.1, 0.2]})
    >>> [tuple(point.values()) for point in expand(study)]
    [(2, 0.1), (2, 0.2), (3, 0.1), (3, 0.2)]
    >>> zipped = Study("edmd", seed=0, vary={"dim": [2, 3], "packing-fraction": [0.1, 0.2]},
    ...                zip=[["dim", "packing-fraction"]])
    >>> [tuple(point.values()) for point in expand(zipped)]
    [(2, 0.1), (3, 0.2)]
    """
    axes = _axes(study)
    points = [{}]
    for names in axes:
        columns = [study.vary[name] for name in names]
        points = [point | dict(zip(names, values)) for point in points for values in zip(*columns)]
    return [{name: point[name] for name in study.vary} for point in points]


def _axes(study: Study) -> list[tuple[str, ...]]:
    """The independent axes of the product: zip groups (at their first option) and single options."""
    group_of = {name: group for group in study.zip for name in group}
    axes: list[tuple[str, ...]] = []
    for name in study.vary:
        axis = group_of.get(name, (name,))
        if axis not in axes:
            axes.append(axis)
    return axes


def point_seed(root: int, point: int, replica: int) -> int:
    """The integer seed of a point's replica: ``SeedSequence(root).spawn(...)[point].spawn(...)[replica]``.

    Adding replicas or points to a study does not change the seeds of the
    others; the seed is a 32-bit integer drawn from the child sequence.

    Examples
    --------
    >>> point_seed(1, 0, 0) == point_seed(1, 0, 0) != point_seed(1, 0, 1)
    True
    >>> import numpy as np
    >>> child = np.random.SeedSequence(1).spawn(3)[2].spawn(2)[1]
    >>> child.spawn_key, point_seed(1, 2, 1) == int(child.generate_state(1)[0])
    ((2, 1), True)
    """
    child = np.random.SeedSequence(root, spawn_key=(point, replica))
    return int(child.generate_state(1, dtype=np.uint32)[0])


@dataclass(frozen=True)
class PointTask:
    """One run of the subcommand: a point, a replica, its seed, its folder and its arguments.

    Examples
    --------
    >>> study = Study("encounter", seed=0, vary={"vinf": [0.5, 1.0]})
    >>> task = point_tasks(study, "out", options=ENCOUNTER_LIKE)[1]
    >>> task.name, task.parameters, task.spawn_key
    ('p0001-r00', {'vinf': 1.0}, (1, 0))
    """

    command: str
    index: int
    replica: int
    parameters: Mapping[str, Any]
    seed: int
    spawn_key: tuple[int, int]
    directory: Path
    arguments: tuple[str, ...]

    @property
    def name(self) -> str:
        return point_name(self.index, self.replica)

    @property
    def result_path(self) -> Path:
        return self.directory / RESULT_FILE


def point_name(index: int, replica: int) -> str:
    """The folder name of a point's replica.

    Examples
    --------
    >>> point_name(3, 1)
    'p0003-r01'
    """
    _check_integer("index", index, 0, None)
    _check_integer("replica", replica, 0, None)
    return f"p{index:04d}-r{replica:02d}"


# ------------------------------------------------------------------ the subcommand's options


@dataclass(frozen=True)
class OptionSpec:
    """What the sweep needs to know of one option of a subcommand.

    Examples
    --------
    >>> spec = OptionSpec("plots", "--plots", "--no-plots", is_flag=True, annotation=bool)
    >>> spec.flag, spec.negative_flag, spec.is_flag
    ('--plots', '--no-plots', True)
    """

    name: str
    flag: str
    negative_flag: str | None = None
    is_flag: bool = False
    annotation: Any = None


# a description of the encounter command's options, for cheap doctests without the CLI
ENCOUNTER_LIKE = {
    "vinf": OptionSpec("vinf", "--vinf", annotation=float),
    "out": OptionSpec("out", "--out"),
    "summary": OptionSpec("summary", "--summary"),
    "plots": OptionSpec("plots", "--plots", "--no-plots", is_flag=True, annotation=bool),
}


def command_options(command: str) -> dict[str, OptionSpec]:
    """The options of a registered ``collisionkit`` subcommand, by dashed name.

    Raises
    ------
    ValueError
        If no such subcommand is registered.

    Examples
    --------
    >>> options = command_options("encounter")
    >>> options["vinf"].flag, options["plots"].negative_flag
    ('--vinf', '--no-plots')
    """
    commands = _cli_commands()
    if command not in commands:
        raise ValueError(f"unknown command {command!r}; available: {', '.join(sorted(commands))}")
    return {_dashed(param.name): _option_spec(param) for param in commands[command].params if param.name}


def _cli_commands() -> dict:
    import typer

    from .cli import app

    return dict(typer.main.get_command(app).commands)


def _option_spec(param) -> OptionSpec:
    opts = list(getattr(param, "opts", []) or [f"--{_dashed(param.name)}"])
    secondary = list(getattr(param, "secondary_opts", []) or [])
    annotation = getattr(getattr(param, "type_descriptor", None), "annotation", None)
    return OptionSpec(
        name=param.name,
        flag=max(opts, key=len),
        negative_flag=max(secondary, key=len) if secondary else None,
        is_flag=bool(getattr(param, "is_flag", False)),
        annotation=annotation,
    )


def check_command(study: Study, options: Mapping[str, OptionSpec] | None = None) -> dict[str, OptionSpec]:
    """Check that the study's command exists and accepts every fixed and varied option.

    Parameters
    ----------
    study : Study
    options : mapping, optional
        The command's options (default: read from the ``collisionkit`` CLI).

    Returns
    -------
    dict
        The command's options, as from :func:`command_options`.

    Examples
    --------
    >>> check_command(Study("encounter", seed=0, vary={"vinf": [1.0]}), ENCOUNTER_LIKE)["vinf"].flag
    '--vinf'
    >>> check_command(Study("encounter", seed=0, vary={"speed": [1.0]}), ENCOUNTER_LIKE)
    Traceback (most recent call last):
    ...
    ValueError: command 'encounter' has no option 'speed'; its options: plots, vinf
    """
    if study.command in NOT_SWEPT:
        raise ValueError(f"command {study.command!r} cannot be swept; sweep a simulation command such as edmd")
    options = command_options(study.command) if options is None else dict(options)
    if "summary" not in options:
        raise ValueError(f"command {study.command!r} has no --summary option; the sweep reads each point's results from it")
    allowed = sorted(name for name in options if name not in SET_BY_THE_SWEEP)
    for name, values in [*((key, (value,)) for key, value in study.fixed.items()), *study.vary.items()]:
        if name in SET_BY_THE_SWEEP or (name == "seed" and "seed" in options):
            raise ValueError(f"option {name!r} is set by the sweep for every point; remove it from the study")
        if name not in options:
            raise ValueError(f"command {study.command!r} has no option {name!r}; its options: {', '.join(allowed)}")
        for value in values:
            _check_option_value(options[name], name, value)
    return options


def _check_option_value(option: OptionSpec, name: str, value: Any) -> None:
    expected = option.annotation
    if option.is_flag or expected is bool:
        if not isinstance(value, bool):
            raise TypeError(f"option {name!r} is a switch: give true or false; got {value!r}")
    elif isinstance(value, bool):
        raise TypeError(f"option {name!r} takes a value, not true/false; got {value!r}")
    elif expected is int and not isinstance(value, int):
        raise TypeError(f"option {name!r} takes an integer; got {value!r}")
    elif expected is float and not isinstance(value, (int, float)):
        raise TypeError(f"option {name!r} takes a number; got {value!r}")


def _argument(option: OptionSpec, value: Any, directory: Path) -> list[str]:
    if option.is_flag:
        if value:
            return [option.flag]
        if option.negative_flag is None:
            return []
        return [option.negative_flag]
    if option.annotation is Path and not Path(value).is_absolute():
        return [option.flag, str(directory / value)]  # each point writes its own file
    return [option.flag, repr(value) if isinstance(value, float) else str(value)]


def point_tasks(study: Study, out, options: Mapping[str, OptionSpec] | None = None) -> list[PointTask]:
    """Every run of the study, point by point and replica by replica, with seeds and arguments.

    Parameters
    ----------
    study : Study
    out : path
        The study's folder; the runs go to ``out/points/pNNNN-rNN``
        (absolute: workers elsewhere must see the same path). Options that
        take a file, given as a relative path (e.g. edmd's ``trajectory``),
        go inside each point's folder.
    options : mapping, optional
        The command's options (default: read from the ``collisionkit`` CLI).

    Examples
    --------
    >>> study = Study("encounter", seed=0, vary={"vinf": [0.5, 1.0]}, replicas=2)
    >>> tasks = point_tasks(study, "out", options=ENCOUNTER_LIKE)
    >>> [task.name for task in tasks]
    ['p0000-r00', 'p0000-r01', 'p0001-r00', 'p0001-r01']
    >>> tasks[0].arguments[:3]
    ('encounter', '--vinf', '0.5')
    """
    options = check_command(study, options)
    out = Path(out).absolute()  # workers may run in another directory
    tasks = []
    for index, parameters in enumerate(expand(study)):
        for replica in range(study.replicas):
            seed = point_seed(study.seed, index, replica)
            directory = out / "points" / point_name(index, replica)
            arguments = _arguments(study, options, parameters, seed, directory)
            tasks.append(PointTask(study.command, index, replica, parameters, seed, (index, replica), directory, arguments))
    return tasks


def _arguments(study, options, parameters, seed, directory) -> tuple[str, ...]:
    values = {**study.fixed, **parameters}
    arguments = [study.command]
    for name, value in values.items():
        arguments += _argument(options[name], value, directory)
    if "seed" in options:
        arguments += [options["seed"].flag, str(seed)]
    if "plots" in options and "plots" not in values:
        arguments += _argument(options["plots"], False, directory)
    if "out" in options:
        arguments += [options["out"].flag, str(directory)]
    arguments += [options["summary"].flag, str(directory / "summary.json")]
    return tuple(arguments)


# ------------------------------------------------------------------ running one point

_CONSOLE_LOCK = threading.Lock()


def run_point(task: PointTask) -> dict[str, Any]:
    """Run one point's replica in this process and write its ``result.json`` atomically.

    Never raises for a failing command: a non-zero exit code, an exception
    or a missing summary gives a record with ``status = "failed"`` and the
    error. The command's output goes to ``output.log`` in the point's folder.

    Returns
    -------
    dict
        The record written to ``result.json``: ``status``, ``error``,
        ``exit_code``, ``elapsed`` (wall, s), ``cpu_time`` (of the running
        thread, s), ``summary`` and the task's fields.

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
    started, cpu_started = time.perf_counter(), time.thread_time()
    exit_code, error, output = _invoke(task.arguments)
    elapsed, cpu_time = time.perf_counter() - started, time.thread_time() - cpu_started
    atomic_write_text(task.directory / "output.log", output)
    summary = _read_summary(task.directory / "summary.json") if exit_code == 0 and error is None else None
    if exit_code == 0 and error is None and summary is None:
        error = "the command wrote no readable summary"
    record = _record(task, "ok" if error is None else "failed", error, exit_code, elapsed, summary)
    record["cpu_time"] = cpu_time
    atomic_write_json(task.result_path, record)
    return record


def _invoke(arguments: tuple[str, ...]) -> tuple[int | None, str | None, str]:
    """Run ``collisionkit ARGUMENTS`` in-process: (exit code, error or None, captured output)."""
    buffer = io.StringIO()
    with _CONSOLE_LOCK, contextlib.redirect_stdout(buffer), contextlib.redirect_stderr(buffer):
        try:
            exit_code = _main(list(arguments))
        except SystemExit as stop:
            exit_code = stop.code if isinstance(stop.code, int) else (0 if stop.code is None else 1)
        except Exception as exception:  # the command's failure is the point's result
            buffer.write(traceback.format_exc())
            return getattr(exception, "exit_code", None), f"{type(exception).__name__}: {exception}", buffer.getvalue()
    output = buffer.getvalue()
    if exit_code:
        return exit_code, f"exit code {exit_code}: {_last_lines(output)}", output
    return 0, None, output


def _main(arguments: list[str]) -> int:
    import typer

    from .cli import app

    result = typer.main.get_command(app).main(arguments, standalone_mode=False, prog_name="collisionkit")
    return result if isinstance(result, int) else 0


def _last_lines(output: str, limit: int = 400) -> str:
    text = " ".join(output.split())
    return text if len(text) <= limit else "..." + text[-limit:]


def _read_summary(path: Path) -> dict | None:
    try:
        data = json.loads(path.read_text())
    except (OSError, ValueError):
        return None
    return data if isinstance(data, dict) else None


def _record(task: PointTask, status, error, exit_code, elapsed, summary) -> dict[str, Any]:
    return {
        "format": RESULT_FORMAT,
        "command": task.command,
        "point": task.index,
        "replica": task.replica,
        "name": task.name,
        "parameters": dict(task.parameters),
        "seed": task.seed,
        "spawn_key": list(task.spawn_key),
        "status": status,
        "error": error,
        "exit_code": exit_code,
        "elapsed": elapsed,
        "arguments": list(task.arguments),
        "summary": summary,
    }


def _is_complete(task: PointTask) -> dict | None:
    """The point's saved record if it finished successfully with this task's parameters and seed."""
    record = _read_summary(task.result_path)
    if record is None or record.get("status") != "ok" or record.get("format") != RESULT_FORMAT:
        return None
    same = record.get("seed") == task.seed and record.get("parameters") == json.loads(json.dumps(dict(task.parameters)))
    return record if same and isinstance(record.get("summary"), dict) else None


# ------------------------------------------------------------------ executors


def _is_dask_client(executor) -> bool:
    return type(executor).__module__.split(".")[0] == "distributed"


@contextlib.contextmanager
def local_client(workers: int | None = None):
    """An embedded ``dask.distributed`` cluster of worker processes (one thread each) and its client.

    Parameters
    ----------
    workers : int, optional
        Worker processes (>= 1); default: the machine's cores.

    Yields
    ------
    distributed.Client
        Closed, with the cluster, on leaving the ``with`` block.

    Examples
    --------
    >>> with local_client(workers=1) as client:
    ...     print(client.submit(sum, [1, 2, 3]).result())
    6
    """
    if workers is not None:
        _check_integer("workers", workers, 1, None)
    try:
        from distributed import Client, LocalCluster
    except ImportError:  # pragma: no cover - depends on the installation
        raise ImportError("the embedded cluster needs dask.distributed: pip install 'collisionkit[cluster]'") from None
    count = workers or os.cpu_count() or 1
    with LocalCluster(n_workers=count, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster:
        with Client(cluster) as client:
            yield client


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
        record = _record(task, "failed", f"{type(exception).__name__}: {exception}", None, math.nan, None)
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


def check_folder(study: Study, out, resume: bool = False) -> None:
    """Check that ``out`` can take the study: empty of studies, or (to resume) holding the same study.

    Raises
    ------
    ValueError
        If ``out`` holds a study and ``resume`` is false, or holds another study.

    Examples
    --------
    >>> import tempfile
    >>> check_folder(Study("encounter", seed=0, vary={"vinf": [1.0]}), tempfile.mkdtemp())
    """
    out = Path(out)
    path = out / STUDY_FILE
    if not path.exists():
        return
    if not resume:
        raise ValueError(f"out {out} already holds a study; pass resume=True (--resume) to continue it, or another folder")
    saved = _read_summary(path) or {}
    if saved.get("fingerprint") != study.fingerprint():
        raise ValueError(f"out {out} holds a different study ({path}); resume it with the same study or use another folder")


def _prepare_folder(study: Study, out: Path, resume: bool) -> Path:
    check_folder(study, out, resume)
    return atomic_write_json(out / STUDY_FILE, {"fingerprint": study.fingerprint(), "study": study.to_dict()})


def run_study(study, out, executor=None, workers: int | None = None, resume: bool = False,
              progress: Callable[[dict], Any] | None = None) -> StudyResults:  # fmt: skip
    """Run every point and replica of a study and write the table and the plot.

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
        Continue the study in ``out``: skip the points whose ``result.json``
        is complete, rerun the others. Without it, ``out`` must not hold a study.
    progress : callable, optional
        Called with each point's record as it finishes (skipped ones first).

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
    out = Path(out)
    tasks = point_tasks(study, out)
    files = [_prepare_folder(study, out, resume)]
    done = {task.name: record for task in tasks if resume and (record := _is_complete(task)) is not None}
    for record in done.values():
        _report(progress, record)
    pending = [task for task in tasks if task.name not in done]
    if pending:
        with contextlib.ExitStack() as stack:
            if executor is None:
                executor = stack.enter_context(local_client(workers))
            done |= _execute(executor, pending, progress)
    records = [done[task.name] for task in tasks]
    table = results_table(study, records)
    files += write_outputs(study, out, table)
    return StudyResults(study, records, table, files, skipped=len(tasks) - len(pending))


def _report(progress, record) -> None:
    if progress is not None:
        progress(record)


def _execute(executor, tasks: list[PointTask], progress) -> dict[str, dict]:
    futures, finished = _submit(executor, tasks)
    records: dict[str, dict] = {}
    try:
        for future in finished:
            task = futures[future]
            records[task.name] = _collect(future, task)
            _report(progress, records[task.name])
    finally:
        _cancel(executor, [future for future, task in futures.items() if task.name not in records])
    return records


# ------------------------------------------------------------------ the table, the plot


def _flatten(summary: Mapping[str, Any], prefix: str = "") -> Iterator[tuple[str, Any]]:
    for key, value in summary.items():
        name = f"{prefix}{key}"
        if isinstance(value, Mapping):
            yield from _flatten(value, name + ".")
        elif isinstance(value, (int, float)) and not isinstance(value, bool):
            yield name, value


def results_table(study: Study, records: Iterable[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """One row per point and replica: varied options, sweep columns and the summary's numbers.

    Nested summary keys are joined with dots (``orbit.deflection_angle``);
    booleans, strings and lists are left out. Failed points have empty
    summary columns.

    Examples
    --------
    >>> study = Study("encounter", seed=0, vary={"vinf": [0.5]})
    >>> record = {"point": 0, "replica": 0, "seed": 7, "spawn_key": [0, 0], "status": "ok", "error": None,
    ...           "elapsed": 0.1, "parameters": {"vinf": 0.5}, "summary": {"orbit": {"e": 1.1, "kind": "hyp"}}}
    >>> results_table(study, [record])[0]
    {'vinf': 0.5, 'point': 0, 'replica': 0, 'seed': 7, 'spawn_key': '[0, 0]', 'status': 'ok', 'error': '', 'elapsed': 0.1, 'orbit.e': 1.1}
    """
    rows = []
    for record in records:
        row = {name: record["parameters"][name] for name in study.vary}
        row |= {column: record[column] for column in TABLE_COLUMNS}
        row["spawn_key"] = json.dumps(list(record["spawn_key"]))
        row["error"] = record["error"] or ""
        reserved = set(row)
        row |= {key: value for key, value in _flatten(record["summary"] or {}) if key not in reserved}
        rows.append(row)
    return rows


def _columns(table: list[Mapping[str, Any]]) -> list[str]:
    columns: dict[str, None] = {}
    for row in table:
        columns |= dict.fromkeys(row)
    return list(columns)


def write_csv(path, table: list[Mapping[str, Any]]) -> Path:
    """Write the table as CSV atomically (floats as their shortest exact text; missing cells empty).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> path = write_csv(pathlib.Path(tempfile.mkdtemp()) / "t.csv", [{"a": 0.1, "b": 1}, {"a": 0.2}])
    >>> path.read_text().splitlines()
    ['a,b', '0.1,1', '0.2,']
    """
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=_columns(table), restval="", lineterminator="\n")
    writer.writeheader()
    writer.writerows(table)
    return atomic_write_text(path, buffer.getvalue())


def _arrow_column(values: list[Any]):
    import pyarrow as pa

    present = [value for value in values if value is not None and value != ""]
    if present and all(isinstance(value, int) and not isinstance(value, bool) for value in present):
        return pa.array([value if value in present else None for value in values], pa.int64())
    if present and all(isinstance(value, (int, float)) and not isinstance(value, bool) for value in present):
        return pa.array([None if value is None or value == "" else float(value) for value in values], pa.float64())
    return pa.array([None if value is None else str(value) for value in values], pa.string())


def write_parquet(path, table: list[Mapping[str, Any]]) -> Path | None:
    """Write the table as Parquet atomically if ``pyarrow`` is installed; return None otherwise.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> path = write_parquet(pathlib.Path(tempfile.mkdtemp()) / "t.parquet", [{"a": 0.1, "b": "x"}])
    >>> path is None or path.suffix == ".parquet"
    True
    """
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError:
        return None
    columns = _columns(table)
    arrays = [_arrow_column([row.get(column) for row in table]) for column in columns]
    buffer = io.BytesIO()
    pq.write_table(pa.Table.from_arrays(arrays, names=columns), buffer)
    return atomic_write_bytes(path, buffer.getvalue())


def aggregate(table: Iterable[Mapping[str, Any]], key: str, by: Iterable[str]) -> list[dict[str, Any]]:
    """Mean and standard error across replicas of ``key``, per combination of the ``by`` columns.

    Only successful rows with a finite value count. The standard error is
    ``std(ddof=1) / sqrt(n)``; with one replica it is the row's
    ``<key>_error`` if the summary has one, else NaN.

    Returns
    -------
    list of dict
        The ``by`` values, ``n``, ``mean`` and ``error``, in first-appearance order.

    Examples
    --------
    >>> rows = [{"x": 1, "y": 2.0, "status": "ok"}, {"x": 1, "y": 4.0, "status": "ok"},
    ...         {"x": 2, "y": 5.0, "status": "failed"}]
    >>> aggregate(rows, "y", ["x"])
    [{'x': 1, 'n': 2, 'mean': 3.0, 'error': 1.0}]
    """
    by = list(by)
    groups: dict[tuple, list[Mapping[str, Any]]] = {}
    for row in table:
        value = row.get(key)
        if row.get("status") == "ok" and isinstance(value, (int, float)) and math.isfinite(value):
            groups.setdefault(tuple(row[name] for name in by), []).append(row)
    return [dict(zip(by, values)) | _mean_and_error(rows, key) for values, rows in groups.items()]


def _mean_and_error(rows: list[Mapping[str, Any]], key: str) -> dict[str, Any]:
    values = np.array([row[key] for row in rows], dtype=float)
    if len(values) > 1:
        error = float(values.std(ddof=1) / math.sqrt(len(values)))
    else:
        own = rows[0].get(f"{key}_error")
        error = float(own) if isinstance(own, (int, float)) else math.nan
    return {"n": len(values), "mean": float(values.mean()), "error": error}


def write_outputs(study: Study, out, table: list[Mapping[str, Any]]) -> list[Path]:
    """Write ``results.csv``, ``results.parquet`` (with pyarrow) and ``main_result.png`` (with matplotlib).

    The plot needs the study's main key in at least one successful row.

    Examples
    --------
    >>> import tempfile
    >>> study = Study("encounter", seed=0, vary={"vinf": [1.0, 2.0]}, main="deflection")
    >>> table = [{"vinf": 1.0, "replica": 0, "status": "ok", "deflection": 1.2},
    ...          {"vinf": 2.0, "replica": 0, "status": "ok", "deflection": 0.6}]
    >>> sorted(path.name for path in write_outputs(study, tempfile.mkdtemp(), table))
    ['main_result.png', 'results.csv', 'results.parquet']
    """
    out = Path(out)
    files = [write_csv(out / "results.csv", table)]
    parquet = write_parquet(out / "results.parquet", table)
    if parquet is not None:
        files.append(parquet)
    plot = _plot_main(study, out / "main_result.png", table)
    if plot is not None:
        files.append(plot)
    return files


def _plot_main(study: Study, path: Path, table: list[Mapping[str, Any]]) -> Path | None:
    if study.main is None or not aggregate(table, study.main, []):
        return None
    try:
        import matplotlib
    except ImportError:  # pragma: no cover - depends on the installation
        return None
    matplotlib.use("Agg")
    from . import plotting

    x = next(iter(study.vary))
    along_x = next((group for group in study.zip if x in group), (x,))  # zipped options move with x
    series = [name for name in study.vary if name not in along_x]
    theory = f"{study.main}_theory"  # e.g. edmd's compressibility_factor_theory
    theory = theory if any(theory in row for row in table) else None
    ax = plotting.plot_sweep(table, x, study.main, series=series, title=f"collisionkit {study.command}", theory=theory)
    return plotting.save(ax, path)
