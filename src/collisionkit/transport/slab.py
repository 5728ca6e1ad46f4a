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
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._arrays import seed_value
from ._slab_batches import BATCHES, COLLISIONS_PER_CALL, SlabBatches, run_batches, slab_physics  # noqa: F401
from ._validation import integer_in_range, real_in_range
from .._repr import dataclass_repr

__all__ = ["SlabResult", "simulate_slab", "slab_result", "INCIDENCES"]

INCIDENCES = ("normal", "isotropic")


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
    batches = SlabBatches.start(seed, particles, angle_bins, energy_bins)
    run_batches(batches, threads, progress,
                 slab_physics(thickness, albedo, incidence, model, mass_ratio, angle_bins, energy_bins))
    return slab_result(batches, thickness, albedo, incidence, model)


def slab_result(batches: SlabBatches, thickness, albedo, incidence, model) -> SlabResult:
    """The result of finished ``batches``: the fractions of all histories, their binomial errors, the histograms.

    Examples
    --------
    >>> batches = SlabBatches.start(seed=1, particles=640, angle_bins=4, energy_bins=4)
    >>> run_batches(batches, 1, None, slab_physics(1.0, 1.0, "normal", "rod", math.inf, 4, 4))
    >>> result = slab_result(batches, 1.0, 1.0, "normal", "rod")
    >>> result.particles, result.transmission + result.reflection
    (640, 1.0)
    """
    particles = batches.done + int(batches.left.sum())
    total = batches.counts.sum(axis=0)
    transmission, reflection, absorption = (_fraction(total[k], particles) for k in range(3))
    angle_bins, energy_bins = batches.angles.shape[-1], batches.energies.shape[-1]
    return SlabResult(
        thickness=float(thickness), albedo=float(albedo), incidence=incidence, model=model, particles=int(particles),
        transmission=transmission[0], transmission_error=transmission[1],
        reflection=reflection[0], reflection_error=reflection[1],
        absorption=absorption[0], absorption_error=absorption[1],
        collisions_per_particle=float(total[3] / particles),
        angle_edges=np.linspace(0.0, 1.0, angle_bins + 1),
        transmitted_angles=batches.angles[:, 0].sum(axis=0) / particles,
        reflected_angles=batches.angles[:, 1].sum(axis=0) / particles,
        energy_edges=np.linspace(0.0, 1.0, energy_bins + 1),
        transmitted_energies=batches.energies[:, 0].sum(axis=0) / particles,
        reflected_energies=batches.energies[:, 1].sum(axis=0) / particles,
    )
