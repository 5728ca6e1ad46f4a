"""A study's runs: one task per point and replica, with its seed, folder and checked parameters."""

from __future__ import annotations

import difflib
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .commands import SweepCommand, sweep_command
from .study import Study, _check_integer, expand

RESULT_FILE = "result.json"
POINTS_FOLDER = "points"  # in the study's folder: a folder per point and replica
SET_BY_THE_SWEEP = ("summary", "out", "config", "resume", "checkpoint", "plots")  # each point's files: the sweep's


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


@dataclass(frozen=True)
class PointTask:
    """One run of the command: a point, a replica, its seed, its folder and its options.

    ``options`` holds every option of the run by command-line spelling
    (fixed and varied; the seed too when the command takes one).

    Examples
    --------
    >>> study = Study("encounter", seed=0, vary={"vinf": [0.5, 1.0]})
    >>> task = point_tasks(study, "out")[1]
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
    options: Mapping[str, Any]

    @property
    def name(self) -> str:
        return point_name(self.index, self.replica)

    @property
    def result_path(self) -> Path:
        return self.directory / RESULT_FILE


def _split_options(command: SweepCommand, options: Mapping[str, Any]):
    """The options as (the command's checked parameters, its other options by dashed name).

    Raises
    ------
    ValueError, TypeError
        If the command has no such option or refuses a value (the
        command's own checks, as on the command line).
    """
    if command.derive is not None:
        options = command.derive(dict(options))
    physics = {key: value for key, value in options.items() if key not in command.outputs}
    outputs = {key: value for key, value in options.items() if key in command.outputs}
    for key, kind in command.outputs.items():
        value = outputs.get(key)
        allowed = (str, Path) if kind is Path else (int, float) if kind is float else kind
        if value is not None and (not isinstance(value, allowed) or isinstance(value, bool)):
            raise TypeError(f"option {key!r} takes a {kind.__name__ if kind is not Path else 'file name'}; got {value!r}")
    return command.parameters.from_mapping(physics), outputs


def check_command(study: Study) -> SweepCommand:
    """Check that the study's command can be swept and takes every fixed and varied option, at every point.

    Returns
    -------
    SweepCommand

    Raises
    ------
    ValueError, TypeError
        Naming the option, the point and the command's rule.

    Examples
    --------
    >>> check_command(Study("encounter", seed=0, vary={"vinf": [1.0]})).name
    'encounter'
    >>> check_command(Study("encounter", seed=0, vary={"speed": [1.0]}))
    Traceback (most recent call last):
    ...
    ValueError: command 'encounter' has no option 'speed' (its options: layout, m1, m2, radius1, radius2, rp, sep0, units, vinf)
    >>> check_command(Study("encounter", seed=0, vary={"vinfty": [1.0]}))
    Traceback (most recent call last):
    ...
    ValueError: command 'encounter' has no option 'vinfty'; did you mean 'vinf'? (its options: layout, m1, m2, radius1, radius2, rp, sep0, units, vinf)
    """
    command = sweep_command(study.command)
    allowed = command.options()
    takes_seed = "seed" in command.parameters.names()
    for name in [*study.fixed, *study.vary]:
        if name in SET_BY_THE_SWEEP or (name == "seed" and takes_seed):
            raise ValueError(f"option {name!r} is set by the sweep for every point; remove it from the study")
        if name not in allowed:
            shown = sorted(key for key in allowed if not (key == "seed" and takes_seed))
            close = difflib.get_close_matches(name, shown, n=2, cutoff=0.75)
            guess = f"; did you mean {' or '.join(repr(option) for option in close)}?" if close else ""
            raise ValueError(f"command {study.command!r} has no option {name!r}{guess} (its options: "
                             f"{', '.join(shown)})")
    for point in expand(study):
        try:
            _split_options(command, _options(study, point, 0, takes_seed))
        except (ValueError, TypeError) as error:
            raise type(error)(f"the point {dict(point)} is refused by 'collisionkit {study.command}': {error}") from None
    return command


def _options(study: Study, point: Mapping[str, Any], seed: int, takes_seed: bool) -> dict[str, Any]:
    return {**study.fixed, **point, **({"seed": seed} if takes_seed else {})}


def point_tasks(study: Study, out) -> list[PointTask]:
    """Every run of the study, point by point and replica by replica, with seeds and options.

    Parameters
    ----------
    study : Study
    out : path
        The study's folder; the runs go to ``out/points/pNNNN-rNN``
        (absolute: workers elsewhere must see the same path). Options that
        name a file (edmd's ``trajectory``) name it inside each point's folder.

    Examples
    --------
    >>> study = Study("encounter", seed=0, vary={"vinf": [0.5, 1.0]}, replicas=2)
    >>> tasks = point_tasks(study, "out")
    >>> [task.name for task in tasks]
    ['p0000-r00', 'p0000-r01', 'p0001-r00', 'p0001-r01']
    >>> tasks[0].options
    {'vinf': 0.5}
    """
    command = check_command(study)
    takes_seed = "seed" in command.parameters.names()
    out = Path(out).absolute()  # workers may run in another directory
    tasks = []
    for index, point in enumerate(expand(study)):
        for replica in range(study.replicas):
            seed = point_seed(study.seed, index, replica)
            directory = out / POINTS_FOLDER / point_name(index, replica)
            options = _options(study, point, seed, takes_seed)
            tasks.append(PointTask(study.command, index, replica, point, seed, (index, replica), directory, options))
    return tasks
