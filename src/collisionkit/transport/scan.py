"""A swarm scan over E/N: the ``swarm`` command as a library object, with checkpoint and resume.

:class:`SwarmParameters` holds the physics of a scan (the gas, the E/N
values, B/N, the gas temperature, the swarm size, the seed and the
accuracy). :class:`SwarmScan` runs the E/N points in order with
:func:`~collisionkit.transport.simulate_swarm`, writes a checkpoint after
each finished point and every minute within a point when asked (a crash
loses at most the last minute of work) and resumes from it, bit for bit::

    scan = SwarmScan(SwarmParameters(model="reid", reduced_field=[12, 24]), checkpoint="scan.npz")
    scan.run()                               # interrupted? then:
    scan = SwarmScan.resume("scan.npz")
    scan.run()
    scan.summary()["results"][1]["mean_energy"]

The checks of the parameters' values are in ``_scan_values``, the reading
of a checkpoint's saved results in ``_scan_checkpoint``.
"""

from __future__ import annotations

import dataclasses
import hashlib
import math
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, ClassVar

from .._io import CheckpointError, exclusive, file_digest, read_checkpoint, write_checkpoint
from .._params import Parameters, check_choice, check_unchanged, check_integer, check_real, check_seed
from ._run_snapshot import SnapshotMismatch, run_snapshot
from ._scan_checkpoint import _saved_result, saved_running_point
from ._scan_values import _paths, _populations, _reals, _reduced_fields, _reduced_frequency, _scattering, _strings
from ._scan_values import _waveform
from ._swarm_setup import resumable_point
from ._validation import MAX_GAS_TEMPERATURE, MAX_REDUCED_MAGNETIC_FIELD
from .angular import SCATTERING_LAWS
from .catalogue import catalogue_files, catalogue_gas
from .gases import MODEL_GASES, SCATTERING_KINDS, Gas, model_gas
from .lxcat import read_lxcat
from .swarm import SwarmResult, simulate_swarm

__all__ = ["SwarmParameters", "SwarmScan", "swarm_summary"]

CHECKPOINT_KIND = "swarm"
SAVE_EVERY = 60.0  # seconds between saves of a running point, by default
SHARING_MODES = ("equal", "uniform")


@dataclasses.dataclass(frozen=True)
class SwarmParameters(Parameters):
    """The physics of a swarm scan, checked when made.

    Parameters
    ----------
    reduced_field : float or sequence of float
        E/N values in Td, in [0, 1e6], run in order (``--E-N``). The ranges of
        E/N, B/N, omega/N and the gas temperature are generous finite ends,
        far beyond practice (:func:`~collisionkit.transport._validation.validate_swarm_setup`).
    model : str, optional
        A model gas (:data:`~collisionkit.transport.MODEL_GASES`); exactly
        one of ``model``, ``gas`` and ``cross_sections``.
    gas : str, optional
        A real gas of the catalogue (``"Ar"``) or a mixture by mole fraction
        (``"Ar:0.9,N2:0.1"``): :func:`~collisionkit.transport.catalogue_gas`.
    cross_sections : path or sequence of paths, optional
        LXCat files, joined (stored resolved, so a resumed scan finds them
        from any folder).
    species, fractions : sequence, optional
        Targets of the LXCat files to use and their number fractions.
    database : str, optional
        The database to take a species from when the files hold it from
        several (:func:`~collisionkit.transport.read_lxcat`).
    reduced_magnetic_field : float
        B/N in Hx (``--B-N``), in [0, 1e6], static, at ``field_angle`` from E.
    field_angle : float
        Degrees between E and B, in [0, 180] (``--angle``, 90 by default);
        the frame has E along z and B in the y-z plane,
        ``B = |B| (0, sin psi, cos psi)``.
    reduced_frequency : float
        omega/N in rad m^3/s (``--omega-N``): 0, a static field, or in [1e-20, 1e-8]:
        E(t) = E0 cos(omega t) with the E/N values as the amplitude E0/N.
    waveform : sequence of (u, E/E0) pairs, optional
        A periodic field of any shape instead of the cosine (``--waveform``;
        needs ``reduced_frequency`` > 0; B as with the cosine): E(t) = E0 f(omega t / 2 pi),
        f linear between the samples, |f| <= 1e6 and the peak E/N at most 1e6 Td, u the fraction of the period
        (:func:`~collisionkit.transport.simulate_swarm`); stored as the pairs.
    gas_temperature : float
        In K, in [0, 1e5] (300 by default); E/N = 0 needs a warm gas. Above 0 the
        reversible excitations have superelastic inverses
        (:mod:`~collisionkit.transport.superelastic`); the model-gas
        benchmarks assume 0.
    scattering : str or dict, optional
        Angular law (:data:`~collisionkit.transport.SCATTERING_LAWS`) of every
        process (``--scattering``), or ``{kind: law}`` for the kinds of
        :data:`~collisionkit.transport.SCATTERING_KINDS` (a TOML table
        ``[scattering]``); kinds left out keep the gas's own (isotropic).
        Elastic tables are momentum-transfer cross sections, converted for
        the law (``forward`` is refused for them).
    populations : dict, optional
        ``{"species:label": fraction}``: the fraction of a species in the
        excited level of a reversible excitation, instead of Boltzmann at
        the gas temperature (a TOML table ``[populations]``).
    particles : int
        Simulated electrons, 128 to 1e7.
    seed : int
        Random seed (>= 0).
    tolerance : float
        Target relative error of the mean energy and the drift velocity
        (of the mean energy alone at E/N = 0), in (0, 0.5].
    collision_budget : float
        Real collisions per E/N point at most, >= 1e4.
    sharing : {"equal", "uniform"}
        Ionization energy sharing.

    Examples
    --------
    >>> SwarmParameters(model="reid", reduced_field=[12, 24]).reduced_field
    (12.0, 24.0)
    >>> SwarmParameters(model="reid", reduced_field=-1)
    Traceback (most recent call last):
    ...
    ValueError: reduced_field (E/N, Td) must be in [0, 1e+06]; got -1
    """

    reduced_field: Any = (12.0,)
    model: str | None = None
    gas: str | None = None
    cross_sections: Any = None
    species: Any = None
    fractions: Any = None
    database: str | None = None
    reduced_magnetic_field: float = 0.0
    field_angle: float = 90.0
    reduced_frequency: float = 0.0
    waveform: Any = None
    gas_temperature: float = 300.0
    particles: int = 20_000
    seed: int = 2026
    tolerance: float = 2e-3
    collision_budget: float = 5e8
    sharing: str = "equal"
    scattering: Any = None
    populations: Any = None

    FLAGS: ClassVar = {"reduced_field": "E-N", "reduced_magnetic_field": "B-N", "field_angle": "angle",
                       "reduced_frequency": "omega-N"}

    def __post_init__(self):
        fields = _reduced_fields(self.reduced_field)
        set_ = object.__setattr__
        set_(self, "reduced_field", fields)
        if sum(value is not None for value in (self.model, self.gas, self.cross_sections)) != 1:
            raise ValueError("give exactly one of model, gas and cross_sections (--model, --gas, --cross-sections)")
        if self.cross_sections is None:
            chosen = f"the model gas {self.model}" if self.model is not None else f"the catalogue gas {self.gas}"
            if self.species is not None or self.fractions is not None or self.database is not None:
                raise ValueError("species, fractions and database pick gases from LXCat files (cross_sections); "
                                 f"{chosen} takes none of them")
        if self.model is not None:
            check_choice("model", self.model, sorted(MODEL_GASES))
        elif self.gas is not None:
            if not isinstance(self.gas, str):
                raise TypeError(f"gas must be a catalogue name or a mixture such as 'Ar:0.9,N2:0.1'; got {self.gas!r}")
            catalogue_files(self.gas)  # an unknown name, bad fractions or a set not downloaded: refused now
        else:
            set_(self, "cross_sections", _paths(self.cross_sections))
            if self.database is not None and not (isinstance(self.database, str) and self.database):
                raise TypeError(f"database must be a database's name; got {self.database!r}")
        set_(self, "species", None if self.species is None else _strings("species", self.species))
        set_(self, "fractions", None if self.fractions is None else _reals("fractions", self.fractions))
        set_(self, "reduced_magnetic_field", check_real("reduced_magnetic_field (B/N, Hx)", self.reduced_magnetic_field,
                                                        0.0, MAX_REDUCED_MAGNETIC_FIELD))
        set_(self, "field_angle", check_real("field_angle (degrees between E and B)", self.field_angle, 0.0, 180.0))
        set_(self, "reduced_frequency", _reduced_frequency(self.reduced_frequency))
        set_(self, "waveform", _waveform(self.waveform, self.reduced_frequency, max(fields)))
        set_(self, "gas_temperature", check_real("gas_temperature (K)", self.gas_temperature, 0.0,
                                                 MAX_GAS_TEMPERATURE))
        set_(self, "particles", check_integer("particles", self.particles, 128, 10_000_000))
        set_(self, "seed", check_seed("seed", self.seed))
        set_(self, "tolerance", check_real("tolerance", self.tolerance, 0.0, 0.5, low_open=True))
        set_(self, "collision_budget", check_real("collision_budget", self.collision_budget, 1e4))
        check_choice("sharing", self.sharing, SHARING_MODES)
        set_(self, "scattering", _scattering(self.scattering))
        set_(self, "populations", _populations(self.populations))
        if 0.0 in fields and self.gas_temperature == 0.0:
            raise ValueError("E/N = 0 in a gas at 0 K has no steady state (nothing heats the swarm; it cools "
                             "without end): give gas_temperature > 0 (--gas-temperature) or E/N > 0")

    def make_gas(self) -> Gas:
        """The target gas: the model gas, the catalogue gas, or the LXCat files' species (ValueError if unreadable).

        Examples
        --------
        >>> SwarmParameters(model="reid").make_gas().species[0].name
        'reid'
        >>> SwarmParameters(gas="Ar").make_gas().species[0].name
        'Ar'
        """
        if self.model is not None:
            gas = model_gas(self.model)
        elif self.gas is not None:
            gas = catalogue_gas(self.gas)
        else:
            for path in self.cross_sections:
                if path.is_dir():
                    raise ValueError(f"cross_sections {path} is a folder; give an LXCat file")
            gas = read_lxcat(self.cross_sections, species=self.species, fractions=self.fractions,
                             database=self.database)
        return self.physics_of(gas)

    def physics_of(self, gas: Gas) -> Gas:
        """``gas`` with the scan's angular laws and level populations (ValueError for a law a process refuses).

        Examples
        --------
        >>> gas = SwarmParameters(model="reid", scattering="okhrimovskyy").make_gas()
        >>> [process.scattering for process in gas.species[0].processes]
        ['okhrimovskyy', 'okhrimovskyy']
        """
        if self.scattering is not None:
            laws = self.scattering if isinstance(self.scattering, dict) else dict.fromkeys(SCATTERING_KINDS,
                                                                                           self.scattering)
            try:
                gas = gas.with_scattering(laws)
            except ValueError as error:
                raise ValueError(f"scattering {self.scattering!r} cannot be used: {error}") from None
        if self.populations is not None:
            gas = gas.with_populations(self.populations)
        return gas

    def gas_files(self) -> list[Path]:
        """The cross-section files the gas is read from (none for a model gas).

        Examples
        --------
        >>> [path.name for path in SwarmParameters(gas="N2").gas_files()], SwarmParameters(model="reid").gas_files()
        (['IST-Lisbon_N2.txt'], [])
        """
        if self.gas is not None:
            return catalogue_files(self.gas)
        return list(self.cross_sections or ())

    def gas_name(self) -> str:
        """The model's name, the catalogue gas or the LXCat files' paths.

        Examples
        --------
        >>> SwarmParameters(model="maxwell").gas_name(), SwarmParameters(gas="Ar:0.9,N2:0.1").gas_name()
        ('maxwell', 'Ar:0.9,N2:0.1')
        """
        if self.cross_sections is not None:
            return ", ".join(str(path) for path in self.cross_sections)
        return str(self.model or self.gas)


def gas_files_digest(paths) -> str | None:
    """SHA-256 of the cross-section files (of one file: its own digest; of several: of their digests in order).

    Examples
    --------
    >>> gas_files_digest([]) is None
    True
    """
    paths = list(paths)
    if not paths:
        return None
    if len(paths) == 1:
        return file_digest(paths[0])
    return hashlib.sha256("\n".join(file_digest(path) for path in paths).encode()).hexdigest()
class SwarmScan:
    """Swarm runs at each E/N in turn, checkpointed after each finished point and within a long one.

    Parameters
    ----------
    parameters : SwarmParameters
    checkpoint : path, optional
        Written (``.npz``, atomically) after every finished E/N point, and
        with the running point's whole state (particles, random streams,
        records) at the end of the first chunk of samples after every
        ``save_every`` seconds: a resumed scan goes on from there exactly
        as the interrupted one would have.
    gas : Gas, optional
        A gas built in Python (default: ``parameters.make_gas()``); the
        parameters' ``scattering`` and ``populations`` apply to it too.
    save_every : float, optional
        Seconds between saves of the running point (default :data:`SAVE_EVERY`, 60; 0 saves
        after every chunk of 25 samples). The last saved state is also kept
        in memory (a copy of the particles): :meth:`run` called again after
        an interruption goes on from it.
    annotations : mapping, optional
        The caller's notes on the scan (str keys; numbers, text, lists or
        mappings of them), saved in the checkpoint and given back by
        :meth:`resume` as :attr:`annotations`; the scan never reads them
        (the command line keeps its detector's ``--pressure`` there).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> parameters = SwarmParameters(model="maxwell", reduced_field=[10.0], particles=640, tolerance=0.05)
    >>> scan = SwarmScan(parameters, checkpoint=folder / "scan.npz")
    >>> results = scan.run()
    >>> resumed = SwarmScan.resume(folder / "scan.npz")
    >>> resumed.finished, resumed.results[0].mean_energy == results[0].mean_energy
    (True, True)
    """

    def __init__(self, parameters: SwarmParameters, checkpoint=None, gas: Gas | None = None,
                 results: Sequence[SwarmResult] = (), save_every: float | None = None, annotations=None):
        if not isinstance(parameters, SwarmParameters):
            raise TypeError(f"parameters must be SwarmParameters; got {type(parameters).__name__}")
        self.parameters = parameters
        self.checkpoint = None if checkpoint is None else Path(checkpoint)
        self.gas = parameters.make_gas() if gas is None else parameters.physics_of(gas)
        self.results: list[SwarmResult] = list(results)
        save_every = SAVE_EVERY if save_every is None else save_every
        self.save_every = check_real("save_every (seconds)", save_every, 0.0, math.inf)
        self.annotations = {} if annotations is None else dict(annotations)
        if not all(isinstance(key, str) for key in self.annotations):
            raise TypeError("annotations must have str keys")
        # the running point's last saved state: (index, state, arrays) of _run_snapshot.run_snapshot, and its file
        self._running: tuple[int, dict, dict] | None = None
        self._running_source: Path | None = None

    def __repr__(self) -> str:
        fields = self.parameters.reduced_field
        return (f"SwarmScan(E/N {', '.join(f'{value:g}' for value in fields)} Td, {len(self.results)} of {len(fields)} "
                f"done, checkpoint={None if self.checkpoint is None else str(self.checkpoint)!r})")

    @property
    def running_point(self) -> int | None:
        """Index of the E/N point whose state was saved while it ran (the next :meth:`run` goes on from it), or None.

        Examples
        --------
        >>> SwarmScan(SwarmParameters(model="maxwell", reduced_field=[5.0, 10.0])).running_point is None
        True
        """
        return None if self._running is None else self._running[0]

    @property
    def finished(self) -> bool:
        """True once every E/N point has a result."""
        return len(self.results) == len(self.parameters.reduced_field)

    def tolerances(self, reduced_field: float) -> dict[str, float]:
        """The accuracy asked of one point: mean energy and drift; the mean energy alone at E/N = 0 and in an
        oscillating field.

        Examples
        --------
        >>> scan = SwarmScan(SwarmParameters(model="maxwell", reduced_field=[5.0, 10.0], particles=640, tolerance=0.05))
        >>> scan.tolerances(5.0), scan.tolerances(0.0)
        ({'mean_energy': 0.05, 'drift_velocity_bulk': 0.05}, {'mean_energy': 0.05})
        """
        tolerance = self.parameters.tolerance
        if reduced_field == 0.0 or self.parameters.reduced_frequency > 0.0:
            # the drift (averaged over a cycle of an oscillating field) is zero by symmetry: no relative error to reach
            return {"mean_energy": tolerance}
        return {"mean_energy": tolerance, "drift_velocity_bulk": tolerance}

    def run(self, progress: Callable[[float], Any] | None = None) -> list[SwarmResult]:
        """Run the E/N points not done yet; return every result.

        Parameters
        ----------
        progress : callable, optional
            Called as ``progress(fraction)``, the fraction of the scan's
            points done, in [0, 1].

        Raises
        ------
        collisionkit._io.FileLockedError
            If another process is writing the scan's checkpoint (it is
            locked for the run).

        Examples
        --------
        >>> scan = SwarmScan(SwarmParameters(model="maxwell", reduced_field=[5.0, 10.0], particles=640, tolerance=0.05))
        >>> [round(result.reduced_field) for result in scan.run()], scan.finished
        ([5, 10], True)
        """
        p, total = self.parameters, len(self.parameters.reduced_field)
        with exclusive(self.checkpoint):  # a second process writing the checkpoint is refused
            for value in p.reduced_field[len(self.results):]:
                done = len(self.results)

                def report(fraction, done=done):
                    if progress is not None:
                        progress((done + fraction) / total)

                saved = self._running[1:] if self._running is not None and self._running[0] == done else None
                try:
                    with resumable_point(saved, self._point_saver(done)):
                        result = simulate_swarm(
                            self.gas, value, reduced_magnetic_field=p.reduced_magnetic_field,
                            field_angle=p.field_angle, reduced_frequency=p.reduced_frequency, waveform=p.waveform,
                            gas_temperature=p.gas_temperature, particles=p.particles, seed=p.seed,
                            sharing=p.sharing, tolerances=self.tolerances(value),
                            collision_budget=p.collision_budget, progress=report)
                except SnapshotMismatch as error:
                    raise CheckpointError(f"{self._running_source} is a damaged swarm checkpoint: its running point "
                                          f"(E/N = {value:g} Td) cannot be restored: {error}") from None
                self._running = None
                self.results.append(result)
                self.save()
        if progress is not None:
            progress(1.0)
        return self.results

    def _point_saver(self, index: int) -> Callable | None:
        """What saves the running point ``index`` after a chunk of samples, once ``save_every`` seconds have passed
        since the last save (None without a checkpoint)."""
        if self.checkpoint is None:
            return None
        last = time.monotonic()

        def save_point(run):
            nonlocal last
            if time.monotonic() - last >= self.save_every:
                self._running = (index, *run_snapshot(run))
                self._running_source = self.checkpoint
                self.save()
                last = time.monotonic()

        return save_point

    def save(self, path=None) -> Path | None:
        """Write the checkpoint (to ``path``, default the scan's checkpoint); None if there is none.

        Examples
        --------
        >>> import pathlib, tempfile
        >>> scan = SwarmScan(SwarmParameters(model="maxwell", reduced_field=[5.0, 10.0], particles=640, tolerance=0.05))
        >>> scan.save(pathlib.Path(tempfile.mkdtemp()) / "scan.npz").suffix, scan.save()
        ('.npz', None)
        """
        path = self.checkpoint if path is None else Path(path)
        if path is None:
            return None
        state = {"cross_sections_sha256": gas_files_digest(self.parameters.gas_files()),
                 "results": [result.to_dict() for result in self.results], "annotations": self.annotations}
        arrays = {}
        if self._running is not None:
            index, run_state, arrays = self._running
            state["running_point"] = {"index": index, "run": run_state}
        return write_checkpoint(path, CHECKPOINT_KIND, self.parameters.to_dict(), state, arrays)

    @classmethod
    def resume(cls, path, checkpoint=None, gas: Gas | None = None, save_every: float | None = None,
               **given) -> SwarmScan:
        """The scan saved in ``path``, ready to run its unfinished points.

        Parameters
        ----------
        path : path
            A checkpoint written by :meth:`save`.
        checkpoint : path, optional
            Where to write checkpoints from now on (default: ``path``).
        gas : Gas, optional
            The gas, if the scan was made with one built in Python.
        save_every : float, optional
            Seconds between saves of the running point (as in the constructor).
        \\*\\*given
            Parameters given again (Python names or flags): each must equal
            the saved one (a resumed scan keeps its physics).

        Raises
        ------
        ValueError
            If the file is not a swarm checkpoint or a damaged one (a saved
            result or entry of the wrong type or shape:
            :class:`~collisionkit._io.CheckpointError`), a parameter given
            differs, or the LXCat file changed since.

        Examples
        --------
        >>> import pathlib, tempfile
        >>> path = pathlib.Path(tempfile.mkdtemp()) / "scan.npz"
        >>> scan = SwarmScan(SwarmParameters(model="maxwell", reduced_field=[5.0, 10.0], particles=640, tolerance=0.05))
        >>> _ = scan.save(path)                          # as before the first point
        >>> SwarmScan.resume(path, particles=640).finished   # a parameter given again must agree
        False
        """
        saved = read_checkpoint(path, CHECKPOINT_KIND)
        try:
            parameters = SwarmParameters.from_mapping(saved.parameters)
        except (KeyError, TypeError, ValueError) as error:
            raise CheckpointError(f"{path} is a damaged swarm checkpoint: {error}") from None
        results = [_saved_result(saved, index, entry) for index, entry in enumerate(saved.entry("results", "list"))]
        check_unchanged(parameters, given, path)
        digest = saved.entry("cross_sections_sha256", "text", optional=True)
        files = parameters.gas_files()
        if files and digest is not None and all(file.is_file() for file in files) \
                and gas_files_digest(files) != digest:
            raise ValueError(f"{', '.join(str(file) for file in files)} has changed since {path} was written (its "
                             "SHA-256 differs): a resumed scan must use the same cross sections")
        if [r.reduced_field for r in results] != list(parameters.reduced_field[: len(results)]):
            raise CheckpointError(f"{path} holds results for E/N = {[r.reduced_field for r in results]}, not the "
                                  f"first points of its scan {list(parameters.reduced_field)}")
        scan = cls(parameters, checkpoint=path if checkpoint is None else checkpoint, gas=gas, results=results,
                   save_every=save_every)
        scan._running = saved_running_point(saved, len(results), len(parameters.reduced_field))
        scan.annotations = saved.entry("annotations", "mapping", optional=True) or {}  # (none before they were saved)
        scan._running_source = path
        return scan

    def summary(self, files: Sequence = ()) -> dict[str, Any]:
        """The scan's results: :func:`swarm_summary` of its parameters and results.

        Examples
        --------
        >>> scan = SwarmScan(SwarmParameters(model="maxwell", reduced_field=[5.0, 10.0], particles=640, tolerance=0.05))
        >>> _ = scan.run()
        >>> [entry["E_N"] for entry in scan.summary()["results"]]
        [5.0, 10.0]
        """
        return swarm_summary(self.parameters, self.results, files)


def swarm_summary(parameters: SwarmParameters, results: Sequence[SwarmResult], files: Sequence = ()) -> dict[str, Any]:
    """The swarm command's JSON summary: one shape for Python and the shell.

    ``results`` holds one flat object per E/N point (every value with its
    ``*_error`` partner, ``E_N`` the point's E/N in Td); a scan of a single
    E/N also has that point's values at the top level, so a sweep point
    reads ``mean_energy`` directly. ``parameters`` reruns the scan.

    Examples
    --------
    >>> from collisionkit.transport import simulate_swarm
    >>> parameters = SwarmParameters(model="maxwell", reduced_field=10.0)
    >>> result = simulate_swarm(parameters.make_gas(), 10.0, particles=640, seed=1, tolerances={"mean_energy": 0.05})
    >>> summary = swarm_summary(parameters, [result])
    >>> summary["mean_energy"] == summary["results"][0]["mean_energy"], summary["parameters"]["model"]
    (True, 'maxwell')
    """
    entries = [result.to_dict() | {"E_N": result.reduced_field} for result in results]
    summary: dict[str, Any] = dict(entries[0]) if len(entries) == 1 else {}
    summary |= {"gas": parameters.gas_name(), "results": entries, "converged": all(r.converged for r in results),
                "files": [str(path) for path in files], "parameters": parameters.to_dict()}
    return summary


