"""Collision rates along a tracked trajectory and the choice of a real collision's process.

Tables are those of :func:`collisionkit.transport._tables.build_tables`
(the swarm's), plus ``species_sigma`` (nodes x species: each species' summed
cross section, fractions included) and, for a warm gas, ``thermal`` (speed
bins x species: each species' collision frequency per unit density averaged
over the gas Maxwellian, on a uniform speed grid of step ``thermal_step``).
"""

from __future__ import annotations

import math

from ...._jit import inline_kernel
from ..cross_sections import node_index as _node_index
from ..cross_sections import rate_bound as _rate_bound
from ..rng import normal_pair, uniform

# the swarm's node lookup and rate bound, inlined here: they run at every stage or every step, and a call that is
# not inlined costs reference counting on its arrays (measured: 2/3 of the time per collision of the path-length
# method)
node_index = inline_kernel(_node_index.py_func)
rate_bound = inline_kernel(_rate_bound.py_func)


@inline_kernel
def trial_rates(speed, density, gas, bound, inverse_step, sigma_max, const_max, nu_s):
    """Trial frequency per species (in ``nu_s``) and their sum for projectile speeds <= ``speed``: the swarm's
    :func:`collisionkit._kernels.transport.cross_sections.trial_frequencies`, with its rate bound inlined."""
    total = 0.0
    for s in range(gas.shape[0]):
        nu = density * rate_bound(s, speed + gas[s, 2], bound, inverse_step, sigma_max, const_max)
        nu_s[s] = nu
        total += nu
    return total


@inline_kernel
def species_rates(speed, mass, density, nodes, accelerator, inverse_cell, species_sigma, species_const, thermal,
                  thermal_step, nu_s):
    """Each species' collision frequency (1/s) at the projectile's lab speed (in ``nu_s``), and their sum.

    Cold gas (``thermal`` has one row): N (sigma_s(eps) v + k_s) with
    eps = m v^2 / 2, linear in the node interval (exact for the tables).
    Warm gas: the Maxwellian average, linear between speed bins; beyond
    the table the cold value.
    """
    n_species = nu_s.shape[0]
    total = 0.0
    if thermal.shape[0] > 1:
        x = speed / thermal_step
        if x < thermal.shape[0] - 1:
            i = int(x)
            w = x - i
            for s in range(n_species):
                nu = density * (thermal[i, s] + w * (thermal[i + 1, s] - thermal[i, s]))
                nu_s[s] = nu
                total += nu
            return total
    energy = 0.5 * mass * speed * speed
    node = node_index(energy, nodes, accelerator, inverse_cell)
    last = nodes.shape[0] - 1
    if node < 0:
        node, w = 0, 0.0
    elif node >= last:
        node, w = last - 1, 1.0
    else:
        w = (energy - nodes[node]) / (nodes[node + 1] - nodes[node])
    for s in range(n_species):
        sigma = species_sigma[node, s] + w * (species_sigma[node + 1, s] - species_sigma[node, s])
        nu = density * (sigma * speed + species_const[s])
        nu_s[s] = nu
        total += nu
    return total


@inline_kernel
def chosen_process(r, s, g_speed, energy, density, species_of, threshold, const_rate, nodes, sigma, accelerator,
                   inverse_cell):
    """The process j of species ``s`` whose cumulative rate N (sigma_j(eps) g + k_j) first exceeds ``r``, or -1.

    ``energy`` = m g^2 / 2 (J) of the relative speed ``g``.
    """
    node = node_index(energy, nodes, accelerator, inverse_cell)
    last = nodes.shape[0] - 1
    if node < 0:
        node, w = 0, 0.0
    elif node >= last:
        node, w = last - 1, 1.0
    else:
        w = (energy - nodes[node]) / (nodes[node + 1] - nodes[node])
    cumulative = 0.0
    for j in range(species_of.shape[0]):
        if species_of[j] != s:
            continue
        rate = const_rate[j]
        if energy >= threshold[j]:
            rate += (sigma[node, j] + w * (sigma[node + 1, j] - sigma[node, j])) * g_speed
        cumulative += density * rate
        if r < cumulative:
            return j
    return -1


@inline_kernel
def target_velocity(gas, species, rng):
    """A target's velocity from the Maxwellian of ``species`` (``gas[s, 1]``: the thermal speed per component;
    at rest in a cold gas), a tuple."""
    if gas[species, 1] <= 0.0:
        return 0.0, 0.0, 0.0
    gas_vx, gas_vy = normal_pair(rng)
    gas_vz, _ = normal_pair(rng)
    return gas_vx * gas[species, 1], gas_vy * gas[species, 1], gas_vz * gas[species, 1]


@inline_kernel
def trial_collision(vx, vy, vz, nu_trial, trial_s, rng, mass, density, gas, species_of, threshold, const_rate, nodes,
                    sigma, accelerator, inverse_cell):
    """A trial collision of a particle of velocity (vx, vy, vz) at the trial frequency ``nu_trial`` (the sum of
    ``trial_s``): (species, target velocity (3), relative velocity (3), relative speed g, m g^2 / 2, process).

    The species is drawn by its share of the trial frequency, a target from
    its Maxwellian (``gas[s, 1]``: the thermal speed per component), and the
    trial is the process whose cumulative rate first exceeds the rest of the
    uniform draw, or null (process -1) (Skullerud 1968).
    """
    r = uniform(rng) * nu_trial
    species = chosen_species(r, trial_s)
    for s in range(species):
        r -= trial_s[s]
    gas_vx, gas_vy, gas_vz = target_velocity(gas, species, rng)
    gx, gy, gz = vx - gas_vx, vy - gas_vy, vz - gas_vz
    g_speed = math.sqrt(gx * gx + gy * gy + gz * gz)
    energy = 0.5 * mass * g_speed * g_speed
    chosen = chosen_process(r, species, g_speed, energy, density, species_of, threshold, const_rate, nodes, sigma,
                            accelerator, inverse_cell)
    return species, gas_vx, gas_vy, gas_vz, gx, gy, gz, g_speed, energy, chosen


@inline_kernel
def chosen_species(r, nu_s):
    """The species whose share of the total ``sum(nu_s)`` holds ``r`` (in [0, total))."""
    s = 0
    while s < nu_s.shape[0] - 1 and r >= nu_s[s]:
        r -= nu_s[s]
        s += 1
    return s


@inline_kernel
def profile_bin(kind, p, bins, x, y, z):
    """The bin of (x, y, z) in a profile along z (kind 0) or the distance from an axis (kind 1); -1 outside."""
    if kind == 0:
        c = z
    else:
        c = math.sqrt((x - p[0]) ** 2 + (y - p[1]) ** 2)
    f = (c - p[2]) / (p[3] - p[2])
    if f < 0.0 or f >= 1.0:
        return -1
    return min(bins - 1, int(f * bins))
