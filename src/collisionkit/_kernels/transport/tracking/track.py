"""The tracking kernel: particles and their ionization secondaries through fields, gas and surfaces.

Krasov's algorithm (sec. 5.5) with the trajectory integrated numerically:
a particle moves under E(x) and B(x) (Dormand-Prince steps with error
control, :mod:`.integrator`, or the exact flight of :mod:`..flight` where
both fields are uniform); collisions come

* by the path length (``PATH_LENGTH``): an optical depth -ln(xi) is drawn
  and the integral of nu(|v(t)|) dt, a component of the integrated state,
  gathered step by step until it reaches it (the energy-dependent form of
  the drawn free path s = -ln(xi) / (N sigma)); the crossing is found on the
  step's dense output; or
* by null collisions (``NULL_COLLISION``): trial collisions along the
  step's dense output at a rate constant over windows of the step (each at
  most ``WINDOW_COLLISIONS`` / the previous window's rate long, and as long
  as |a| t stays below ``WINDOW_GROWTH`` times the speed), the trial
  frequency of the swarm tables at the largest speed reachable in the
  window: |v(t0)| + a (t1 - t0), with a an upper bound of |qE/m| within the
  window's reach (the magnetic force does no work), or exactly the larger
  end of |v + a t| in a uniform E; each trial real with probability true
  rate / trial rate (Skullerud 1968). The motion is the scalar step of
  :mod:`.motion`.

A step that leaves the volume (some surface's signed distance < 0 at its
middle or end) is cut at the crossing, found by bisection on the dense
output; the particle is absorbed, leaves (both recorded) or is reflected.
Ionization pushes the new electron on the call's stack (and records the
ion's birth); every particle that ends writes an end record.

The call processes the stack until it is empty (``DONE``) or suspends
(``SUSPENDED``) after a collision once the stack, the ion records or the
collision budget of the call run short, or before taking a particle when
the end records are full: the caller empties or grows the buffers and
calls again. Every particle carries its own random stream (children are
seeded from their parent's), so results do not depend on where a call
stopped or on how primaries are split between calls.
"""

from __future__ import annotations

import math


from ...._jit import borrowing_kernel, kernel
from ..layout import ATTACHMENT, IONIZATION
from ..rng import uniform
from ..scattering import isotropic_direction
from .bookkeeping import (
    add_samples, end_record, first_sample, induced_charge, ionize, put_back, record_point, reflected, scatter,
    spread_signal, weighting_charge,
)
from .codes import (
    DONE, E_MAP, B_MAP, ENDED_ATTACHED, ENDED_OUTSIDE_FIELD, ENDED_STEPS, ENDED_SURFACE, ENDED_TIME, NULL_COLLISION,
    REFLECT, SUSPENDED, TALLY_ELECTRONS, TALLY_INDUCED, TALLY_NULL, TALLY_REJECTED, TALLY_STEPS, TALLY_TIME,
)
from .fields import weighting_potential
from .finding import depth_collision, null_collisions, path_collision
from .geometry import lowest_surface
from .integrator import step_factor
from .stepping import exact_step, integrated_step, start_derivative, state_on_step, step_length_limits, volume_exit

SPEED_FLOOR_EV = 1e-3  # eV: the speed scale of the error control and of the step limits for a particle at rest
EV = 1.602176634e-19


@borrowing_kernel
def track_particles(stack_pos, stack_vel, stack_time, stack_birth, stack_state, stack_h, stack_primary, stack_fresh,
                    stack_id, control, tallies, records, births, profiles, signal, moments, group, sample_times,
                    points, e_kind, e_par, e_meta, e_values, e_blocks, e_user, b_kind, b_par, b_meta, b_values, b_user,
                    w_kind, w_par, surfaces, exact, flight,
                    mass, charge, density, method, tolerance, depth_tolerance, length, step_length, time_limit,
                    max_steps, budget, record_births, sharing, profile_kind, profile_par, signal_start, signal_step,
                    gas, kind, species_of, threshold, const_rate, angular, screening, nodes, sigma, accelerator,
                    accelerator_step, bound, bound_step, sigma_max, const_max, species_sigma, species_const, thermal,
                    thermal_step, k, y0, y1, ys, nu_s, trial_s, rng, buffer):
    """Track the particles on the stack (and their secondaries) until they end; see the module docstring.

    ``control``: [stack size, end records written, ion births written,
    real collisions of this call, path points written, the next particle
    number]. ``points`` receives (particle number, t, x, y, z) at the start
    of every particle and the end of every step, while there is room (for
    plots of tracks). Returns ``DONE`` or ``SUSPENDED``.
    """
    qm = charge / mass
    n_proc = kind.shape[0]
    path = method != NULL_COLLISION
    components = 7 if path else 6  # the optical depth is integrated by the path-length method only
    inverse_step = (1.0 / bound_step) * (1.0 + 1e-12)
    inverse_cell = (1.0 / accelerator_step) * (1.0 - 1e-12)
    speed_floor = math.sqrt(2.0 * SPEED_FLOOR_EV * EV / mass)
    current_recorded = signal.shape[0] > 0
    e_box = e_kind == E_MAP
    b_box = b_kind == B_MAP
    uniform_accel = math.sqrt(flight[0] ** 2 + flight[1] ** 2 + flight[2] ** 2)
    # the helpers' arguments, grouped (an inlined call takes at most 30: Python passes more as *args)
    electric, magnetic = (e_kind, e_par, e_meta, e_values), (b_kind, b_par, b_meta, b_values)
    field_bound = (qm, e_kind, e_par, e_meta, e_blocks)
    rates = (mass, density, nodes, accelerator, inverse_cell, species_sigma, species_const, thermal, thermal_step, nu_s)
    trial_tables = (gas, species_of, threshold, const_rate, nodes, sigma, accelerator, inverse_cell, bound,
                    inverse_step, sigma_max, const_max)
    stack = (stack_pos, stack_vel, stack_time, stack_birth, stack_state, stack_h, stack_primary, stack_fresh, stack_id)
    collisions = 0
    while control[0] > 0:
        if control[0] >= stack_pos.shape[0] or control[1] >= records.shape[0]:
            return SUSPENDED
        top = control[0] - 1
        control[0] = top
        x, y, z = stack_pos[top, 0], stack_pos[top, 1], stack_pos[top, 2]
        vx, vy, vz = stack_vel[top, 0], stack_vel[top, 1], stack_vel[top, 2]
        t = stack_time[top]
        birth = stack_birth[top]
        for c in range(4):
            rng[c] = stack_state[top, c]
        h_control = stack_h[top]  # the error control's step; a step taken may be shorter (windows, trials, surfaces)
        h = h_control
        nu_window = 0.0  # the trial frequency of the last window (null collisions)
        primary = stack_primary[top]
        number = stack_id[top]
        if stack_fresh[top]:
            tallies[primary, n_proc + TALLY_ELECTRONS] += 1.0
            record_point(points, control, number, t, x, y, z)
        phi_start = weighting_potential(w_kind, w_par, x, y, z)
        status = -1
        surface = -1
        tau_left = -math.log(uniform(rng))
        need_derivative = True
        steps = 0
        pending = 0  # a crossing found on the dense output: the step is taken again to end exactly there
        pending_h = 0.0
        next_sample = first_sample(sample_times, t)
        while True:
            if need_derivative:
                start_derivative(x, y, z, vx, vy, vz, exact, path, qm, y0, k, electric, e_user, magnetic, b_user,
                                 buffer, rates)
                need_derivative = False
            if steps >= max_steps:
                status = ENDED_STEPS
                break
            remaining = time_limit - t
            if remaining <= 0.0:
                status = ENDED_TIME
                break
            h, accel, clear = step_length_limits(
                x, y, z, math.sqrt(vx * vx + vy * vy + vz * vz), pending_h if pending != 0 else h_control, remaining,
                step_length, speed_floor, surfaces, exact, path, uniform_accel, qm, e_kind, e_par, e_meta, e_blocks,
                e_box, b_box, b_meta)
            # ---- one step: the state at its end in y1, the end derivative in k[6]
            if exact:
                error = exact_step(x, y, z, vx, vy, vz, h, flight, path, y1, k, rates, depth_tolerance)
            else:
                error = integrated_step(x, y, z, vx, vy, vz, h, path, components, qm, y0, y1, k, ys, electric, e_user,
                                        magnetic, b_user, buffer, rates, length, speed_floor, tolerance,
                                        depth_tolerance)
            if error > 1.0:
                h_control = h * step_factor(error)
                pending = 0
                tallies[primary, n_proc + TALLY_REJECTED] += 1.0
                continue
            # the accepted step is the controller's next one; it grows only after a step that ran to its end
            h_control = h
            steps += 1
            tallies[primary, n_proc + TALLY_STEPS] += 1.0
            # ---- where the step ends: leaving the volume (0 none, 2 surface, 3 outside the map), a collision (1),
            # the time limit (4)
            event, s_event, crossed = volume_exit(clear, exact, x, y, z, vx, vy, vz, flight, y0, y1, k, h, surfaces,
                                                  e_box, e_meta, b_box, b_meta)
            if event != 0:
                surface = crossed
                if not exact and s_event > 0.0 and pending == 0:
                    # the dense output is less accurate than a step's end: take the step again, as far as the
                    # crossing, so that the particle ends (or is reflected) with a step's accuracy
                    pending = event
                    pending_h = s_event
                    h = s_event
                    continue
            elif pending != 0 and h == pending_h:  # the step taken again ends at the crossing
                event = pending
                surface = lowest_surface(surfaces, y1[0], y1[1], y1[2])[1] if event == 2 else -1
            pending = 0
            # collisions before s_event
            if path:
                event, s_event, tau_left = depth_collision(event, s_event, tau_left, exact, vx, vy, vz, flight, y0,
                                                           y1, k, h, rates)
            else:
                (event, s_event, tau_left, nu_window, species, gas_vx, gas_vy, gas_vz, gx, gy, gz, g_speed, energy,
                 chosen) = null_collisions(event, s_event, tau_left, nu_window, exact, accel, x, y, z, vx, vy, vz,
                                           flight, y0, y1, k, h, field_bound, speed_floor, tallies, primary,
                                           n_proc + TALLY_NULL, rng, mass, density, trial_tables, trial_s)
            if event == 0 and h >= remaining:
                event = 4
            # ---- the state at s_event; samples and the induced current on the way
            if s_event == h and not exact:
                nx, ny, nz, fx, fy, fz = y1[0], y1[1], y1[2], y1[3], y1[4], y1[5]
            else:
                nx, ny, nz, fx, fy, fz = state_on_step(s_event, exact, x, y, z, vx, vy, vz, flight, y0, y1, k, h)
            next_sample = add_samples(next_sample, t, s_event, exact, x, y, z, vx, vy, vz, flight, y0, y1, k, h,
                                      sample_times, moments, group[primary], mass)
            if current_recorded and s_event > 0.0:
                induced = induced_charge(s_event, exact, x, y, z, vx, vy, vz, nx, ny, nz, fx, fy, fz, flight, y0, y1,
                                         k, h, charge, w_kind, w_par)
                tallies[primary, n_proc + TALLY_INDUCED] += induced
                spread_signal(signal, induced, t, s_event, signal_start, signal_step)
            x, y, z, vx, vy, vz = nx, ny, nz, fx, fy, fz
            t += s_event
            tallies[primary, n_proc + TALLY_TIME] += s_event
            record_point(points, control, number, t, x, y, z)
            if event == 0:
                if not exact:
                    for c in range(6):
                        k[0, c] = k[6, c]
                    y0[0], y0[1], y0[2], y0[3], y0[4], y0[5] = x, y, z, vx, vy, vz
                if path:
                    k[0, 6] = k[6, 6]
                    y0[6] = 0.0
                h_control = h * step_factor(error)
                continue
            if event == 4:
                status = ENDED_TIME
                break
            if event == 3:
                status = ENDED_OUTSIDE_FIELD
                break
            if event == 2:
                if surfaces[surface, 1] == REFLECT:
                    vx, vy, vz = reflected(surfaces, surface, x, y, z, vx, vy, vz)
                    need_derivative = True
                    continue
                status = ENDED_SURFACE
                break
            # ---- a real collision at (x, y, z) with velocity (vx, vy, vz)
            if path:
                species, gas_vx, gas_vy, gas_vz, gx, gy, gz, g_speed, energy, chosen = path_collision(
                    vx, vy, vz, rng, trial_tables, rates)
            collisions += 1
            control[3] += 1
            tallies[primary, chosen] += 1.0
            process = kind[chosen]
            if process == ATTACHMENT:
                status = ENDED_ATTACHED
                break
            if process == IONIZATION:
                vx, vy, vz = ionize(chosen, x, y, z, t, h_control, primary, gas_vx, gas_vy, gas_vz, gx, gy, gz,
                                    g_speed, energy, mass, threshold, sharing, angular, screening, rng, stack,
                                    control, record_births, births, profiles, profile_kind, profile_par)
            else:
                vx, vy, vz = scatter(chosen, process, species, vx, vy, vz, gas_vx, gas_vy, gas_vz, gx, gy, gz,
                                     g_speed, energy, mass, gas, threshold, angular, screening, rng, profiles,
                                     profile_kind, profile_par, x, y, z)
            need_derivative = True
            if control[0] + 2 > stack_pos.shape[0] or (record_births and control[2] + 1 > births.shape[0]) \
                    or collisions >= budget:
                put_back(stack, control, x, y, z, vx, vy, vz, t, birth, rng, h_control, primary, number)
                weighting_charge(tallies, primary, n_proc, charge, w_kind, w_par, x, y, z, phi_start,
                                 current_recorded)
                return SUSPENDED
            tau_left = -math.log(uniform(rng))  # (a suspended particle draws it when taken again)
            record_point(points, control, number, t, x, y, z)
        # ---- the particle ended: its record
        # the surface it ended on, none for another ending (surface may still name one it bounced off or one a
        # collision came before)
        end_record(records, control, primary, status, surface if status == ENDED_SURFACE else -1, t, x, y, z, vx,
                   vy, vz, birth)
        weighting_charge(tallies, primary, n_proc, charge, w_kind, w_par, x, y, z, phi_start, current_recorded)
    return DONE


@kernel
def launch(states, speed, direction, velocities):
    """Velocities of ``speed`` (m/s) along ``direction`` (a unit vector), or isotropic if it is zero, each drawn
    from its particle's own stream (``states``, advanced).

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.tracking.track import launch
    >>> states = np.arange(8, dtype=np.uint64).reshape(2, 4) + np.uint64(1)
    >>> velocities = np.zeros((2, 3))
    >>> launch(states, 2.0, np.zeros(3), velocities)
    >>> np.linalg.norm(velocities, axis=1).round(12).tolist()
    [2.0, 2.0]
    """
    isotropic = direction[0] == 0.0 and direction[1] == 0.0 and direction[2] == 0.0
    for i in range(states.shape[0]):
        if isotropic:
            nx, ny, nz = isotropic_direction(states[i])
        else:
            nx, ny, nz = direction[0], direction[1], direction[2]
        velocities[i, 0], velocities[i, 1], velocities[i, 2] = speed * nx, speed * ny, speed * nz
