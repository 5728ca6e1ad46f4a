"""A study: a command, its fixed and varied parameters, replicas and a root seed (TOML or Python)."""

from __future__ import annotations

import hashlib
import json
import math
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .commands import MAIN_RESULTS, sweep_command

STUDY_KEYS = ("command", "replicas", "seed", "fixed", "vary", "zip", "main")
RANGE_KEYS = {"start", "stop", "num", "step", "log"}
MAX_REPLICAS = 100_000
MAX_RUNS = 1_000_000  # points x replicas of one study: each run has its folder and files
MAX_RANGE_VALUES = 100_000  # values of one range: more is a typo (a step of 1e-9), and would take minutes to list
SIGNIFICANT_DIGITS = 12


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
        fixed = _canonical_mapping(self.command, "fixed", self.fixed)
        vary = {key: _expand_values(key, values)
                for key, values in _canonical_mapping(self.command, "vary", self.vary).items()}
        if not vary:
            raise ValueError("vary must name at least one option to vary (e.g. packing-fraction = [0.1, 0.2])")
        for key, value in fixed.items():
            _check_scalar(f"fixed.{key}", value)
        both = sorted(set(fixed) & set(vary))
        if both:
            raise ValueError(f"options {both} are both fixed and varied; keep each in one table")
        groups = _check_zip(self.command, self.zip, vary)
        _check_size(vary, groups, self.replicas)
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
    if isinstance(value, list) and value:  # a list option, e.g. species = ["Ar", "N2"]
        for item in value:
            _check_scalar(name, item)
        return
    if not isinstance(value, (bool, int, float, str)):
        raise TypeError(f"{name} must be a number, a string, a boolean or a list of them; got {value!r}")


def _spelling(command: str, key: str) -> str:
    """The command-line spelling of an option (``reduced_field`` -> ``E-N``); dashed if the command has no such option."""
    try:
        canonical = sweep_command(command).canonical(key)
    except ValueError:  # an unknown command: check_command says so
        canonical = None
    return canonical or _dashed(key)


def _canonical_mapping(command: str, name: str, values: Any) -> dict[str, Any]:
    if not isinstance(values, Mapping):
        raise TypeError(f"{name} must be a table of option = value; got {values!r}")
    result: dict[str, Any] = {}
    for key, value in values.items():
        _check_name(f"a key of {name}", key)
        spelled = _spelling(command, key)
        if spelled in result:
            raise ValueError(f"{name} names {spelled!r} twice (as a flag and a Python name, or with dashes and "
                             "underscores)")
        result[spelled] = value
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
    if isinstance(values, np.ndarray) and values.ndim == 1:  # np.linspace(...): its values as Python numbers
        values = values.tolist()
    if isinstance(values, Mapping):
        return _expand_range(name, values)
    if isinstance(values, (list, tuple)):
        if not values:
            raise ValueError(f"vary.{name} is an empty list; give at least one value")
        for value in values:
            _check_scalar(f"vary.{name}", value)
        return tuple(values)
    raise TypeError(f"vary.{name} must be a list or a range {{start, stop, num or step}}; got {values!r}")


def _check_zip(command: str, groups: Any, vary: Mapping[str, tuple]) -> tuple[tuple[str, ...], ...]:
    if not isinstance(groups, (list, tuple)):
        raise TypeError(f"zip must be a list of lists of varied options; got {groups!r}")
    seen: set[str] = set()
    result = []
    for group in groups:
        if not isinstance(group, (list, tuple)) or len(group) < 2:
            raise ValueError(f"each zip group must list at least two varied options; got {group!r}")
        names = tuple(_spelling(command, str(name)) for name in group)
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


def _check_size(vary: Mapping[str, tuple], groups: tuple[tuple[str, ...], ...], replicas: int) -> None:
    """Refuse a study of more runs than :data:`MAX_RUNS` (a typo, e.g. a step of 1e-6, grew 2.5 GB a minute)."""
    grouped = {name for group in groups for name in group}
    points = math.prod(len(values) for name, values in vary.items() if name not in grouped)
    points *= math.prod(len(vary[group[0]]) for group in groups)
    if points * replicas > MAX_RUNS:
        raise ValueError(f"the study has {points} points x {replicas} replicas = {points * replicas} runs; at most "
                         f"{MAX_RUNS} (fewer values, fewer replicas, or several studies)")


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
    except UnicodeDecodeError as error:  # TOML is UTF-8 text
        raise ValueError(f"study file {path} is not UTF-8 text, as TOML must be (byte {error.start}: "
                         f"{error.reason})") from None
    return study_from_dict(data)


# ------------------------------------------------------------------ points


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
