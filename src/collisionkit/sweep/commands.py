"""The commands a study can sweep, as library calls: parameters in, a flat summary out.

Each command names its parameters class (a :class:`collisionkit._params.Parameters`:
the same checks as the command line), the library call that runs one
point in a folder, and the main result plotted against the varied
option. Nothing here imports the command line.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

__all__ = ["MAIN_RESULTS", "SweepCommand", "sweep_command", "sweep_commands"]

NOT_SWEPT = ("sweep", "demo", "animate")  # commands of the command line that are not simulations
POINT_CHECKPOINT = "checkpoint.npz"  # in each point's folder: a point whose worker died resumes from it
MAIN_RESULTS = {
    "edmd": "compressibility_factor",
    "swarm": "mean_energy",
    "slab": "transmission",
    "encounter": "orbit.deflection_angle",
    "track": "gain",
    "boltzmann": "mean_energy",
}


@dataclass(frozen=True)
class SweepCommand:
    """One sweepable command.

    Attributes
    ----------
    name : str
        The command's name (``edmd``, ``swarm``, ``slab``, ``encounter``).
    load_parameters : callable
        Returns the command's parameters class (imported when needed).
    run : callable
        ``run(parameters, folder, outputs) -> dict``: runs one point, may
        write files in ``folder``, returns the command's JSON summary.
    outputs : mapping of str to type
        Options that are not physics (dashed names): ``Path`` ones name a
        file written in the point's folder.
    files : tuple of str
        The files ``run`` writes in the point's folder under fixed names
        (besides the point's checkpoint and those ``outputs`` name).
    derived : mapping of str to type
        Options the command line turns into parameters (swarm's ``E`` in
        V/cm, with ``pressure``, into ``E-N``): ``derive`` does it.
    derive : callable, optional
        ``derive(options) -> options``: the point's options (dashed names)
        with the ``derived`` ones replaced by the parameters they give.

    Examples
    --------
    >>> command = sweep_command("edmd")
    >>> command.parameters.__name__, command.main, sorted(command.outputs)
    ('EdmdParameters', 'compressibility_factor', ['frame-every', 'trajectory', 'xyz'])
    """

    name: str
    load_parameters: Callable[[], type]
    run: Callable[[Any, Path, Mapping[str, Any]], dict]
    outputs: Mapping[str, type] = field(default_factory=dict)
    files: tuple[str, ...] = ()
    derived: Mapping[str, type] = field(default_factory=dict)
    derive: Callable[[dict], dict] | None = None

    @property
    def parameters(self) -> type:
        """The command's parameters class."""
        return self.load_parameters()

    @property
    def main(self) -> str:
        """The summary key plotted against the varied option."""
        return MAIN_RESULTS[self.name]

    def options(self) -> dict[str, str]:
        """Every option a study may set, by command-line spelling: {flag: Python name}.

        Examples
        --------
        >>> sweep_command("swarm").options()["E-N"]
        'reduced_field'
        """
        parameters = self.parameters
        spelled = {parameters.flag(name): name for name in parameters.names()}
        return spelled | {name: name.replace("-", "_") for name in (*self.outputs, *self.derived)}

    def canonical(self, key: str) -> str | None:
        """The command-line spelling of an option given as a flag or a Python name, or None.

        Examples
        --------
        >>> command = sweep_command("edmd")
        >>> command.canonical("packing_fraction"), command.canonical("frame_every"), command.canonical("speed")
        ('packing-fraction', 'frame-every', None)
        """
        name = self.parameters.name_of(key)
        if name is not None:
            return self.parameters.flag(name)
        dashed = str(key).replace("_", "-")
        return dashed if dashed in self.outputs or dashed in self.derived else None


# ------------------------------------------------------------------ the commands' point runs


def _edmd_parameters():
    from ..edmd import EdmdParameters

    return EdmdParameters


def _run_edmd(parameters, folder: Path, outputs: Mapping[str, Any]) -> dict:
    from ..edmd import EdmdRun

    trajectory = outputs.get("trajectory")
    trajectory = None if trajectory is None else folder / trajectory
    checkpoint = folder / POINT_CHECKPOINT
    run = _resumed(EdmdRun, checkpoint, parameters.resolved(), trajectory=trajectory)
    if run is None:
        run = EdmdRun(parameters, checkpoint=checkpoint, trajectory=trajectory, frame_every=outputs.get("frame-every"),
                      overwrite=True)  # the point's own folder: a failed attempt's files are replaced
    run.run()
    files = [] if trajectory is None else [run.trajectory]
    if outputs.get("xyz") is not None:
        files.append(run.write_xyz(folder / outputs["xyz"]))
    return run.summary(files)


def _resumed(run_class, checkpoint: Path, parameters, **options):
    """The run saved in the point's own checkpoint (a worker killed mid-point), if it is this point's; else None."""
    from .._io import CheckpointError

    if not checkpoint.exists():
        return None
    try:
        run = run_class.resume(checkpoint, **options)
    except (CheckpointError, ValueError):
        return None  # damaged, or of an older study in this folder: the point starts again
    return run if run.parameters == parameters else None


def _swarm_parameters():
    from ..transport import SwarmParameters

    return SwarmParameters


def _run_swarm(parameters, folder: Path, outputs: Mapping[str, Any]) -> dict:
    """A swarm point; with ``pressure`` (Torr) each result also holds its ``detector`` coefficients, as the
    command's --pressure gives them (:func:`~collisionkit.transport.detector_coefficients`)."""
    from ..transport import SwarmScan, detector_coefficients, gas_number_density

    pressure = outputs.get("pressure")
    if pressure is not None:  # refused before the work
        gas_number_density(pressure, parameters.gas_temperature)
        if parameters.reduced_magnetic_field != 0.0 or parameters.reduced_frequency != 0.0:
            raise ValueError("pressure gives a detector's table of a static E without B: not with B-N or omega-N")
    checkpoint = folder / POINT_CHECKPOINT
    scan = _resumed(SwarmScan, checkpoint, parameters) or SwarmScan(parameters, checkpoint=checkpoint)
    scan.run()
    summary = scan.summary()
    if pressure is not None:
        for entry, result in zip(summary["results"], scan.results):
            entry["detector"] = detector_coefficients(result, pressure)
        if len(summary["results"]) == 1:  # one E/N: its values are at the top level too (swarm_summary)
            summary["detector"] = summary["results"][0]["detector"]
    return summary


def _swarm_fields_from_volts(options: dict) -> dict:
    """A swarm study's ``E`` (V/cm) at its ``pressure`` (Torr) and gas temperature (300 K if not given) as ``E-N``,
    as the command's --E gives it (:func:`~collisionkit.transport.reduced_fields`).

    Examples
    --------
    >>> options = _swarm_fields_from_volts({"E": 1000.0, "pressure": 760.0, "gas-temperature": 293.15})
    >>> [round(value, 4) for value in options["E-N"]], "E" in options
    ([3.9944], False)
    """
    fields = options.pop("E", None)
    if fields is None:
        return options
    from ..transport import reduced_fields

    if options.get("E-N") is not None:
        raise ValueError("give the field as E (V/cm, with pressure) or as E-N (Td), not both")
    pressure = options.get("pressure")
    if pressure is None:
        raise ValueError("E (V/cm) needs a pressure (Torr) for the gas's number density")
    temperature = options.get("gas-temperature")
    temperature = 300.0 if temperature is None else temperature
    values = fields if isinstance(fields, (list, tuple)) else [fields]
    for name, value in (("pressure", pressure), ("gas-temperature", temperature), *(("E", item) for item in values)):
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise TypeError(f"option {name!r} takes a number; got {value!r}")
    if not temperature > 0.0:
        raise ValueError("E (V/cm) needs a gas-temperature > 0 K for N = p / (k T)")
    return options | {"E-N": [float(value) for value in reduced_fields(values, pressure, temperature)]}


def _slab_parameters():
    from ..transport import SlabParameters

    return SlabParameters


def _run_slab(parameters, folder: Path, outputs: Mapping[str, Any]) -> dict:
    from ..transport import run_slab, slab_summary

    return slab_summary(parameters, run_slab(parameters))


def _encounter_parameters():
    from ..encounters import EncounterParameters

    return EncounterParameters


def _run_encounter(parameters, folder: Path, outputs: Mapping[str, Any]) -> dict:
    from ..encounters import encounter_summary

    summary, initial_conditions = encounter_summary(parameters)
    files = initial_conditions.write(folder, units=parameters.unit_system())  # initial_conditions.json and .txt
    return summary | {"files": [str(path) for path in files]}


def _boltzmann_parameters():
    from ..transport import TwoTermParameters

    return TwoTermParameters


def _run_boltzmann(parameters, folder: Path, outputs: Mapping[str, Any]) -> dict:
    from ..transport import run_two_term, two_term_summary

    scan = run_two_term(parameters)  # milliseconds to seconds a point: no checkpoint
    if scan.failed:  # a point without a solution is a failed point of the study (as the command's exit 1)
        raise RuntimeError("; ".join(f"E/N = {failure['E_N']:g} Td: {failure['reason']}" for failure in scan.failed))
    return two_term_summary(parameters, scan)


def _track_parameters():
    from ..transport.tracking import TrackParameters

    return TrackParameters


def _run_track(parameters, folder: Path, outputs: Mapping[str, Any]) -> dict:
    from ..transport.tracking import TrackRun

    checkpoint = folder / POINT_CHECKPOINT
    run = _resumed(TrackRun, checkpoint, parameters) or TrackRun(parameters, checkpoint=checkpoint)
    run.run()
    return run.summary()


_COMMANDS = {
    "edmd": SweepCommand("edmd", _edmd_parameters, _run_edmd, {"trajectory": Path, "frame-every": int, "xyz": Path}),
    "swarm": SweepCommand("swarm", _swarm_parameters, _run_swarm, {"pressure": float}, derived={"E": float},
                          derive=_swarm_fields_from_volts),
    "slab": SweepCommand("slab", _slab_parameters, _run_slab),
    "encounter": SweepCommand("encounter", _encounter_parameters, _run_encounter,
                              files=("initial_conditions.json", "initial_conditions.txt")),
    "track": SweepCommand("track", _track_parameters, _run_track),
    "boltzmann": SweepCommand("boltzmann", _boltzmann_parameters, _run_boltzmann),
}


def sweep_commands() -> tuple[str, ...]:
    """The names of the commands a study can sweep.

    Examples
    --------
    >>> sweep_commands()
    ('boltzmann', 'edmd', 'encounter', 'slab', 'swarm', 'track')
    """
    return tuple(sorted(_COMMANDS))


def sweep_command(name: str) -> SweepCommand:
    """The sweepable command ``name``; ValueError naming the others if there is none.

    Examples
    --------
    >>> sweep_command("swarm").canonical("reduced_field")
    'E-N'
    """
    if name in NOT_SWEPT:
        raise ValueError(f"command {name!r} cannot be swept; sweep a simulation command: {', '.join(sweep_commands())}")
    if name not in _COMMANDS:
        raise ValueError(f"unknown command {name!r}; available: {', '.join(sweep_commands())}")
    return _COMMANDS[name]
