"""The ``track`` command as a library object: a run in checkpointed chunks of primaries, and its summary.

:class:`TrackRun` runs the primaries of :class:`~collisionkit.transport.tracking.TrackParameters` in chunks,
writes a checkpoint after each (a crash loses one chunk at most) and resumes from it; every primary draws from
its own stream, so a resumed run ends with the numbers of an uninterrupted one. :func:`track_summary` is the
command's JSON summary::

    run = TrackRun(TrackParameters.from_sections(tables), checkpoint="run.npz")
    run.run()                                  # interrupted? then:
    run = TrackRun.resume("run.npz")
    run.run()
    run.summary()["gain"]
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from ..._io import CheckpointError, exclusive, read_checkpoint, write_checkpoint
from ..._params import check_unchanged
from ..gases import Gas
from ..scan import gas_files_digest
from .parameters import TrackParameters
from .result import TrackingResult
from .run import IonDrift, too_many_electrons, track

__all__ = ["TrackRun", "track_summary"]

CHECKPOINT_KIND = "track"
CHUNKS = 20  # a run is saved after each twentieth of its primaries (at least CHUNK_MIN of them)
CHUNK_MIN = 16
SPECTRUM_BINS = 50


class TrackRun:
    """A ``track`` run in chunks of primaries, checkpointed after each.

    Parameters
    ----------
    parameters : TrackParameters
    checkpoint : path, optional
        Written (``.npz``, atomically) after every chunk.
    gas : Gas, optional
        A gas built in Python (default: made from the parameters).
    threads : int, optional
        Worker threads (results do not depend on them).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "run.npz"
    >>> p = TrackParameters(model="maxwell", gap=1e-4, voltage=1.0, density=1e23, electrons=20, position=[0, 0, 5e-5])
    >>> run = TrackRun(p, checkpoint=path)
    >>> result = run.run()
    >>> TrackRun.resume(path).result.collected.tolist() == result.collected.tolist()
    True
    """

    def __init__(self, parameters: TrackParameters, checkpoint=None, gas: Gas | None = None,
                 threads: int | None = None, result: TrackingResult | None = None,
                 signal_window: float | None = None):
        if not isinstance(parameters, TrackParameters):
            raise TypeError(f"parameters must be TrackParameters; got {type(parameters).__name__}")
        self.parameters = parameters
        self.checkpoint = None if checkpoint is None else Path(checkpoint)
        self.device = parameters.device(gas)
        self.threads = threads
        self.result = result
        self.signal_window = signal_window

    @property
    def done(self) -> int:
        """Primaries finished so far."""
        return 0 if self.result is None else self.result.primaries

    @property
    def finished(self) -> bool:
        """True once every primary has been followed."""
        return self.done >= self.parameters.electrons

    def run(self, progress: Callable[[float], Any] | None = None) -> TrackingResult:
        """Follow the primaries not done yet; return the result of them all.

        ``progress(fraction)`` is called with the fraction of primaries done.

        Raises
        ------
        collisionkit.transport.tracking.ElectronLimitError
            If the avalanches follow more electrons than ``max_electrons``
            (counted as they go, or projected from the chunks done): the
            chunks done are saved in the checkpoint.

        Examples
        --------
        >>> p = TrackParameters(model="maxwell", gap=1e-4, voltage=1.0, density=1e23, electrons=4,
        ...                     position=[0, 0, 5e-5])
        >>> TrackRun(p).run().gain
        1.0
        """
        p = self.parameters
        chunk = max(CHUNK_MIN, math.ceil(p.electrons / CHUNKS))
        with exclusive(self.checkpoint):
            while not self.finished:
                count = min(chunk, p.electrons - self.done)
                done = self.done

                def report(fraction, done=done, count=count):
                    if progress is not None:
                        progress((done + fraction * count) / p.electrons)

                followed = 0 if self.result is None else int(self.result.records.shape[0])
                if done and followed / done * p.electrons > p.max_electrons:
                    raise too_many_electrons(p.max_electrons, followed / done * p.electrons,
                                             f"the first {done} primaries made {followed / done:.3g} electrons each: "
                                             f"{p.electrons} primaries would follow about", stopped=True)
                part = track(self.device, primaries=count, position=p.positions()[0], energy=p.energy,
                             direction=p.direction, method=p.method, seed=p.seed, sharing=p.sharing,
                             ions=None if p.ion_mobility is None else IonDrift(p.ion_mobility),
                             tolerance=p.tolerance, signal_window=self.signal_window or "auto",
                             first_primary=done, threads=self.threads, progress=report,
                             max_electrons=max(1, p.max_electrons - followed),
                             record_points=2000 if done == 0 else 0)
                if self.signal_window is None:
                    self.signal_window = part.signal_step * part.signal.size if part.signal.size else None
                self.result = part if self.result is None else TrackingResult.combine([self.result, part])
                self.save()
        if progress is not None:
            progress(1.0)
        return self.result

    def save(self, path=None) -> Path | None:
        """Write the checkpoint (to ``path``, default the run's); None if there is none.

        Examples
        --------
        >>> TrackRun(TrackParameters(model="reid", gap=1e-3)).save() is None
        True
        """
        path = self.checkpoint if path is None else Path(path)
        if path is None:
            return None
        state = {"done": self.done, "signal_window": self.signal_window,
                 "cross_sections_sha256": gas_files_digest(self.parameters.swarm_parameters().gas_files())}
        arrays = {} if self.result is None else {f"result_{k}": v for k, v in self.result.to_arrays().items()}
        return write_checkpoint(path, CHECKPOINT_KIND, self.parameters.to_dict(), state, arrays)

    @classmethod
    def resume(cls, path, checkpoint=None, gas: Gas | None = None, threads: int | None = None,
               **given) -> TrackRun:
        """The run saved in ``path``; parameters given again must equal the saved ones.

        Raises
        ------
        ValueError
            If the file is not a track checkpoint or a damaged one, a
            parameter differs, or a cross-section file changed since.

        Examples
        --------
        >>> import pathlib, tempfile
        >>> path = pathlib.Path(tempfile.mkdtemp()) / "run.npz"
        >>> _ = TrackRun(TrackParameters(model="reid", gap=1e-3), checkpoint=path).save()
        >>> TrackRun.resume(path, gap=1e-3).done
        0
        """
        saved = read_checkpoint(path, CHECKPOINT_KIND)
        try:
            parameters = TrackParameters.from_mapping(saved.parameters)
        except (KeyError, TypeError, ValueError) as error:
            raise CheckpointError(f"{path} is a damaged track checkpoint: {error}") from None
        check_unchanged(parameters, given, path)
        digest = saved.entry("cross_sections_sha256", "text", optional=True)
        files = parameters.swarm_parameters().gas_files()
        if digest is not None and all(Path(f).is_file() for f in files) and gas_files_digest(files) != digest:
            raise ValueError(f"the cross-section files of {path} have changed since it was written: a resumed run "
                             "must use the same cross sections")
        done = saved.entry("done", "integer", 0, parameters.electrons)
        window = saved.entry("signal_window", "number", 0.0, optional=True)
        result = None
        if done:
            try:
                result = TrackingResult.from_arrays({k[len("result_"):]: v for k, v in saved.arrays.items()
                                                     if k.startswith("result_")})
            except (KeyError, TypeError, ValueError) as error:
                raise saved.damaged(f"its result cannot be read ({error})") from None
            if result.primaries != done:
                raise saved.damaged(f"it holds {result.primaries} primaries, not the {done} it says")
        return cls(parameters, checkpoint=path if checkpoint is None else checkpoint, gas=gas, threads=threads,
                   result=result, signal_window=window)

    def summary(self, files=()) -> dict[str, Any]:
        """:func:`track_summary` of the run so far.

        Examples
        --------
        >>> p = TrackParameters(model="maxwell", gap=1e-4, voltage=1.0, density=1e23, electrons=4,
        ...                     position=[0, 0, 5e-5])
        >>> run = TrackRun(p)
        >>> _ = run.run()
        >>> run.summary()["gain"]
        1.0
        """
        if self.result is None:
            raise ValueError("the run has no result yet: call run() first")
        return track_summary(self.parameters, self.result, files)


def _plain(values) -> list:
    return [float(v) if math.isfinite(v) else None for v in np.asarray(values, dtype=float).reshape(-1)]


def track_summary(parameters: TrackParameters, result: TrackingResult, files=()) -> dict[str, Any]:
    """The ``track`` command's JSON summary: ``gain`` and ``drift_time`` with their ``*_error`` partners, the
    gain's distribution (Polya theta), the spectra, profiles, the induced current and the run's counts.

    Examples
    --------
    >>> p = TrackParameters(model="maxwell", gap=1e-4, voltage=1.0, density=1e23, electrons=4,
    ...                     position=[0, 0, 5e-5])
    >>> summary = track_summary(p, TrackRun(p).run())
    >>> summary["gain"], summary["gain_error"], sorted(summary["arrival_time_spectrum"])
    (1.0, 0.0, ['counts', 'edges'])
    """
    theta, theta_error = result.polya_theta()
    electrons = result.electrons
    ionizations = result.process_counts("ionization")
    entry = {
        "gain": result.gain, "gain_error": result.gain_error,
        "drift_time": result.drift_time, "drift_time_error": result.drift_time_error,
        "electrons_per_primary": float(electrons.mean()),
        "electrons_per_primary_error": float(electrons.std(ddof=1) / math.sqrt(electrons.size))
        if electrons.size > 1 else math.nan,
        "ionizations_per_primary": float(ionizations.mean()),
        "polya_theta": theta, "polya_theta_error": theta_error,
        "induced_charge": float(result.induced_charge.mean()),
        "induced_charge_error": float(result.induced_charge.std(ddof=1) / math.sqrt(result.primaries))
        if result.primaries > 1 else math.nan,
    }
    for name, key in (("arrival_time_spectrum", "arrival"), ("energy_spectrum", "energy")):
        if result.collected_records().shape[0]:
            edges, counts = getattr(result, name)(SPECTRUM_BINS)
            entry[name] = {"edges": _plain(edges), "counts": _plain(counts)}
        else:
            entry[name] = {"edges": [], "counts": []}
    edges, ionization = result.profile("ionization")
    entry["profiles"] = {"coordinate": result.profile_coordinate, "edges": _plain(edges),
                         "ionization": _plain(ionization), "excitation": _plain(result.profile("excitation")[1])}
    edges, current = result.current()
    entry["current"] = {"edges": _plain(edges), "current": _plain(current)}
    gains, fractions = result.gain_distribution()
    entry["gain_distribution"] = {"gain": [int(g) for g in gains], "fraction": _plain(fractions)}
    if result.ion_records.shape[0]:
        times = result.ion_records[:, 3] - result.ion_records[:, 10]
        entry["ion_drift_time"] = float(times.mean())
        entry["ion_drift_time_error"] = float(times.std(ddof=1) / math.sqrt(times.size)) if times.size > 1 else None
    entry |= {"primaries": result.primaries, "collisions": int(result.collisions.sum()),
              "null_collisions": result.null_collisions, "steps": result.steps, "seconds": result.seconds,
              "method": result.method, "collector": result.collector, "surfaces": list(result.surfaces),
              "gas": parameters.swarm_parameters().gas_name(), "files": [str(path) for path in files],
              "parameters": parameters.to_dict()}
    return entry
