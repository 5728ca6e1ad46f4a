"""The swarm step: every particle (and its ionization children) from one time to the next.

The null-collision method with an exact, speed-dependent trial frequency,
piecewise constant in time (see :mod:`collisionkit._kernels.transport`).
"""

from __future__ import annotations

import math
import types

import numpy as np

from ..._jit import borrowing_inline_kernel, borrowing_kernel, inline_kernel
from .collisions import ionized, two_body
from .cross_sections import node_index as _node_index
from .cross_sections import trial_frequencies as _trial_frequencies
from .flight import flight_envelope as _flight_envelope
from .flight import flown_position as _flown_position
from .flight import flown_velocity as _flown_velocity
from .flight import gyrated_position, gyrated_velocity
from .flight import window_growth_speed as _window_growth_speed
from .flight import window_top_speed as _window_top_speed
from .ac_window import flight_envelope_ac, oscillating_window, stepped_window
from .oscillating import (
    RECORD_SIZE, STATIC_SIZE, displacement_with_phases, flight_with_phases, oscillating_flown_velocity, record_values,
    sincos, sincos_spread,
)
from .particular import particular_flight, particular_position, particular_terms
from .waveform import WAVE_START
from .waveform_magnetic import shaped_flight as _shaped_flight
from .waveform_magnetic import shaped_velocity, shaped_window
from .waveform_periodic import periodic_chained_constants as _periodic_chained_constants
from .waveform_periodic import periodic_displacement as _periodic_displacement
from .waveform_periodic import periodic_flight_constants as _periodic_flight_constants
from .waveform_periodic import periodic_trials
from .waveform_periodic import periodic_velocity as _periodic_velocity
from .waveform_window import shaped_flight_constants as _shaped_flight_constants
from .waveform_window import stepped_shaped_window as _stepped_shaped_window
from .layout import (
    ATTACHMENT, BOUND_COLUMN_OFFSET, DISPLACEMENT_COLUMN_OFFSET, ELASTIC, EXCITATION, NULL_COLUMN_OFFSET, SUPERELASTIC,
    TIME_COLUMN_OFFSET,
)
from .rng import next_u64, normal_pair, seed_state, uniform

# the kinds of field, each with its own machine code of the particle loop (:func:`field_variant`)
STATIC, MAGNETIC, OSCILLATING, OSCILLATING_MAGNETIC, NEAR_RESONANCE, WAVEFORM = range(6)
LOOP_VARIANT = STATIC  # the kind of field of the loop: each copy of it in PARTICLE_LOOPS sees its own
# ... and what it implies, each a global of its own: numba prunes a branch on a global before it inlines the
# flights, so a loop compiles only its own kind's code (first compilation, measured: static 39 -> 14 s, static
# B 34 -> 10 s, waveform 46 -> 31 s)
LOOP_OSCILLATING = LOOP_WAVEFORM = LOOP_PARTICULAR = False
# a flight window lasts WINDOW_COLLISIONS / (trial frequency of the previous window): longer windows mean
# fewer window updates but a looser bound (more null trials); 1.3 is the fastest on Reid's ramp at 1-12 Td
WINDOW_COLLISIONS = 1.3
# ... and at most the time in which |a| t reaches WINDOW_GROWTH times the speed (or 16 speed bins): in a strong
# field, a long window would reach speeds where the bound is far above the rate along most of the window
WINDOW_GROWTH = 0.5
# windows and trials a particle (with its children) may take in one call by default: a step is planned for a
# few tens of collisions a particle, so a particle that needs a million runs away (cross sections zero or tiny
# over the energies it reaches) and would never end the step; the call gives up on it (about 0.1 s of work)
TRIAL_BUDGET = 1 << 20
# a species with this many processes or more tests a trial against its summed table before its processes: a null
# trial then costs one table lookup instead of one per process, a real one a lookup more (with 15 % null trials,
# as on Reid's ramp, that pays from about 7 processes; the threshold leaves the two- and three-process model gases
# on the plain scan, which measured 7 % faster on Reid's ramp)
EARLY_REJECTION = 5

# the table lookups, inlined into the borrowing particle loop: a call that is not inlined costs reference counting
# on its arrays (perf: trial_frequencies alone took 15-18 % of a static run)
node_index = inline_kernel(_node_index.py_func)
trial_frequencies = inline_kernel(_trial_frequencies.py_func)
# ... and the static flight and its window bounds, the flights fed the record's tuple (no array: no reference counts)
flown_velocity = inline_kernel(_flown_velocity.py_func)
flown_position = inline_kernel(_flown_position.py_func)
flight_envelope = inline_kernel(_flight_envelope.py_func)
window_top_speed = inline_kernel(_window_top_speed.py_func)
window_growth_speed = inline_kernel(_window_growth_speed.py_func)
# ... and the waveform's flight constants, window bound and trial flight (a call with stack arguments per flight,
# window and trial before; inlining the trial flight measured 0.91x the waveform's cost per collision)
shaped_flight_constants = borrowing_inline_kernel(_shaped_flight_constants.py_func)
stepped_shaped_window = borrowing_inline_kernel(_stepped_shaped_window.py_func)
shaped_flight = borrowing_inline_kernel(_shaped_flight.py_func)
# ... and a waveform's trials with B from the periodic solution (the per-trial state stays in registers)
periodic_flight_constants = inline_kernel(_periodic_flight_constants.py_func)
periodic_chained_constants = inline_kernel(_periodic_chained_constants.py_func)
periodic_velocity = inline_kernel(_periodic_velocity.py_func)
periodic_displacement = inline_kernel(_periodic_displacement.py_func)


def _advance_particles(lo, hi, pos, vel, states, alive, t_start, t_end, field, mass, density, gas, kind, species_of,
                       threshold, const_rate, angular, screening, sharing, nodes, sigma, accelerator, accelerator_step,
                       bound, bound_step, sigma_max, const_max, sigma_total, tallies, child_pos, child_vel,
                       child_state, child_alive, child_count, check, window, growth, budget, child_time, rng, nu_s,
                       channels):
    """:func:`advance_swarm`'s particle loop, compiled without reference counting (:func:`collisionkit._jit.
    borrowing_kernel`): it allocates nothing, its scratch arrays (``child_time``: slots; ``rng``: 4 uint64;
    ``nu_s``, ``channels``: one per species) come from the caller. The global ``LOOP_VARIANT``
    (:func:`field_variant`) says which flights and bounds the field takes: each kind of field has its own copy of
    this function with its own value of it (:data:`PARTICLE_LOOPS`), a constant to numba, which leaves the other
    kinds' code out, so that each kind's loop keeps its variables in registers."""
    n_species = gas.shape[0]
    n_proc = kind.shape[0]
    null_column = n_proc + NULL_COLUMN_OFFSET
    time_column = n_proc + TIME_COLUMN_OFFSET
    bound_column = n_proc + BOUND_COLUMN_OFFSET
    moved_column = n_proc + DISPLACEMENT_COLUMN_OFFSET
    accel_mag = math.sqrt(field[0] ** 2 + field[1] ** 2 + field[2] ** 2)
    variant = LOOP_VARIANT
    ac = LOOP_OSCILLATING  # E0 cos(omega t) (:mod:`.oscillating`)
    omega = field[STATIC_SIZE] if ac else 0.0
    shaped = LOOP_WAVEFORM  # a periodic waveform given as samples (:mod:`.waveform`)
    if ac or shaped:
        accel_mag += field[STATIC_SIZE + 12]
    record = record_values(field)  # a tuple: the inlined flight functions then take no array (no reference counts)
    ax, ay, az = field[0], field[1], field[2]
    # an oscillating field without static acceleration: the windows chain the parallel velocity and the phase
    envelope = ac and ax == 0.0 and ay == 0.0 and az == 0.0
    # a waveform without static acceleration: the windows are bounded from constants of the flight (.waveform_window)
    tight = shaped and ax == 0.0 and ay == 0.0 and az == 0.0
    # ... and with B: the trials from the periodic solution, one rotation a trial (.waveform_periodic)
    periodic = tight and periodic_trials(field)
    inverse_period = 1.0 / field[WAVE_START] if shaped else 0.0
    inverse_w = 1.0 / field[12] if periodic else 0.0
    exact = variant == STATIC or variant == OSCILLATING or (variant == WAVEFORM and field[12] == 0.0)
    half_gyration = 0.5 * field[12]
    # off cyclotron resonance, an oscillating flight with B about the particular solution v_p (:mod:`.particular`)
    particular = LOOP_PARTICULAR
    _, k_s, k_c = particular_terms(field)
    bx, by, bz, ux, uy, uz = field[3], field[4], field[5], field[9], field[10], field[11]
    a_par_field = field[6] * bx + field[7] * by + field[8] * bz
    inverse_step = (1.0 / bound_step) * (1.0 + 1e-12)
    inverse_cell = (1.0 / accelerator_step) * (1.0 - 1e-12)
    inverse_accel = 1.0 / accel_mag if accel_mag > 0.0 else math.inf
    static_inverse_accel = inverse_accel  # (a product, not a division, on the chain of a window's bound)
    if ac:  # |cos| averages 2/pi over a period: the growth limit in the mean acceleration (5 % faster, measured)
        inverse_accel *= 0.5 * math.pi
    fallback = 0.01 * bound.shape[1] * bound_step / accel_mag if accel_mag > 0.0 else math.inf
    speed_floor = 16.0 * bound_step
    last_node = nodes.shape[0] - 1
    slots = child_pos.shape[1]
    channels[:] = 0  # processes per species
    for j in range(n_proc):
        channels[species_of[j]] += 1
    for i in range(lo, hi):
        if not alive[i]:
            continue
        n_children = 0
        iterations = 0  # windows and trials of the particle and its children
        member = -1  # -1: the particle itself, then its children
        while True:
            if member < 0:
                x, y, z = pos[i, 0], pos[i, 1], pos[i, 2]
                vx, vy, vz = vel[i, 0], vel[i, 1], vel[i, 2]
                for k in range(4):
                    rng[k] = states[i, k]
                t = t_start
            else:
                x, y, z = child_pos[i, member, 0], child_pos[i, member, 1], child_pos[i, member, 2]
                vx, vy, vz = child_vel[i, member, 0], child_vel[i, member, 1], child_vel[i, member, 2]
                for k in range(4):
                    rng[k] = child_state[i, member, k]
                t = child_time[member]
            t_begin = t
            chained = False  # a waveform flight with B from the last flight's trial (.waveform_periodic)
            s_phase, s_piece, s_turn = 0.0, 0, 0.0j
            # the field's phase at t: computed here, then carried from flight to flight by the trials' rotations
            phase_sin, phase_cos = sincos(omega * t) if ac else (0.0, 1.0)
            x0, y0, z0 = x, y, z
            survives = True
            # a thermal target's velocity takes three normal numbers, drawn in pairs: the third of one pair is kept
            # for the next trial of the same particle (its own stream, so results do not depend on the threads)
            spare, has_spare = 0.0, False
            speed0 = math.sqrt(vx * vx + vy * vy + vz * vz)
            nu_window = trial_frequencies(speed0, density, gas, bound, inverse_step, sigma_max, const_max, nu_s)
            inverse_nu = 1.0 / nu_window if nu_window > 0.0 else math.inf
            while True:  # one flight, from the last real collision
                speed0 = math.sqrt(vx * vx + vy * vy + vz * vz)
                vb, radius, a_par = 0.0, 0.0, 0.0
                c0, s0 = phase_cos, phase_sin  # the phase of the field at the flight's start
                # u0 = v - v_p(theta0): the static part of the flight about the particular solution (:mod:`.particular`)
                px, py, pz = vx, vy, vz
                if particular:
                    px = vx - (s0 * k_s[0] + c0 * k_c[0])
                    py = vy - (s0 * k_s[1] + c0 * k_c[1])
                    pz = vz - (s0 * k_s[2] + c0 * k_c[2])
                wvx, wvy, wvz, wc, ws = vx, vy, vz, c0, s0  # the state at the next window's start
                w_par, radius_ac, w_speed, s_window, turning, turned = 0.0, 0.0, 0.0, speed0, 0.0j, 0.0j
                if ac and envelope:
                    w_par, radius_ac, w_speed, turning = flight_envelope_ac(vx, vy, vz, c0, s0, record)
                    turned = turning  # U at the next window's start
                step = step_sin = 0.0
                step_cos = 1.0
                su0 = sg0 = s_along = s_across = s_offset = sdx = sdy = sdz = sfx = sfy = sfz = 0.0
                sk0 = 0
                s_gap = s_zeta = 0.0j
                if shaped and periodic and chained:  # ... and the walk's state, from the trial ending the last flight
                    su0, sk0, sg0, s_along, s_across, s_offset, s_gap, s_turn = periodic_chained_constants(
                        vx, vy, vz, s_phase, s_piece, s_turn, inverse_w, field)
                elif shaped and periodic:  # ... from the start time: a sine and a search
                    su0, sk0, sg0, s_along, s_across, s_offset, s_gap, s_turn = periodic_flight_constants(
                        vx, vy, vz, t, field)
                elif shaped:  # the phase and its piece: the trials' flights start there
                    su0, sk0, sg0, s_along, s_across, s_offset = shaped_flight_constants(vx, vy, vz, t, field)
                s_piece, s_periods = sk0, 0.0
                hint_period, hint = 0.0, sk0  # where the next window's walk over the pieces starts
                s_gwin = sg0  # G1 at the next window's start
                sh = ch = gs = gc = 0.0  # the half-angle sines of the last trial (oscillating field)
                if not exact:
                    vb, radius, a_par = flight_envelope(vx, vy, vz, bx, by, bz, ux, uy, uz, a_par_field)
                horizon = t_end - t
                elapsed = 0.0  # flight time so far
                window_end = 0.0
                s_low = speed0 if exact else window_top_speed(vx, vy, vz, ax, ay, az, 0.0, exact, vb, radius, a_par)
                tau = -math.log(uniform(rng))
                landed = False  # reached t_end without a real collision
                while True:  # windows and trials of this flight
                    iterations += 1
                    if iterations > budget:
                        if ac:
                            fx, fy, fz, _, _ = oscillating_flown_velocity(vx, vy, vz, c0, s0, elapsed, record)
                        elif shaped:
                            fx, fy, fz = shaped_velocity(vx, vy, vz, t, elapsed, field)
                        elif exact:
                            fx, fy, fz = vx + ax * elapsed, vy + ay * elapsed, vz + az * elapsed
                        else:
                            fx, fy, fz = flown_velocity(vx, vy, vz, elapsed, record)
                        return i, math.sqrt(fx * fx + fy * fy + fz * fz)
                    if elapsed >= window_end:  # open the next window
                        if ac and envelope:  # the bound from the parallel velocity and phase at the window's start
                            # (the previous window's bound stands in for the speed at the start)
                            if window_end == 0.0:  # the flight's windows all of the first one's length: one sine
                                step = window * inverse_nu if nu_window > 0.0 else fallback
                                step = min(step, growth * max(s_window, speed_floor) * inverse_accel)
                                step_sin, step_cos = sincos(0.5 * omega * step)
                            h = step
                            s_window, w_par, wc, ws, turned = stepped_window(
                                w_par, wc, ws, omega * (t + window_end), step_sin, step_cos, h, window_end + h,
                                radius_ac, w_speed, turning, turned, speed0, accel_mag, record)
                            nu_window = trial_frequencies(s_window, density, gas, bound, inverse_step, sigma_max,
                                                          const_max, nu_s)
                            window_end += h
                        elif shaped:  # the bound from the flight's constants, or the velocity at the window's start
                            h = window * inverse_nu if nu_window > 0.0 else fallback
                            h = min(h, growth * max(s_window, speed_floor) * inverse_accel)
                            if tight:
                                s_window, s_gwin, hint_period, hint = stepped_shaped_window(
                                    su0, sg0, s_along, s_across, s_offset, window_end, h, field, s_gwin, hint_period,
                                    hint)
                            else:
                                s_window = shaped_window(vx, vy, vz, t, window_end, h, field, accel_mag)
                            nu_window = trial_frequencies(s_window, density, gas, bound, inverse_step, sigma_max,
                                                          const_max, nu_s)
                            window_end += h
                        elif ac:  # the bound from the exact state at the window's start; the state at its end
                            s_start = math.sqrt(wvx * wvx + wvy * wvy + wvz * wvz)
                            h = window * inverse_nu if nu_window > 0.0 else fallback
                            h = min(h, growth * max(s_start, speed_floor) * inverse_accel)
                            s_window, wvx, wvy, wvz, wc, ws = oscillating_window(
                                wvx, wvy, wvz, wc, ws, omega * (t + window_end), h, record, accel_mag)
                            nu_window = trial_frequencies(s_window, density, gas, bound, inverse_step, sigma_max,
                                                          const_max, nu_s)
                            window_end += h
                        elif accel_mag > 0.0:
                            h = window * inverse_nu if nu_window > 0.0 else fallback
                            h = min(h, growth * max(s_low, speed_floor) * static_inverse_accel)
                            s_high = window_top_speed(vx, vy, vz, ax, ay, az, window_end + h, exact, vb, radius,
                                                      a_par)
                            s_window = min(max(s_low, s_high),
                                           window_growth_speed(speed0, accel_mag, window_end + h, exact, radius))
                            nu_window = trial_frequencies(s_window, density, gas, bound, inverse_step, sigma_max,
                                                          const_max, nu_s)
                            s_low = s_high
                            window_end += h
                        else:
                            nu_window = trial_frequencies(speed0, density, gas, bound, inverse_step, sigma_max,
                                                          const_max, nu_s)
                            window_end = math.inf
                        inverse_nu = 1.0 / nu_window if nu_window > 0.0 else math.inf
                    stop = min(window_end, horizon)
                    room = nu_window * (stop - elapsed)
                    if tau >= room:
                        if stop >= horizon:
                            landed = True
                            break
                        tau -= room
                        elapsed = window_end
                        continue
                    elapsed = min(stop, elapsed + tau * inverse_nu)
                    # a trial: the velocity it would have, the target species by its share of the trial frequency
                    if particular:
                        tvx, tvy, tvz, phase_cos, phase_sin, sh, ch, gs, gc = particular_flight(
                            px, py, pz, c0, s0, elapsed, k_s, k_c, record)
                    elif ac:
                        tvx, tvy, tvz, phase_cos, phase_sin, sh, ch, gs, gc = flight_with_phases(
                            vx, vy, vz, c0, s0, elapsed, record)
                    elif shaped and periodic:  # the half-angle sines of the gyration give the rotation of the gap
                        gs, gc = sincos_spread(half_gyration * elapsed)
                        tvx, tvy, tvz, s_zeta, s_piece, s_periods, s_turn = periodic_velocity(
                            s_along, sg0, s_gap, su0, elapsed, gs, gc, s_piece, s_periods, s_turn, inverse_period,
                            inverse_w, field)
                    elif shaped:  # a real collision's displacement comes with its velocity
                        tvx, tvy, tvz, sdx, sdy, sdz = shaped_flight(vx, vy, vz, su0, sk0, elapsed, field)
                    elif exact:
                        tvx, tvy, tvz = vx + ax * elapsed, vy + ay * elapsed, vz + az * elapsed
                    else:  # the half-angle sines kept for the position at a real collision
                        gs, gc = sincos_spread(half_gyration * elapsed)
                        tvx, tvy, tvz = gyrated_velocity(vx, vy, vz, elapsed, gs, gc, record)
                    r = uniform(rng) * nu_window
                    s = 0
                    while s < n_species - 1 and r >= nu_s[s]:
                        r -= nu_s[s]
                        s += 1
                    gas_vx = gas_vy = gas_vz = 0.0
                    if gas[s, 1] > 0.0:
                        gas_vx, gas_vy = normal_pair(rng)
                        if has_spare:
                            gas_vz, has_spare = spare, False
                        else:
                            gas_vz, spare = normal_pair(rng)
                            has_spare = True
                        gas_vx *= gas[s, 1]
                        gas_vy *= gas[s, 1]
                        gas_vz *= gas[s, 1]
                    gx, gy, gz = tvx - gas_vx, tvy - gas_vy, tvz - gas_vz
                    g_squared = gx * gx + gy * gy + gz * gz
                    g_speed = math.sqrt(g_squared)
                    energy = 0.5 * mass * g_squared  # not from g_speed: the lookup need not wait for the root
                    # linear interpolation in node interval `node` (one division for all processes)
                    node = node_index(energy, nodes, accelerator, inverse_cell)
                    if node < 0:
                        node, w = 0, 0.0
                    elif node >= last_node:
                        node, w = last_node - 1, 1.0
                    else:
                        w = (energy - nodes[node]) / (nodes[node + 1] - nodes[node])
                    chosen = -1
                    if not check and channels[s] >= EARLY_REJECTION:  # above the species' total: null at once
                        total = const_max[s] + (sigma_total[node, s] + w * (sigma_total[node + 1, s]
                                                                             - sigma_total[node, s])) * g_speed
                        if r >= density * total:
                            tallies[i, null_column] += 1.0
                            tau = -math.log(uniform(rng))
                            continue
                    cumulative = 0.0
                    for j in range(n_proc):
                        if species_of[j] != s:
                            continue
                        rate = const_rate[j]
                        if energy >= threshold[j]:
                            rate += (sigma[node, j] + w * (sigma[node + 1, j] - sigma[node, j])) * g_speed
                        cumulative += density * rate
                        if chosen < 0 and r < cumulative:
                            chosen = j
                            if not check:
                                break
                    if check and cumulative > nu_s[s]:
                        tallies[i, bound_column] += 1.0
                    if chosen >= 0:
                        break
                    tallies[i, null_column] += 1.0
                    tau = -math.log(uniform(rng))
                if landed:
                    elapsed = horizon
                if particular:
                    if landed:  # the flight to t_end (a real collision's reuses its trial's sines)
                        tvx, tvy, tvz, phase_cos, phase_sin, sh, ch, gs, gc = particular_flight(
                            px, py, pz, c0, s0, elapsed, k_s, k_c, record)
                    x, y, z = particular_position(x, y, z, px, py, pz, c0, s0, elapsed, sh, ch, gs, gc, k_s, k_c,
                                                  record)
                    if landed:
                        vx, vy, vz = tvx, tvy, tvz
                        t = t_end
                        break
                elif exact:
                    half = 0.5 * elapsed * elapsed
                    x, y, z = x + vx * elapsed + ax * half, y + vy * elapsed + ay * half, z + vz * elapsed + az * half
                elif shaped and periodic and not landed:  # a real collision: its displacement below, from its trial
                    pass
                elif landed or shaped:
                    x, y, z = flown_position(x, y, z, vx, vy, vz, elapsed, record)
                else:  # a real collision: the sines of its trial's gyration (static or oscillating flight)
                    x, y, z = gyrated_position(x, y, z, vx, vy, vz, elapsed, gs, gc, record)
                if ac and not particular:
                    if landed:  # the flight to t_end (a real collision's reuses its trial's sines)
                        vx, vy, vz, phase_cos, phase_sin, sh, ch, gs, gc = flight_with_phases(
                            vx, vy, vz, c0, s0, elapsed, record)
                    dx, dy, dz = displacement_with_phases(c0, s0, elapsed, sh, ch, gs, gc, record)
                    x, y, z = x + dx, y + dy, z + dz
                if shaped:  # a real collision's from its trial
                    if landed:
                        sfx, sfy, sfz, sdx, sdy, sdz = shaped_flight(vx, vy, vz, su0, sk0, elapsed, field)
                    elif periodic:
                        sdx, sdy, sdz = periodic_displacement(vx, vy, vz, s_zeta, su0, sk0, elapsed, gs, gc, inverse_w,
                                                              field)
                        # the next flight starts at this trial's phase, piece and turn times rotation
                        s_phase = su0 + elapsed * inverse_period - s_periods
                        s_turn = complex(1.0 - 2.0 * gs * gs, -2.0 * gs * gc) * s_turn
                        chained = True
                    x, y, z = x + sdx, y + sdy, z + sdz
                if landed:
                    if shaped:
                        vx, vy, vz = sfx, sfy, sfz
                    elif exact and not ac:
                        vx, vy, vz = vx + ax * elapsed, vy + ay * elapsed, vz + az * elapsed
                    elif not ac:
                        vx, vy, vz = flown_velocity(vx, vy, vz, elapsed, record)
                    t = t_end
                    break
                # a real collision, where the particle now is
                vx, vy, vz = tvx, tvy, tvz
                t += elapsed
                tallies[i, chosen] += 1.0
                process = kind[chosen]
                if process == ELASTIC or process == EXCITATION or process == SUPERELASTIC:
                    # a superelastic collision's threshold is minus the energy it gives
                    loss = 0.0 if process == ELASTIC else threshold[chosen]
                    vx, vy, vz = two_body(vx, vy, vz, gas_vx, gas_vy, gas_vz, gx, gy, gz, g_speed, energy, mass,
                                          gas[s, 0], loss, angular[chosen], screening[chosen], rng)
                elif process == ATTACHMENT:
                    survives = False
                    break
                else:
                    v1x, v1y, v1z, v2x, v2y, v2z = ionized(gas_vx, gas_vy, gas_vz, gx, gy, gz, g_speed, energy,
                                                           mass, threshold[chosen], sharing, angular[chosen],
                                                           screening[chosen], rng)
                    vx, vy, vz = v1x, v1y, v1z
                    if n_children >= slots:
                        n_children += 1  # overflow: the caller repeats the step with more slots
                        break
                    child_pos[i, n_children, 0] = x
                    child_pos[i, n_children, 1] = y
                    child_pos[i, n_children, 2] = z
                    child_vel[i, n_children, 0] = v2x
                    child_vel[i, n_children, 1] = v2y
                    child_vel[i, n_children, 2] = v2z
                    child_time[n_children] = t
                    seed_state(next_u64(rng), child_state[i, n_children])
                    n_children += 1
            tallies[i, time_column] += t - t_begin
            # the time integral of the velocity: the exact flights end to end (to the attachment point if any)
            tallies[i, moved_column] += x - x0
            tallies[i, moved_column + 1] += y - y0
            tallies[i, moved_column + 2] += z - z0
            if member < 0:
                pos[i, 0], pos[i, 1], pos[i, 2] = x, y, z
                vel[i, 0], vel[i, 1], vel[i, 2] = vx, vy, vz
                for k in range(4):
                    states[i, k] = rng[k]
                alive[i] = survives
            else:
                child_pos[i, member, 0], child_pos[i, member, 1], child_pos[i, member, 2] = x, y, z
                child_vel[i, member, 0], child_vel[i, member, 1], child_vel[i, member, 2] = vx, vy, vz
                for k in range(4):
                    child_state[i, member, k] = rng[k]
                child_alive[i, member] = survives
            member += 1
            if member >= n_children or n_children > slots:
                break
        child_count[i] = n_children
    return -1, 0.0


def advance_swarm(lo, hi, pos, vel, states, alive, t_start, t_end, field, mass, density, gas, kind, species_of,
                  threshold, const_rate, angular, screening, sharing, nodes, sigma, accelerator, accelerator_step,
                  bound, bound_step, sigma_max, const_max, sigma_total, tallies, child_pos, child_vel, child_state,
                  child_alive, child_count, check=False, window=WINDOW_COLLISIONS, growth=WINDOW_GROWTH,
                  budget=TRIAL_BUDGET):
    """Advance particles lo..hi-1 (and their descendants) from t_start to t_end.

    Returns ``(-1, 0.0)``, or ``(i, speed)`` if particle i (with its
    children) used up ``budget`` windows and trials before ``t_end``: the
    call gives up at once (the step is incomplete), with the speed the
    particle had reached. A particle whose collision rate stays far below
    the step's plan (zero or tiny cross sections) runs away in a field and
    would otherwise never end its step.

    ``tallies[i]`` receives the collisions per process, the null collisions,
    the particle time of particle i and its children, their displacement
    (the time integral of their velocity over the step) and (with ``check``)
    the trials at which the true collision rate exceeded the trial bound
    (never, if the method is exact; checked runs evaluate every process at
    every trial instead of first testing the trial, for a species of
    ``EARLY_REJECTION`` processes or more, against the species' total
    ``const_max[s] + sigma_total[:, s] g``, which can only exceed the sum of
    the processes' rates); children are stored in ``child_*[i]``
    (``child_count[i]`` of them, more than the slots means overflow and the
    step must be repeated with more slots).

    A flight runs from one real collision to the next. Trial collisions
    along it form a Poisson process whose rate is piecewise constant over
    windows of the flight (each ``window`` / its previous rate long): in a
    window, the table bound at the largest speed the particle can reach in
    it (:mod:`.flight`). An exponential optical depth is drawn
    per trial and used up window after window (the integrated hazard of a
    piecewise-constant rate: exact). A null trial leaves the flight as it
    is: particles move only at real collisions and at ``t_end``.

    The particle loop is written out in one function, compiled without
    reference counting (:func:`_advance_particles`, a borrowing kernel fed
    scratch arrays allocated here), its table lookups inlined: a numba call
    that is not inlined, or any call in a reference-counting function, costs
    two atomic reference-count operations per array argument.

    A waveform record (:mod:`.waveform`: a periodic E of any shape, given
    as samples, with or without a static B: :mod:`.waveform_magnetic`) adds
    the exact response to the field over the flight to the static flight
    (:func:`.waveform_magnetic.shaped_flight`: from the phase's piece at the
    flight's start, found once a flight; a real collision's displacement
    comes with its trial's velocity). With B and without static
    acceleration the trials take the periodic solution instead
    (:mod:`.waveform_periodic`: one rotation a trial, the next flight's
    constants from the trial that ended the last one). Without static
    acceleration each window is bounded from G1 at its ends and the
    constants of the flight (:func:`.waveform_window.stepped_shaped_window`:
    G1, its period and piece handed from window to window); with it, from
    the exact velocity at the window's start
    (:func:`.waveform_magnetic.shaped_window`).

    An oscillating record (:mod:`.oscillating`: the static record extended
    by E0 cos(omega t) with omega > 0) adds the exact response to the
    oscillating force to every flight, the flight's start time giving its
    phase, and bounds each window's speed with
    :func:`.ac_window.stepped_window` (without static acceleration: each
    window hands the parallel velocity and the phase at its end to the next;
    a flight's windows are all as long as its first, so the sines of the
    phase step are taken once a flight) or :func:`.ac_window.oscillating_window` (the exact state). The field's phase is computed once per particle and
    step, then carried from flight to flight: a trial's flight returns the
    phase at its end and its half-angle sines, which give a real collision's
    displacement and the next flight's phase without a sine of their own;
    with B, off cyclotron resonance, the flight is taken about the periodic
    particular solution (:mod:`.particular`: no complex arithmetic).

    Each kind of field (:func:`field_variant`) runs its own machine code of
    the particle loop (:data:`PARTICLE_LOOPS`), compiled on first use: the
    loop of one kind carries none of the others' code and variables.
    """
    scratch = (np.empty(child_pos.shape[1]), np.empty(4, np.uint64), np.empty(gas.shape[0]),
               np.zeros(gas.shape[0], np.int64))
    return PARTICLE_LOOPS[field_variant(field)](
        lo, hi, pos, vel, states, alive, t_start, t_end, field, mass, density, gas, kind, species_of, threshold,
        const_rate, angular, screening, sharing, nodes, sigma, accelerator, accelerator_step, bound, bound_step,
        sigma_max, const_max, sigma_total, tallies, child_pos, child_vel, child_state, child_alive, child_count, check,
        window, growth, budget, *scratch)


def field_variant(field):
    """The kind of field of a record, as the particle loop's variant: :data:`STATIC` (E, and gravity),
    :data:`MAGNETIC` (a static B), :data:`OSCILLATING` (E0 cos(omega t) without B), :data:`OSCILLATING_MAGNETIC`
    (with B, off cyclotron resonance: :func:`.particular.particular_terms`), :data:`NEAR_RESONANCE` (with B within
    :data:`.particular.PARTICULAR_DETUNING` of resonance) or :data:`WAVEFORM` (sampled, with or without B).

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.advance import MAGNETIC, STATIC, field_variant
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> field_variant(derived_field(np.array([0.0, 0.0, 1.0]), np.zeros(3))) == STATIC
    True
    >>> field_variant(derived_field(np.array([0.0, 0.0, 1.0]), np.array([0.0, 1.0, 0.0]))) == MAGNETIC
    True
    """
    if field.shape[0] > RECORD_SIZE:
        return WAVEFORM
    if field.shape[0] > STATIC_SIZE and field[STATIC_SIZE] > 0.0:
        if field[12] == 0.0:
            return OSCILLATING
        return OSCILLATING_MAGNETIC if particular_terms(field)[0] else NEAR_RESONANCE
    return STATIC if field[12] == 0.0 else MAGNETIC


def _variant_loop(variant):
    """The particle loop of one kind of field: a copy of :func:`_advance_particles` that sees ``LOOP_VARIANT =
    variant`` (numba freezes globals as constants), under a name of its own (numba names its cache files by it)."""
    source = _advance_particles
    scope = dict(source.__globals__, LOOP_VARIANT=variant, LOOP_WAVEFORM=variant == WAVEFORM,
                 LOOP_OSCILLATING=variant in (OSCILLATING, OSCILLATING_MAGNETIC, NEAR_RESONANCE),
                 LOOP_PARTICULAR=variant == OSCILLATING_MAGNETIC)
    copy = types.FunctionType(source.__code__, scope, f"{source.__name__}_{variant}")
    copy.__qualname__ = f"{source.__qualname__}_{variant}"
    copy.__doc__, copy.__module__ = source.__doc__, source.__module__
    return borrowing_kernel(copy)


# one compiled particle loop per kind of field, each compiled at its first use
PARTICLE_LOOPS = tuple(_variant_loop(variant) for variant in range(WAVEFORM + 1))
