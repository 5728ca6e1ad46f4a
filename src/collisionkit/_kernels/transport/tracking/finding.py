"""Where a tracked particle collides along a step, and with what: the path-length and the null-collision methods.

The helpers of :func:`.track.track_particles`, inlined into it (see the
module docstring of :mod:`.track` for the two methods).
"""

from __future__ import annotations

import math

import numpy as np

from ...._jit import inline_kernel
from ..flight import flown_velocity
from ..rng import uniform
from .fields import electric_bound
from .integrator import dense_state, depth_crossing, hermite_cubic
from .rates import (
    chosen_process, chosen_species, rate_bound, species_rates, target_velocity, trial_collision, trial_rates,
)

# null collisions: trials come in windows of constant trial frequency, each at most WINDOW_COLLISIONS / (the previous
# window's frequency) long and the time in which a|t| reaches WINDOW_GROWTH times the speed (a tighter bound than the
# step's, fewer null trials)
WINDOW_COLLISIONS = 1.3
WINDOW_GROWTH = 0.5
NEWTON_ITERATIONS = 8  # path length: refinements of the collision time on the integrated optical depth
GAUSS_NODES = np.array([-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526])
GAUSS_WEIGHTS = np.array([0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538])


@inline_kernel
def depth_and_rate(s_root, exact, vx, vy, vz, flight, y0, y1, k, h, rates):
    """The optical depth over the step's first ``s_root`` and the collision frequency there: ``(depth, rate)``.

    depth = (s/2) sum_i w_i nu(|v(s (1 + x_i) / 2)|), 4-point Gauss-Legendre
    (nodes x_i, weights w_i; Abramowitz & Stegun 25.4.30) along the exact or
    dense velocity; ``rates``: the arguments of :func:`.rates.species_rates` after the speed.
    """
    mass, density, nodes, accelerator, inverse_cell, species_sigma, species_const, thermal, thermal_step, nu_s = rates
    depth = 0.0
    rate = 0.0
    for node in range(5):
        s_node = 0.5 * s_root * (1.0 + GAUSS_NODES[node]) if node < 4 else s_root
        if exact:
            ux, uy, uz = flown_velocity(vx, vy, vz, s_node, flight)
        else:
            theta = s_node / h
            _, _, _, ux, uy, uz = dense_state(y0, y1, k, h, theta)
        rate = species_rates(math.sqrt(ux * ux + uy * uy + uz * uz), mass, density, nodes, accelerator,
                             inverse_cell, species_sigma, species_const, thermal, thermal_step, nu_s)
        if node < 4:
            depth += GAUSS_WEIGHTS[node] * rate
    depth *= 0.5 * s_root
    return depth, rate


@inline_kernel
def depth_collision(event, s_event, tau_left, exact, vx, vy, vz, flight, y0, y1, k, h, rates):
    """The path-length method over the step's first ``s_event``: ``(event, s_event, tau_left)``.

    If the optical depth integrated over it (the seventh component, on the
    cubic Hermite interpolant) reaches the drawn ``tau_left``, a collision
    (event 1) at its root, refined by Newton's method s -= (depth(s) -
    tau) / nu(s) on the Gauss-Legendre depth (:func:`depth_and_rate`): the
    cubic alone ignores how the rate varies inside the step, and biased the
    collision times. Otherwise the depth is used up (``tau_left`` less it).
    """
    if s_event == h:
        reached = y1[6]
    else:
        reached = hermite_cubic(0.0, k[0, 6], y1[6], k[6, 6], h, s_event / h)
    if reached < tau_left:
        return event, s_event, tau_left - reached
    s_root = depth_crossing(k[0, 6], y1[6], k[6, 6], h, tau_left, s_event, reached)
    for _ in range(NEWTON_ITERATIONS):
        depth, rate = depth_and_rate(s_root, exact, vx, vy, vz, flight, y0, y1, k, h, rates)
        s_next = s_root - (depth - tau_left) / rate if rate > 0.0 else s_root
        s_next = min(max(s_next, 0.0), s_event)
        if abs(s_next - s_root) <= 1e-12 * h:
            s_root = s_next
            break
        s_root = s_next
    return 1, s_root, tau_left


@inline_kernel
def trial_window(start, s_event, speed, nu_window, exact, accel, wx, wy, wz, vx, vy, vz, flight, field_bound,
                 speed_floor, density, trial_tables, trial_s):
    """The window of trials from ``start`` (position (wx, wy, wz), speed ``speed``): ``(end, nu_window)``.

    It lasts at most WINDOW_COLLISIONS / (the previous window's frequency)
    and WINDOW_GROWTH max(|v|, floor) / a, with a the step's bound of |qE/m|
    or a tighter one over the window's reach; its trial frequency is the
    tables' bound at the largest speed reachable in it: in a uniform E
    without B the larger end of |v + a t| (convex in t), else |v| + a (end -
    start) (the magnetic force does no work; Skullerud 1968). ``field_bound``:
    (q/m, and E's kind, parameters, map header and blocks);
    ``trial_tables``: see :func:`null_collisions`.
    """
    qm, e_kind, e_par, e_meta, e_blocks = field_bound
    gas, bound, inverse_step, sigma_max, const_max = (trial_tables[0], trial_tables[8], trial_tables[9],
                                                      trial_tables[10], trial_tables[11])
    window_reference = max(speed, speed_floor)
    end = s_event
    if nu_window > 0.0:
        end = min(end, start + WINDOW_COLLISIONS / nu_window)
    window_accel = accel  # the step's bound, or a tighter one over the window's own reach
    if not exact:
        window_accel = min(accel, abs(qm) * electric_bound(
            e_kind, e_par, e_meta, e_blocks, wx, wy, wz, (1.0 + WINDOW_GROWTH) * window_reference * (end - start)))
    if window_accel > 0.0:
        end = min(end, start + WINDOW_GROWTH * window_reference / window_accel)
    if end <= start:  # (a window too short to advance the time in floating point)
        end, window_accel = s_event, accel
    if exact and flight[12] == 0.0:  # |v + a t| is convex in t: its largest value is at an end
        top_speed = max(speed, math.sqrt((vx + flight[0] * end) ** 2 + (vy + flight[1] * end) ** 2
                                         + (vz + flight[2] * end) ** 2))
    else:  # the magnetic force does no work: d|v|/dt <= |q E / m|
        top_speed = speed + window_accel * (end - start)
    return end, trial_rates(top_speed, density, gas, bound, inverse_step, sigma_max, const_max, trial_s)


@inline_kernel
def null_collisions(event, s_event, tau_left, nu_window, exact, accel, x, y, z, vx, vy, vz, flight, y0, y1, k, h,
                    field_bound, speed_floor, tallies, primary, null_column, rng, mass, density, trial_tables,
                    trial_s):
    """The null-collision method over the step's first ``s_event``, window by window (:func:`trial_window`).

    Trials come where the drawn optical depth runs out at the window's
    constant frequency; each is real with probability true rate / trial
    rate (:func:`.rates.trial_collision`). Returns ``(event, s_event,
    tau_left, nu_window, species, gas_vx, gas_vy, gas_vz, gx, gy, gz,
    g_speed, energy, chosen)``: event 1 at the first real trial (``chosen``
    its process, the rest its target and relative velocity), else the
    depth left after the windows (``chosen`` -1). ``trial_tables``: (gas,
    species_of, threshold, const_rate, nodes, sigma, accelerator,
    inverse_cell, bound, inverse_step, sigma_max, const_max).
    """
    gas, species_of, threshold, const_rate, nodes, sigma, accelerator, inverse_cell = trial_tables[:8]
    chosen = -1
    species = 0
    gas_vx = gas_vy = gas_vz = 0.0
    gx = gy = gz = g_speed = energy = 0.0
    start = 0.0
    while start < s_event:
        wx, wy, wz, ux, uy, uz = x, y, z, vx, vy, vz
        if start > 0.0 and exact:
            ux, uy, uz = flown_velocity(vx, vy, vz, start, flight)
        elif start > 0.0:
            wx, wy, wz, ux, uy, uz = dense_state(y0, y1, k, h, start / h)
        speed = math.sqrt(ux * ux + uy * uy + uz * uz)
        end, nu_window = trial_window(start, s_event, speed, nu_window, exact, accel, wx, wy, wz, vx, vy, vz, flight,
                                      field_bound, speed_floor, density, trial_tables, trial_s)
        position = start
        while nu_window > 0.0 and position + tau_left / nu_window < end:
            position += tau_left / nu_window
            if exact:
                ux, uy, uz = flown_velocity(vx, vy, vz, position, flight)
            else:
                _, _, _, ux, uy, uz = dense_state(y0, y1, k, h, position / h)
            species, gas_vx, gas_vy, gas_vz, gx, gy, gz, g_speed, energy, chosen = trial_collision(
                ux, uy, uz, nu_window, trial_s, rng, mass, density, gas, species_of, threshold, const_rate, nodes,
                sigma, accelerator, inverse_cell)
            if chosen >= 0:
                break
            tallies[primary, null_column] += 1.0
            tau_left = -math.log(uniform(rng))
        if chosen >= 0:
            s_event = position
            event = 1
            break
        tau_left -= nu_window * (end - position)
        start = end
    return (event, s_event, tau_left, nu_window, species, gas_vx, gas_vy, gas_vz, gx, gy, gz, g_speed, energy,
            chosen)


@inline_kernel
def path_collision(vx, vy, vz, rng, trial_tables, rates):
    """The target and process of a path-length collision: ``(species, gas_vx, gas_vy, gas_vz, gx, gy, gz, g_speed,
    energy, chosen)``.

    The species by its share of nu(|v|); the target's velocity and the
    process by rejection against the species' bound (its true rate at the
    thermal relative speed g, N sum_j sigma_j(g) g, below N times the rate
    bound at |v| + the thermal speed scale). ``trial_tables``: see
    :func:`null_collisions`; ``rates``: see :func:`depth_and_rate`.
    """
    gas, species_of, threshold, const_rate = trial_tables[:4]
    sigma, bound, inverse_step, sigma_max, const_max = (trial_tables[5], trial_tables[8], trial_tables[9],
                                                        trial_tables[10], trial_tables[11])
    mass, density, nodes, accelerator, inverse_cell, species_sigma, species_const, thermal, thermal_step, nu_s = rates
    speed = math.sqrt(vx * vx + vy * vy + vz * vz)
    total = species_rates(speed, mass, density, nodes, accelerator, inverse_cell, species_sigma, species_const,
                          thermal, thermal_step, nu_s)
    species = chosen_species(uniform(rng) * total, nu_s)
    while True:  # the target's velocity and the process: rejection against the species' bound
        gas_vx, gas_vy, gas_vz = target_velocity(gas, species, rng)
        if gas[species, 1] > 0.0:
            ceiling = density * rate_bound(species, speed + gas[species, 2], bound, inverse_step, sigma_max,
                                           const_max)
        else:
            ceiling = nu_s[species]
        gx, gy, gz = vx - gas_vx, vy - gas_vy, vz - gas_vz
        g_speed = math.sqrt(gx * gx + gy * gy + gz * gz)
        energy = 0.5 * mass * g_speed * g_speed
        chosen = chosen_process(uniform(rng) * ceiling, species, g_speed, energy, density, species_of, threshold,
                                const_rate, nodes, sigma, accelerator, inverse_cell)
        if chosen >= 0:
            break
    return species, gas_vx, gas_vy, gas_vz, gx, gy, gz, g_speed, energy, chosen
