"""A swarm run's state between two chunks of samples, as a checkpoint stores it, and back.

:class:`~collisionkit.transport.SwarmScan` saves the running E/N point with
its finished ones, so that a crash in a long point loses at most the time
since the last save, not the point. :func:`run_snapshot` splits a run
(:class:`~._swarm_run.SwarmRun` or a subclass, at the end of a chunk of
samples) into a JSON-ready mapping and numpy arrays; :func:`restore_run`
puts them into a run made afresh with the same arguments (by
:func:`~._swarm_setup.new_run`), which then goes on exactly as the saved
one would have: the particles' random streams, population control's
generator and every per-sample record are restored bit for bit.

The attributes a run's constructor derives from its arguments (the tables,
the stepper, the density, the number of groups, the field's frequency) are
not saved: the run made afresh has them.
"""

from __future__ import annotations

import numpy as np

from ._swarm_run import Swarm

# made by the run's constructor from its arguments: the same in the fresh run, so not saved
REBUILT = frozenset({"stepper", "tables", "density", "groups", "conservative", "omega", "phases", "phase_step"})
SWARM_COLUMNS = {"pos": (np.float64, 3), "vel": (np.float64, 3), "states": (np.uint64, 4), "alive": (np.bool_, 0),
                 "group": (np.int64, 0)}
STEPPER_STATE = ("slots", "trial_budget")  # what a stepper learns while it runs
PREFIX = "point."  # of the arrays' names in a checkpoint


class SnapshotMismatch(ValueError):
    """A saved run state that does not fit the run made afresh for it (a damaged or foreign checkpoint)."""


def run_snapshot(run) -> tuple[dict, dict[str, np.ndarray]]:
    """The state of ``run`` at the end of a chunk of samples: ``(state, arrays)``.

    ``state`` is JSON-ready (the run's class, its scalars, the names of its
    arrays and per-sample series, the generator's state); ``arrays`` holds
    the bulk, keyed ``point.<attribute>`` (a series stacked along its first
    axis, the swarm as ``point.swarm.<column>``): copies, so the snapshot
    stays as it is while the run goes on (the kernels move particles in
    place).

    Raises
    ------
    TypeError
        If the run holds an attribute of a kind not known here (a new
        attribute must be given a way to be saved).

    Examples
    --------
    >>> from scipy import constants
    >>> from collisionkit.transport import reid_ramp
    >>> from collisionkit.transport._tables import build_tables
    >>> from collisionkit.transport.swarm import REFERENCE_DENSITY, _field_record
    >>> from collisionkit.transport._swarm_setup import new_run
    >>> tables = build_tables(reid_ramp(), constants.m_e, 0.0)
    >>> record = _field_record(12.0, 0.0, REFERENCE_DENSITY, constants.m_e, -constants.e, np.zeros(3))
    >>> run, stepper = new_run(tables, record, False, 0.0, 256, 8, 1, constants.m_e, 1.0, "equal", 1, 32,
    ...                        REFERENCE_DENSITY, False)
    >>> state, arrays = run_snapshot(run)
    >>> state["class"], arrays["point.swarm.pos"].shape
    ('TensorRun', (256, 3))
    >>> stepper.close()
    """
    state = {"class": type(run).__name__, "scalars": {}, "arrays": [], "series": [], "none": [],
             "stepper": {name: getattr(run.stepper, name) for name in STEPPER_STATE}}
    arrays = {}
    for name, value in vars(run).items():
        if name in REBUILT:
            continue
        if isinstance(value, Swarm):
            arrays |= {f"{PREFIX}swarm.{column}": getattr(value, column).copy() for column in SWARM_COLUMNS}
        elif isinstance(value, np.random.Generator):
            state["rng"] = value.bit_generator.state
        elif isinstance(value, np.ndarray):
            state["arrays"].append(name)
            arrays[PREFIX + name] = value.copy()
        elif isinstance(value, list):
            state["series"].append(name)
            arrays[PREFIX + name] = np.array(value)
        elif value is None:
            state["none"].append(name)
        elif isinstance(value, (bool, int, float, np.bool_, np.integer, np.floating)):
            state["scalars"][name] = value.item() if isinstance(value, np.generic) else type(value)(value)
        else:
            raise TypeError(f"a swarm run's attribute {name} ({type(value).__name__}) has no way to be saved")
    return state, arrays


def restore_run(run, state: dict, arrays: dict[str, np.ndarray]) -> None:
    """Put a state saved by :func:`run_snapshot` into ``run``, made afresh with the saved run's arguments.

    Raises
    ------
    SnapshotMismatch
        A ValueError: if the state does not fit the run: another kind of run, an
        attribute missing, unknown or of another type, or arrays of the
        wrong type or shape (a damaged file; the message says what).

    Examples
    --------
    >>> from scipy import constants
    >>> from collisionkit.transport import reid_ramp
    >>> from collisionkit.transport._tables import build_tables
    >>> from collisionkit.transport.swarm import REFERENCE_DENSITY, _field_record
    >>> from collisionkit.transport._swarm_setup import new_run
    >>> tables = build_tables(reid_ramp(), constants.m_e, 0.0)
    >>> record = _field_record(12.0, 0.0, REFERENCE_DENSITY, constants.m_e, -constants.e, np.zeros(3))
    >>> def fresh():
    ...     return new_run(tables, record, False, 0.0, 256, 8, 1, constants.m_e, 1.0, "equal", 1, 32,
    ...                    REFERENCE_DENSITY, False)
    >>> run, stepper = fresh()
    >>> run.calibrate(20.0); run.step()
    >>> state, arrays = run_snapshot(run)
    >>> copy, copy_stepper = fresh()
    >>> restore_run(copy, state, arrays)
    >>> run.step(); copy.step()
    >>> bool(np.array_equal(run.swarm.vel, copy.swarm.vel)), len(copy.times)
    (True, 2)
    >>> stepper.close(); copy_stepper.close()
    """
    if state.get("class") != type(run).__name__:
        raise SnapshotMismatch(f"it holds a {state.get('class')!r} run, not a {type(run).__name__}")
    expected = {name for name in vars(run) if name not in REBUILT}
    saved = {name for key in ("scalars", "arrays", "series", "none") for name in _names(state, key)}
    saved |= {"swarm", "rng"}
    if saved != expected:
        raise SnapshotMismatch(f"its run state has the attributes {sorted(saved)}, not {sorted(expected)}")
    values = {"swarm": _saved_swarm(arrays, run.groups)}
    values |= {name: _scalar(name, state["scalars"][name], getattr(run, name)) for name in state["scalars"]}
    values |= {name: None for name in state["none"]}
    values |= {name: _array(arrays, name) for name in state["arrays"]}
    values |= {name: list(_array(arrays, name)) for name in state["series"]}
    lengths = {len(values[name]) for name in state["series"]}
    if len(lengths) > 1:
        raise SnapshotMismatch(f"its per-sample series have different lengths {sorted(lengths)}")
    _restore_generator(run.rng, state.get("rng"))
    _restore_stepper(run.stepper, state.get("stepper"))
    for name, value in values.items():
        setattr(run, name, value)


def _names(state, key):
    names = state.get(key, {} if key == "scalars" else [])
    if not isinstance(names, (dict, list)) or not all(isinstance(name, str) for name in names):
        raise SnapshotMismatch(f"its run state's {key!r} is not a list of names")
    return names


def _scalar(name, value, fresh):
    """A saved scalar, of the type the fresh run's attribute has (an int may stand for a float)."""
    kind = type(fresh) if fresh is not None else type(value)
    if kind is float and isinstance(value, int) and not isinstance(value, bool):
        value = float(value)
    if type(value) is not kind:
        raise SnapshotMismatch(f"its run state {name!r} must be a {kind.__name__}; got {value!r}")
    return value


def _array(arrays, name):
    key = PREFIX + name
    if key not in arrays:
        raise SnapshotMismatch(f"the array {key!r} is missing")
    return arrays[key]


def _saved_swarm(arrays, groups) -> Swarm:
    """The saved particles, each column of its dtype and shape, every group number in [0, groups)."""
    columns = {column: _array(arrays, f"swarm.{column}") for column in SWARM_COLUMNS}
    rows = len(columns["pos"])
    for column, (dtype, width) in SWARM_COLUMNS.items():
        value = columns[column]
        shape = (rows, width) if width else (rows,)
        if value.dtype != dtype or value.shape != shape:
            raise SnapshotMismatch(f"its swarm's {column} is {value.dtype}{list(value.shape)}, not "
                             f"{np.dtype(dtype)}{list(shape)}")
    if rows and not (0 <= columns["group"].min() and columns["group"].max() < groups):
        raise SnapshotMismatch(f"its swarm's group numbers are not all in [0, {groups})")
    return Swarm(**{column: np.ascontiguousarray(value) for column, value in columns.items()})


def _restore_generator(rng, saved):
    try:
        rng.bit_generator.state = saved
    except (TypeError, ValueError, KeyError) as error:  # numpy's own checks of a generator state
        raise SnapshotMismatch(f"its population-control generator cannot be restored ({error})") from None


def _restore_stepper(stepper, saved):
    if not isinstance(saved, dict) or set(saved) != set(STEPPER_STATE) or not all(
            isinstance(saved[name], int) and not isinstance(saved[name], bool) and saved[name] >= 0
            for name in STEPPER_STATE):
        raise SnapshotMismatch(f"its stepper state must give {', '.join(STEPPER_STATE)} as whole numbers; got {saved!r}")
    for name in STEPPER_STATE:
        setattr(stepper, name, saved[name])
