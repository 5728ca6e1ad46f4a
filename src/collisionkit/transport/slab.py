"""The slab problem of Krasov, sec. 5.5: a beam through a layer of scattering matter.

Particles enter a slab ``0 <= x <= d`` (d in mean free paths) at x = 0,
fly free paths ``s = -ln(xi)``, and at each collision are absorbed with
probability ``1 - albedo`` or scattered: isotropically in the laboratory
(heavy targets), isotropically in the centre-of-mass frame of a target of
mass ratio ``A = M/m`` (energy loss, as for neutrons), or, in the rod model,
forward or backward with probability 1/2. Transmission is leaving at
``x > d``, reflection leaving at ``x < 0``.

Histories are split into batches with their own streams
(``SeedSequence.spawn``); errors are the binomial standard errors, and the
batches are run in parallel threads without changing the result.
"""

from __future__ import annotations

import math
import os
import threading
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor, wait
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._arrays import seed_value
from .._kernels import transport as _k
from ._validation import integer_in_range, real_in_range
from .._repr import dataclass_repr

__all__ = ["SlabResult", "simulate_slab", "INCIDENCES"]

INCIDENCES = ("normal", "isotropic")
BATCHES = 64
# collisions in one kernel call of a batch at most (a few milliseconds): Ctrl-C waits for no more
COLLISIONS_PER_CALL = 1 << 18
# how often the progress callback hears of the histories finished
PROGRESS_SECONDS = 0.2


@dataclass
class SlabResult:
    """Transmission, reflection and absorption probabilities with standard errors.

    ``angle_edges`` bins the exit direction cosine |mu| in [0, 1];
    ``transmitted_angles`` and ``reflected_angles`` are the fractions of all
    histories per bin; ``energy_edges`` (units of the incident energy) and
    ``transmitted_energies``, ``reflected_energies`` likewise.

    Examples
    --------
    >>> from collisionkit.transport import simulate_slab
    >>> result = simulate_slab(1.0, 1.0, particles=2000, seed=1)
    >>> round(result.transmission + result.reflection, 12)
    1.0
    """

    __repr__ = dataclass_repr  # arrays by their shape, not printed whole

    thickness: float
    albedo: float
    incidence: str
    model: str
    particles: int
    transmission: float
    transmission_error: float
    reflection: float
    reflection_error: float
    absorption: float
    absorption_error: float
    collisions_per_particle: float
    angle_edges: np.ndarray
    transmitted_angles: np.ndarray
    reflected_angles: np.ndarray
    energy_edges: np.ndarray
    transmitted_energies: np.ndarray
    reflected_energies: np.ndarray

    def to_dict(self) -> dict:
        """A JSON-ready dictionary.

        Examples
        --------
        >>> import json
        >>> from collisionkit.transport import simulate_slab
        >>> data = simulate_slab(1.0, 0.5, particles=1000, seed=1).to_dict()
        >>> data["albedo"], len(json.dumps(data)) > 100
        (0.5, True)
        """
        return {name: (value.tolist() if isinstance(value, np.ndarray) else value)
                for name, value in self.__dict__.items()}


def _run_batches(seed, particles, threads, progress, physics):
    """The BATCHES batches' counts, angle and energy histograms, run in ``threads`` threads.

    Each batch's kernel calls end after at most ``COLLISIONS_PER_CALL``
    collisions; the workers stop between calls once the main thread is
    interrupted, and the main thread reports the histories finished.
    """
    sequences = np.random.SeedSequence(seed).spawn(BATCHES)
    left = np.full(BATCHES, particles // BATCHES)
    left[: particles % BATCHES] += 1
    angle_bins, energy_bins = physics[-2:]
    counts = np.zeros((BATCHES, 4))
    angles = np.zeros((BATCHES, 2, angle_bins))
    energies = np.zeros((BATCHES, 2, energy_bins))
    stop = threading.Event()

    def work(b):
        state = sequences[b].generate_state(4, np.uint64)
        flight = np.zeros(_k.FLIGHT_SIZE)
        while left[b] > 0 and not stop.is_set():
            left[b] -= _k.slab_batch(state, flight, int(left[b]), COLLISIONS_PER_CALL, *physics, counts[b],
                                     angles[b], energies[b])

    with ThreadPoolExecutor(threads) as pool:
        try:
            pending = {pool.submit(work, b) for b in range(BATCHES)}
            while pending:
                done, pending = wait(pending, timeout=PROGRESS_SECONDS)
                for future in done:
                    future.result()
                if progress is not None:
                    progress(1.0 - float(left.sum()) / particles)
        except BaseException:
            stop.set()  # the workers end within one kernel call; the pool waits for them
            raise
    return counts, angles, energies


def _fraction(count, total):
    p = count / total
    return float(p), float(math.sqrt(max(p * (1.0 - p), 0.0) / total))


def simulate_slab(thickness, albedo=1.0, *, incidence="normal", model="isotropic", mass_ratio=math.inf,
                  particles=100_000, seed=0, angle_bins=20, energy_bins=20, threads=None,
                  progress: Callable[[float], Any] | None = None) -> SlabResult:
    r"""Transmission and reflection of particles through a slab (Krasov, sec. 5.5).

    Parameters
    ----------
    thickness : float
        Slab thickness d in mean free paths (finite, >= 0).
    albedo : float
        Single-scattering albedo in [0, 1] (probability to scatter, not be absorbed).
    incidence : {"normal", "isotropic"}
        A normal beam, or an isotropic incident flux (direction cosine mu = sqrt(xi)).
    model : {"isotropic", "rod"}
        3D isotropic scattering, or the 1D rod model (forward/backward, 1/2 each).
    mass_ratio : float
        Target mass / particle mass A (1 ... inf; 1: equal masses, as neutrons on
        hydrogen, which never turn back in one collision) for the 3D model; scattering is
        isotropic in the centre-of-mass frame (energy after / before =
        (A^2 + 2 A cos chi + 1)/(A + 1)^2); inf keeps the energy.
    particles : int
        Histories (>= 64).
    seed : int or numpy.random.Generator
        Random seed (>= 0), or a Generator that draws one.
    angle_bins, energy_bins : int
        Bins of the exit cosine and energy distributions (1 to 10000).
    threads : int
        Worker threads (>= 1; default: all cores); the result does not depend on it.
    progress : callable, optional
        ``progress(fraction)``: the fraction of the histories finished, in [0, 1].
        Ctrl-C stops the run within a kernel call's budget of collisions
        (``COLLISIONS_PER_CALL``, milliseconds), however thick the slab.

    Returns
    -------
    SlabResult

    Raises
    ------
    TypeError
        If a numeric argument is not a real number (bools are refused) or an integer where one is needed.
    ValueError
        If an argument is out of its range; the message names it and the range.

    Notes
    -----
    Exact checks: the rod model with pure scattering gives T = 1/(1 + d/2);
    with albedo 1, R + T = 1; pure absorption gives T = exp(-d) for normal
    incidence and T = 2 E_3(d) for isotropic incidence.

    Examples
    --------
    >>> from collisionkit.transport import simulate_slab
    >>> r = simulate_slab(2.0, model="rod", particles=20000, seed=1, threads=1)
    >>> abs(r.transmission - 0.5) < 4 * r.transmission_error
    True
    """
    thickness = real_in_range(thickness, "thickness (mean free paths)", 0.0, inclusive=(True, False))
    albedo = real_in_range(albedo, "albedo", 0.0, 1.0, inclusive=(True, True))
    if not (isinstance(incidence, str) and incidence in INCIDENCES):
        raise ValueError(f"incidence must be one of {INCIDENCES}; got {incidence!r}")
    if not (isinstance(model, str) and model in ("isotropic", "rod")):
        raise ValueError(f"model must be 'isotropic' or 'rod'; got {model!r}")
    mass_ratio = real_in_range(mass_ratio, "mass_ratio (inf for no energy loss)", 1.0, inclusive=(True, True))
    if model == "rod" and (incidence != "normal" or math.isfinite(mass_ratio)):
        raise ValueError("the rod model is one-dimensional and elastic: it takes incidence='normal' and "
                         f"mass_ratio=inf; got incidence={incidence!r}, mass_ratio={mass_ratio}")
    particles = integer_in_range(particles, "particles", BATCHES)
    seed = integer_in_range(seed_value(seed), "seed", 0)
    angle_bins = integer_in_range(angle_bins, "angle_bins", 1, 10_000)
    energy_bins = integer_in_range(energy_bins, "energy_bins", 1, 10_000)
    threads = (os.cpu_count() or 1) if threads is None else integer_in_range(threads, "threads", 1)
    counts, angles, energies = _run_batches(
        seed, particles, threads, progress,
        (float(thickness), float(albedo), incidence == "isotropic", model == "rod", float(mass_ratio), angle_bins,
         energy_bins),
    )
    total = counts.sum(axis=0)
    transmission, reflection, absorption = (_fraction(total[k], particles) for k in range(3))
    return SlabResult(
        thickness=float(thickness), albedo=float(albedo), incidence=incidence, model=model, particles=int(particles),
        transmission=transmission[0], transmission_error=transmission[1],
        reflection=reflection[0], reflection_error=reflection[1],
        absorption=absorption[0], absorption_error=absorption[1],
        collisions_per_particle=float(total[3] / particles),
        angle_edges=np.linspace(0.0, 1.0, angle_bins + 1),
        transmitted_angles=angles[:, 0].sum(axis=0) / particles,
        reflected_angles=angles[:, 1].sum(axis=0) / particles,
        energy_edges=np.linspace(0.0, 1.0, energy_bins + 1),
        transmitted_energies=energies[:, 0].sum(axis=0) / particles,
        reflected_energies=energies[:, 1].sum(axis=0) / particles,
    )
