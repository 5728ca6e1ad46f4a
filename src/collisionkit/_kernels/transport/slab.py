"""The slab problem (Krasov, sec. 5.5): histories of particles through a layer of scattering matter."""

from __future__ import annotations

import math

from ..._jit import kernel
from .rng import uniform


# slots of a batch's in-flight history (``flight``), kept between calls of :func:`slab_batch`
FLIGHT_X, FLIGHT_MU, FLIGHT_ENERGY, FLIGHT_ACTIVE = 0, 1, 2, 3
FLIGHT_SIZE = 4


@kernel
def slab_batch(state, flight, count, max_collisions, thickness, albedo, isotropic_incidence, rod, mass_ratio,
               angle_bins, energy_bins, out_counts, angle_hist, energy_hist):
    """Go on with a batch's histories through a slab 0 <= x <= thickness (unit mean free path); return those finished.

    Free paths s = -ln(xi) (Krasov, sec. 5.5); at a collision the particle
    is absorbed with probability 1 - albedo, else scattered isotropically in
    the centre-of-mass frame of a target of ``mass_ratio`` = M/m (inf: no
    energy loss, isotropic in the lab) or, for the rod model, forward or
    backward with probability 1/2. Energies are in units of the incident
    energy. ``out_counts`` += (transmitted, reflected, absorbed, collisions).

    The call returns after ``count`` histories have ended or after
    ``max_collisions`` collisions, whichever comes first; a history cut
    short waits in ``flight`` (x, mu, energy, active) for the next call,
    which draws the same random numbers it would have drawn (the result
    does not depend on the budget). A thick slab's single history can take
    d^2 collisions: the budget keeps a call short, so the caller can stop.
    """
    finished = 0
    collisions = 0
    while finished < count:
        if flight[FLIGHT_ACTIVE] == 0.0:
            if rod or not isotropic_incidence:
                mu = 1.0
            else:
                mu = math.sqrt(uniform(state))  # isotropic flux: current density 2 mu
            x = 0.0
            energy = 1.0
            flight[FLIGHT_ACTIVE] = 1.0
        else:
            x, mu, energy = flight[FLIGHT_X], flight[FLIGHT_MU], flight[FLIGHT_ENERGY]
        while True:
            if collisions >= max_collisions:
                flight[FLIGHT_X], flight[FLIGHT_MU], flight[FLIGHT_ENERGY] = x, mu, energy
                return finished
            x += mu * -math.log(uniform(state))
            if x >= thickness:
                out_counts[0] += 1.0
                angle_hist[0, min(angle_bins - 1, int(mu * angle_bins))] += 1.0
                energy_hist[0, min(energy_bins - 1, int(energy * energy_bins))] += 1.0
                break
            if x < 0.0:
                out_counts[1] += 1.0
                angle_hist[1, min(angle_bins - 1, int(-mu * angle_bins))] += 1.0
                energy_hist[1, min(energy_bins - 1, int(energy * energy_bins))] += 1.0
                break
            collisions += 1
            out_counts[3] += 1.0
            if uniform(state) >= albedo:
                out_counts[2] += 1.0
                break
            if rod:
                mu = 1.0 if uniform(state) < 0.5 else -1.0
            elif math.isinf(mass_ratio):
                mu = 2.0 * uniform(state) - 1.0
            else:
                mu, energy = elastic_lab(mu, energy, mass_ratio, state)
        flight[FLIGHT_ACTIVE] = 0.0
        finished += 1
    return finished


@kernel
def elastic_lab(mu, energy, a, state):
    """Direction cosine and energy after isotropic CM scattering off a target of mass a (units of m)."""
    c = 2.0 * uniform(state) - 1.0
    factor = math.sqrt(a * a + 2.0 * a * c + 1.0)
    cos_lab = (1.0 + a * c) / factor if factor > 0.0 else 1.0  # a = 1, c = -1: stopped dead (energy 0)
    new_energy = energy * (a * a + 2.0 * a * c + 1.0) / (a + 1.0) ** 2
    phi = 2.0 * math.pi * uniform(state)
    sin_lab = math.sqrt(max(0.0, 1.0 - cos_lab * cos_lab))
    new_mu = mu * cos_lab + math.sqrt(max(0.0, 1.0 - mu * mu)) * sin_lab * math.cos(phi)
    return min(1.0, max(-1.0, new_mu)), new_energy
