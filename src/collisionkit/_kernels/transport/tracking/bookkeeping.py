"""What a tracked particle leaves behind: samples, induced charge, path points, secondaries, end records.

The helpers of :func:`.track.track_particles`, inlined into it: the
call's stack of particles (each with its own random stream), the moments
sampled at fixed times, the induced current (Shockley 1938, Ramo 1939:
i = q E_w . v), the ionization and excitation profiles and the records
of the particles that end.
"""

from __future__ import annotations

import math

from ...._jit import inline_kernel
from ..collisions import ionized, two_body
from ..layout import ELASTIC, EXCITATION
from ..moments import add_particle
from ..rng import next_u64, seed_state
from .codes import TALLY_INDUCED, TALLY_WEIGHTING
from .fields import weighting_field, weighting_potential
from .geometry import surface_normal
from .rates import profile_bin
from .stepping import state_on_step

IONIZATIONS, EXCITATIONS = 0, 1  # the rows of the profiles


@inline_kernel
def record_point(points, control, number, t, x, y, z):
    """Append (particle number, t, x, y, z) to the path points while there is room (``control[4]`` rows written)."""
    if control[4] < points.shape[0]:
        row = points[control[4]]
        row[0], row[1], row[2], row[3], row[4] = number, t, x, y, z
        control[4] += 1


@inline_kernel
def first_sample(sample_times, t):
    """The index of the first sample time at or after ``t``."""
    next_sample = 0
    while next_sample < sample_times.shape[0] and sample_times[next_sample] < t:
        next_sample += 1
    return next_sample


@inline_kernel
def add_samples(next_sample, t, s_event, exact, x, y, z, vx, vy, vz, flight, y0, y1, k, h, sample_times, moments,
                g_row, mass):
    """Add the particle's moments (:func:`..moments.add_particle`) at every sample time in (t, t + s_event] to
    its group's row; returns the next sample's index."""
    while next_sample < sample_times.shape[0] and sample_times[next_sample] <= t + s_event:
        s_sample = sample_times[next_sample] - t
        sx, sy, sz, ux, uy, uz = state_on_step(s_sample, exact, x, y, z, vx, vy, vz, flight, y0, y1, k, h)
        add_particle(moments[g_row, next_sample], mass, sx, sy, sz, ux, uy, uz)
        next_sample += 1
    return next_sample


@inline_kernel
def induced_charge(s_event, exact, x, y, z, vx, vy, vz, ex_, ey_, ez_, fx, fy, fz, flight, y0, y1, k, h, charge,
                   w_kind, w_par):
    """The charge induced on the readout over the step's first ``s_event``, from (x, y, z), (vx, vy, vz) to
    (ex_, ey_, ez_), (fx, fy, fz).

    Simpson's rule for the integral of the current q E_w . v (Shockley
    1938, Ramo 1939): q s (i0 + 4 i1 + i2) / 6, i at the start, middle and end.
    """
    half = 0.5 * s_event
    mx, my, mz, nx, ny, nz = state_on_step(half, exact, x, y, z, vx, vy, vz, flight, y0, y1, k, h)
    wx, wy, wz = weighting_field(w_kind, w_par, x, y, z)
    i0 = wx * vx + wy * vy + wz * vz
    wx, wy, wz = weighting_field(w_kind, w_par, mx, my, mz)
    i1 = wx * nx + wy * ny + wz * nz
    wx, wy, wz = weighting_field(w_kind, w_par, ex_, ey_, ez_)
    i2 = wx * fx + wy * fy + wz * fz
    return charge * s_event * (i0 + 4.0 * i1 + i2) / 6.0


@inline_kernel
def spread_signal(signal, induced, t, s_event, signal_start, signal_step):
    """Spread the charge ``induced`` over [t, t + s_event] on the current's time bins, in proportion to the
    overlap of each bin (all of it in the bin of t for a step too short to span a bin in floating point)."""
    n_signal = signal.shape[0]
    first = (t - signal_start) / signal_step
    last = (t + s_event - signal_start) / signal_step
    if last - first <= 0.0:
        b = int(math.floor(first))
        if 0 <= b < n_signal:
            signal[b] += induced
    else:
        b = max(0, int(math.floor(first)))
        while b < n_signal and b <= last:
            overlap = min(last, b + 1.0) - max(first, float(b))
            if overlap > 0.0:
                signal[b] += induced * overlap / (last - first)
            b += 1


@inline_kernel
def reflected(surfaces, surface, x, y, z, vx, vy, vz):
    """The velocity reflected specularly about the surface's normal at (x, y, z): v - 2 (v . n) n."""
    nx, ny, nz = surface_normal(surfaces, surface, x, y, z)
    dot = vx * nx + vy * ny + vz * nz
    vx -= 2.0 * dot * nx
    vy -= 2.0 * dot * ny
    vz -= 2.0 * dot * nz
    return vx, vy, vz


@inline_kernel
def add_to_profile(profiles, which, profile_kind, profile_par, x, y, z):
    """Count an event at (x, y, z) in its bin of profile ``which`` (ionizations or excitations), if any."""
    n_profile = profiles.shape[1]
    if n_profile > 0:
        b = profile_bin(profile_kind, profile_par, n_profile, x, y, z)
        if b >= 0:
            profiles[which, b] += 1.0


@inline_kernel
def put_back(stack, control, x, y, z, vx, vy, vz, t, birth, rng, h_control, primary, number):
    """Put a suspended particle back on the call's ``stack`` (its arrays: position, velocity, time, birth, random
    state, step, primary, fresh, number), with its random stream, to be taken again next call."""
    stack_pos, stack_vel, stack_time, stack_birth, stack_state, stack_h, stack_primary, stack_fresh, stack_id = stack
    slot = control[0]
    stack_pos[slot, 0], stack_pos[slot, 1], stack_pos[slot, 2] = x, y, z
    stack_vel[slot, 0], stack_vel[slot, 1], stack_vel[slot, 2] = vx, vy, vz
    stack_time[slot] = t
    stack_birth[slot] = birth
    for c in range(4):
        stack_state[slot, c] = rng[c]
    stack_h[slot] = h_control
    stack_primary[slot] = primary
    stack_fresh[slot] = False
    stack_id[slot] = number
    control[0] = slot + 1


@inline_kernel
def scatter(chosen, process, species, vx, vy, vz, gas_vx, gas_vy, gas_vz, gx, gy, gz, g_speed, energy, mass, gas,
            threshold, angular, screening, rng, profiles, profile_kind, profile_par, x, y, z):
    """An elastic or excitation collision at (x, y, z) (:func:`..collisions.two_body`, losing the threshold of an
    excitation, counted in the excitation profile); returns the velocity after it."""
    loss = 0.0 if process == ELASTIC else threshold[chosen]
    vx, vy, vz = two_body(vx, vy, vz, gas_vx, gas_vy, gas_vz, gx, gy, gz, g_speed, energy, mass, gas[species, 0], loss,
                          angular[chosen], screening[chosen], rng)
    if process == EXCITATION:
        add_to_profile(profiles, EXCITATIONS, profile_kind, profile_par, x, y, z)
    return vx, vy, vz


@inline_kernel
def ionize(chosen, x, y, z, t, h_control, primary, gas_vx, gas_vy, gas_vz, gx, gy, gz, g_speed, energy, mass,
           threshold, sharing, angular, screening, rng, stack, control, record_births, births, profiles, profile_kind,
           profile_par):
    """An ionization at (x, y, z): the two electrons' velocities (:func:`..collisions.ionized`); the new one is
    pushed on the stack with a stream seeded from the particle's, numbered ``control[5]``, its birth recorded and
    counted in the ionization profile (``stack``: see :func:`put_back`). Returns the particle's velocity after it."""
    stack_pos, stack_vel, stack_time, stack_birth, stack_state, stack_h, stack_primary, stack_fresh, stack_id = stack
    v1x, v1y, v1z, v2x, v2y, v2z = ionized(gas_vx, gas_vy, gas_vz, gx, gy, gz, g_speed, energy, mass,
                                           threshold[chosen], sharing, angular[chosen], screening[chosen], rng)
    slot = control[0]
    stack_pos[slot, 0], stack_pos[slot, 1], stack_pos[slot, 2] = x, y, z
    stack_vel[slot, 0], stack_vel[slot, 1], stack_vel[slot, 2] = v2x, v2y, v2z
    stack_time[slot] = t
    stack_birth[slot] = t
    seed_state(next_u64(rng), stack_state[slot])
    stack_h[slot] = h_control
    stack_primary[slot] = primary
    stack_fresh[slot] = True
    stack_id[slot] = control[5]
    control[5] += 1
    control[0] = slot + 1
    if record_births:
        row = births[control[2]]
        row[0], row[1], row[2], row[3], row[4] = primary, t, x, y, z
        control[2] += 1
    add_to_profile(profiles, IONIZATIONS, profile_kind, profile_par, x, y, z)
    return v1x, v1y, v1z


@inline_kernel
def weighting_charge(tallies, primary, n_proc, charge, w_kind, w_par, x, y, z, phi_start, current_recorded):
    """Tally the charge induced over a path from the weighting potential at its ends, -q (phi_w(end) -
    phi_w(start)) (Shockley-Ramo, exact in a static field); also as the induced charge without a recorded current."""
    moved = -charge * (weighting_potential(w_kind, w_par, x, y, z) - phi_start)
    tallies[primary, n_proc + TALLY_WEIGHTING] += moved
    if not current_recorded:  # no current recorded: the induced charge is Shockley-Ramo's
        tallies[primary, n_proc + TALLY_INDUCED] += moved


@inline_kernel
def end_record(records, control, primary, status, surface, t, x, y, z, vx, vy, vz, birth):
    """Write the end record of a particle: (primary, status, surface, t, x, y, z, vx, vy, vz, birth)."""
    row = records[control[1]]
    row[0], row[1], row[2], row[3] = primary, status, surface, t
    row[4], row[5], row[6], row[7], row[8], row[9] = x, y, z, vx, vy, vz
    row[10] = birth
    control[1] += 1
