"""The result of a tracking run: per-primary counts, end records, spectra, profiles, signals and samples.

Every average comes with a standard error over the independent primaries
(the avalanche of each primary is independent of the others): the gain is
the mean number of electrons that reach the collecting electrode per
primary; the drift time the mean time at which they reach it (measured from
the release of their primary), a ratio of per-primary sums whose error
follows from the delta method.

:class:`TrackingResult` holds the arrays and answers the questions; the
estimators behind its answers are in ``_result_statistics`` and its joined
and stored forms (:meth:`~TrackingResult.combine`, the checkpoint arrays)
in ``_result_arrays``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields

import numpy as np
from scipy import constants

from ..._kernels.transport.tracking import codes as _c
from ._result_arrays import combined_values, field_arrays, values_from_arrays
from ._result_statistics import arrival_sums, mean_and_error as _mean_and_error
from ._result_statistics import polya_theta as _polya_theta  # noqa: F401 (the name polya_theta's example imports)
from ._result_statistics import polya_theta_and_error, records_at_collector, swarm_coefficients
from ..._repr import dataclass_repr

__all__ = ["TrackingResult", "ratio_and_error"]

EV = constants.e
STATUS_NAMES = {_c.ENDED_SURFACE: "surface", _c.ENDED_ATTACHED: "attached", _c.ENDED_TIME: "time-limit",
                _c.ENDED_OUTSIDE_FIELD: "outside-field", _c.ENDED_STEPS: "steps"}


def ratio_and_error(numerators, denominators) -> tuple[float, float]:
    """sum(a) / sum(b) over independent units and its standard error (delta method).

    Var(R) ~ Var(a - R b) / (n mean(b)^2).

    Examples
    --------
    >>> ratio_and_error([2.0, 4.0, 6.0], [1.0, 2.0, 3.0])
    (2.0, 0.0)
    """
    a = np.asarray(numerators, dtype=float)
    b = np.asarray(denominators, dtype=float)
    total = b.sum()
    if a.size == 0 or total == 0:
        return math.nan, math.nan
    ratio = float(a.sum() / total)
    if a.size < 2:
        return ratio, math.nan
    residual = a - ratio * b
    return ratio, float(np.sqrt(residual.var(ddof=1) / a.size) / b.mean())


@dataclass
class TrackingResult:
    """What a tracking run measured (SI units; energies in eV where named so).

    Per primary (arrays of length ``primaries``): ``electrons`` followed
    (the primary and its secondaries), ``collected`` at the collecting
    electrode, ``collisions`` per process (``primaries x processes``, columns
    in ``process_labels`` order), ``induced_charge`` (the integral of the
    electrons' induced current on the readout electrode, C, when the run
    records the current; otherwise the next) and ``weighting_charge`` (the
    same from the weighting potential at the ends of every path,
    -q (phi_w(end) - phi_w(start)), C, exact for a static weighting field),
    and the same two for the ions.

    ``records``: one row per electron that ended (see
    :mod:`collisionkit._kernels.transport.tracking.codes`: primary, status,
    surface, time, position, velocity, birth time); ``ion_records`` likewise
    for drifted ions. ``signal`` and ``ion_signal``: the induced charge per
    time bin of width ``signal_step`` from 0 (C per bin, summed over the
    primaries). ``profiles``: ionizations and excitations per bin of the
    profile coordinate over ``profile_edges`` (summed). ``moments``: per
    group and sample time, sums of 1, r, r^2, v, kinetic energy, r_k v_k.
    ``points``: (particle, t, x, y, z) along a few tracks; ``mass``: the
    tracked particle's (kg).

    Examples
    --------
    >>> from collisionkit.transport import maxwell_model
    >>> from collisionkit.transport.tracking import Device, track
    >>> device = Device.parallel_plate(maxwell_model(1e-13, mass=1e-29), 1e-4, 10.0, density=1e23)
    >>> result = track(device, primaries=20, position=(0, 0, 5e-5), seed=1)
    >>> result.gain, result.primaries
    (1.0, 20)
    """

    __repr__ = dataclass_repr  # arrays by their shape, not printed whole

    primaries: int
    surfaces: tuple
    collector: str | None
    process_labels: tuple
    process_kinds: tuple
    electrons: np.ndarray
    collected: np.ndarray
    collisions: np.ndarray
    null_collisions: int
    steps: int
    rejected_steps: int
    particle_time: float
    induced_charge: np.ndarray
    weighting_charge: np.ndarray
    records: np.ndarray
    ion_records: np.ndarray
    ion_induced_charge: np.ndarray
    signal: np.ndarray
    ion_signal: np.ndarray
    signal_step: float
    profile_coordinate: str
    profile_edges: np.ndarray
    profiles: np.ndarray
    sample_times: np.ndarray
    moments: np.ndarray
    seconds: float
    method: str
    points: np.ndarray = field(default_factory=lambda: np.zeros((0, 5)))
    mass: float = constants.m_e

    # ------------------------------------------------------------------ gain and drift

    def collected_records(self) -> np.ndarray:
        """The end records of the electrons that reached the collecting electrode.

        Examples
        --------
        >>> from collisionkit.transport import maxwell_model
        >>> from collisionkit.transport.tracking import Device, track
        >>> device = Device.parallel_plate(maxwell_model(1e-13, mass=1e-29), 1e-4, 10.0, density=1e23)
        >>> track(device, primaries=3, position=(0, 0, 5e-5), seed=1).collected_records().shape
        (3, 11)
        """
        return records_at_collector(self.records, self.surfaces, self.collector)

    @property
    def gain(self) -> float:
        """Mean number of electrons reaching the collecting electrode per primary."""
        return _mean_and_error(self.collected)[0]

    @property
    def gain_error(self) -> float:
        """Standard error of :attr:`gain`."""
        return _mean_and_error(self.collected)[1]

    def _per_primary_times(self):
        return arrival_sums(self.collected_records(), self.primaries)

    @property
    def drift_time(self) -> float:
        """Mean time (s) at which the electrons reach the collecting electrode, from the release of their primary."""
        return ratio_and_error(*self._per_primary_times())[0]

    @property
    def drift_time_error(self) -> float:
        """Standard error of :attr:`drift_time`."""
        return ratio_and_error(*self._per_primary_times())[1]

    def process_counts(self, kind: str) -> np.ndarray:
        """Collisions of every process of ``kind`` (``"ionization"`` ...) per primary.

        Examples
        --------
        >>> from collisionkit.transport import maxwell_model
        >>> from collisionkit.transport.tracking import Device, track
        >>> device = Device.parallel_plate(maxwell_model(1e-13, mass=1e-29), 1e-4, 10.0, density=1e23)
        >>> track(device, primaries=2, position=(0, 0, 5e-5), seed=1).process_counts("ionization").tolist()
        [0.0, 0.0]
        """
        mine = np.array([k == kind for k in self.process_kinds], dtype=bool)
        return self.collisions[:, mine].sum(axis=1) if mine.any() else np.zeros(self.primaries)

    # ------------------------------------------------------------------ spectra

    def arrival_time_spectrum(self, bins: int = 50) -> tuple[np.ndarray, np.ndarray]:
        """(bin edges in s, electrons per primary in each bin) of the arrival times at the collecting electrode.

        Examples
        --------
        >>> from collisionkit.transport import maxwell_model
        >>> from collisionkit.transport.tracking import Device, track
        >>> device = Device.parallel_plate(maxwell_model(1e-13, mass=1e-29), 1e-4, 10.0, density=1e23)
        >>> edges, counts = track(device, primaries=5, position=(0, 0, 5e-5), seed=1).arrival_time_spectrum(4)
        >>> float(counts.sum())
        1.0
        """
        times = self.collected_records()[:, _c.RECORD_TIME]
        counts, edges = np.histogram(times, bins=bins)
        return edges, counts / max(self.primaries, 1)

    def energies(self, records=None) -> np.ndarray:
        """Kinetic energies (eV) of end records (default: those at the collecting electrode) of the tracked particle.

        Examples
        --------
        >>> from collisionkit.transport import maxwell_model
        >>> from collisionkit.transport.tracking import Device, track
        >>> device = Device.parallel_plate(maxwell_model(1e-13, mass=1e-29), 1e-4, 10.0, density=1e23)
        >>> bool((track(device, primaries=2, position=(0, 0, 5e-5), seed=1).energies() > 0).all())
        True
        """
        records = self.collected_records() if records is None else records
        v = records[:, _c.RECORD_VX:_c.RECORD_VZ + 1]
        return 0.5 * self.mass * (v**2).sum(axis=1) / EV

    def energy_spectrum(self, bins: int = 50) -> tuple[np.ndarray, np.ndarray]:
        """(bin edges in eV, electrons per primary and eV) of the energies at the collecting electrode.

        Examples
        --------
        >>> from collisionkit.transport import maxwell_model
        >>> from collisionkit.transport.tracking import Device, track
        >>> device = Device.parallel_plate(maxwell_model(1e-13, mass=1e-29), 1e-4, 10.0, density=1e23)
        >>> edges, density = track(device, primaries=5, position=(0, 0, 5e-5), seed=1).energy_spectrum(4)
        >>> round(float((density * (edges[1] - edges[0])).sum()), 12)
        1.0
        """
        counts, edges = np.histogram(self.energies(), bins=bins)
        width = np.diff(edges)
        return edges, counts / max(self.primaries, 1) / np.where(width > 0, width, 1.0)

    def gain_distribution(self) -> tuple[np.ndarray, np.ndarray]:
        """(gains, fraction of primaries) of the gain's distribution (every value that occurred).

        Examples
        --------
        >>> from collisionkit.transport import maxwell_model
        >>> from collisionkit.transport.tracking import Device, track
        >>> device = Device.parallel_plate(maxwell_model(1e-13, mass=1e-29), 1e-4, 10.0, density=1e23)
        >>> track(device, primaries=4, position=(0, 0, 5e-5), seed=1).gain_distribution()
        (array([1]), array([1.]))
        """
        values, counts = np.unique(self.collected.astype(np.int64), return_counts=True)
        return values, counts / counts.sum()

    def polya_theta(self) -> tuple[float, float]:
        """The Polya parameter theta of the gain distribution from its moments, var/mean^2 = 1/(1 + theta) - 1/mean
        (0 for the exponential Yule-Furry law), with a standard error by the jackknife over primaries.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.transport.tracking.result import _polya_theta
        >>> gains = np.random.default_rng(1).geometric(1 / 200.0, 200000)  # Yule-Furry, mean 200
        >>> bool(abs(_polya_theta(gains)) < 0.02)
        True
        """
        return polya_theta_and_error(self.collected.astype(float))

    # ------------------------------------------------------------------ signals and profiles

    def current(self, ions: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """(bin edges in s, induced current in A per primary) on the readout electrode: electrons (and ions).

        Examples
        --------
        >>> from collisionkit.transport import maxwell_model
        >>> from collisionkit.transport.tracking import Device, track
        >>> device = Device.parallel_plate(maxwell_model(1e-13, mass=1e-29), 1e-4, 10.0, density=1e23)
        >>> edges, current = track(device, primaries=4, position=(0, 0, 5e-5), seed=1).current()
        >>> edges.size == current.size + 1
        True
        """
        total = self.signal + (self.ion_signal if ions else 0.0)
        edges = np.arange(total.size + 1) * self.signal_step
        return edges, total / max(self.primaries, 1) / self.signal_step

    def profile(self, kind: str = "ionization") -> tuple[np.ndarray, np.ndarray]:
        """(bin edges in m, events per primary and metre) of ``ionization`` or ``excitation`` along the profile
        coordinate (z for plates, the distance from the wire for a counter).

        Examples
        --------
        >>> from collisionkit.transport import maxwell_model
        >>> from collisionkit.transport.tracking import Device, track
        >>> device = Device.parallel_plate(maxwell_model(1e-13, mass=1e-29), 1e-4, 10.0, density=1e23)
        >>> edges, rate = track(device, primaries=2, position=(0, 0, 5e-5), seed=1).profile("excitation")
        >>> float(rate.sum())
        0.0
        """
        row = {"ionization": 0, "excitation": 1}.get(kind)
        if row is None:
            raise ValueError(f"kind must be 'ionization' or 'excitation'; got {kind!r}")
        width = np.diff(self.profile_edges)
        counts = self.profiles[row] if self.profiles.shape[1] else np.zeros(0)
        return self.profile_edges, counts / max(self.primaries, 1) / np.where(width > 0, width, 1.0)

    # ------------------------------------------------------------------ transport in an unbounded gas

    def transport(self, start: float = 0.5) -> dict[str, tuple[float, float]]:
        """Swarm coefficients from the sampled moments, fitted over the samples from fraction ``start`` of the run
        on: bulk drift velocity W (along z, m/s), N-less bulk D_L and D_T (m^2/s) and the mean energy (eV),
        each with its standard error over the groups.

        Examples
        --------
        >>> from collisionkit.transport import maxwell_model
        >>> from collisionkit.transport.tracking import Device, UniformField, track
        >>> device = Device(maxwell_model(1e-13, mass=1e-29), 1e23, 0.0, UniformField((0, 0, 1e3)))
        >>> result = track(device, primaries=64, sample_times=[1e-10, 2e-10, 3e-10], seed=1)
        >>> sorted(result.transport())
        ['diffusion_L', 'diffusion_T', 'drift_velocity', 'mean_energy']
        """
        if self.sample_times.size < 2:
            raise ValueError("the run sampled fewer than 2 times: give sample_times to track()")
        return swarm_coefficients(self.sample_times, self.moments, start)

    # ------------------------------------------------------------------ combining and saving

    @classmethod
    def combine(cls, parts) -> TrackingResult:
        """One result from the results of consecutive batches of primaries of the same run.

        Examples
        --------
        >>> from collisionkit.transport import maxwell_model
        >>> from collisionkit.transport.tracking import Device, track
        >>> device = Device.parallel_plate(maxwell_model(1e-13, mass=1e-29), 1e-4, 10.0, density=1e23)
        >>> part = track(device, primaries=2, position=(0, 0, 5e-5), seed=1)
        >>> TrackingResult.combine([part, part]).primaries
        4
        """
        parts = list(parts)
        if not parts:
            raise ValueError("combine needs at least one result")
        return cls(**combined_values([item.name for item in fields(cls)], parts))

    def to_arrays(self) -> dict[str, np.ndarray]:
        """Every field as an array (for a checkpoint); :meth:`from_arrays` reads them back.

        Examples
        --------
        >>> from collisionkit.transport import maxwell_model
        >>> from collisionkit.transport.tracking import Device, track
        >>> device = Device.parallel_plate(maxwell_model(1e-13, mass=1e-29), 1e-4, 10.0, density=1e23)
        >>> result = track(device, primaries=2, position=(0, 0, 5e-5), seed=1)
        >>> TrackingResult.from_arrays(result.to_arrays()).collected.tolist() == result.collected.tolist()
        True
        """
        return field_arrays(self, [item.name for item in fields(self)])

    @classmethod
    def from_arrays(cls, arrays) -> TrackingResult:
        """The result saved by :meth:`to_arrays` (KeyError or ValueError if an entry is missing or damaged).

        Examples
        --------
        >>> TrackingResult.from_arrays({})
        Traceback (most recent call last):
        ...
        KeyError: 'primaries'
        """
        return cls(**values_from_arrays([item.name for item in fields(cls)], arrays))
