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

import numpy as np

from ...._jit import borrowing_kernel, kernel
from ..collisions import ionized, two_body
from ..flight import flown_position, flown_velocity
from ..layout import ATTACHMENT, ELASTIC, EXCITATION, IONIZATION
from ..moments import add_particle
from ..rng import next_u64, seed_state, uniform
from ..scattering import isotropic_direction
from .codes import (
    DONE, E_MAP, B_MAP, ENDED_ATTACHED, ENDED_OUTSIDE_FIELD, ENDED_STEPS, ENDED_SURFACE, ENDED_TIME,
    NULL_COLLISION, REFLECT, SUSPENDED, TALLY_ELECTRONS, TALLY_INDUCED, TALLY_NULL, TALLY_REJECTED, TALLY_STEPS,
    TALLY_TIME, TALLY_WEIGHTING,
)
from .fields import (
    electric_at, electric_bound, inside_map, magnetic_at, map_clearance, weighting_field, weighting_potential,
)
from .geometry import lowest_surface, surface_normal
from .motion import field_step
from .integrator import (
    B5, C, E54, dense_state, depth_crossing, error_norm, hermite_cubic, stage_state, step_factor,
)
from .rates import (
    chosen_process, chosen_species, profile_bin, rate_bound, species_rates, target_velocity, trial_collision,
    trial_rates,
)

GROWTH = 1.0  # null collisions: a step lasts at most the time in which a|t| reaches GROWTH times the speed
# ... and trials come in windows of constant trial frequency, each at most WINDOW_COLLISIONS / (the previous window's
# frequency) long and the time in which a|t| reaches WINDOW_GROWTH times the speed (a tighter bound, fewer null trials)
WINDOW_COLLISIONS = 1.3
WINDOW_GROWTH = 0.5
NEWTON_ITERATIONS = 8  # path length: refinements of the collision time on the integrated optical depth
GAUSS_NODES = np.array([-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526])
GAUSS_WEIGHTS = np.array([0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538])
BISECTIONS = 50  # halvings of a step to find where it leaves the volume
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
    stack_cap = stack_pos.shape[0]
    n_samples = sample_times.shape[0]
    n_profile = profiles.shape[1]
    n_signal = signal.shape[0]
    e_box = e_kind == E_MAP
    b_box = b_kind == B_MAP
    uniform_accel = math.sqrt(flight[0] ** 2 + flight[1] ** 2 + flight[2] ** 2)
    collisions = 0
    while control[0] > 0:
        if control[0] >= stack_cap or control[1] >= records.shape[0]:
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
        g_row = group[primary]
        phi_start = weighting_potential(w_kind, w_par, x, y, z)
        status = -1
        surface = -1
        tau_left = -math.log(uniform(rng))
        need_derivative = True
        steps = 0
        pending = 0  # a crossing found on the dense output: the step is taken again to end exactly there
        pending_h = 0.0
        if stack_fresh[top] and control[4] < points.shape[0]:
            row = points[control[4]]
            row[0], row[1], row[2], row[3], row[4] = number, t, x, y, z
            control[4] += 1
        next_sample = 0
        while next_sample < n_samples and sample_times[next_sample] < t:
            next_sample += 1
        while True:
            if need_derivative:
                y0[0], y0[1], y0[2], y0[3], y0[4], y0[5], y0[6] = x, y, z, vx, vy, vz, 0.0
                if not exact:
                    ex, ey, ez = electric_at(e_kind, e_par, e_meta, e_values, e_user, buffer, x, y, z)
                    bx, by, bz = magnetic_at(b_kind, b_par, b_meta, b_values, b_user, buffer, x, y, z)
                    k[0, 0], k[0, 1], k[0, 2] = vx, vy, vz
                    k[0, 3] = qm * (ex + vy * bz - vz * by)
                    k[0, 4] = qm * (ey + vz * bx - vx * bz)
                    k[0, 5] = qm * (ez + vx * by - vy * bx)
                if path:
                    k[0, 6] = species_rates(math.sqrt(vx * vx + vy * vy + vz * vz), mass, density, nodes,
                                            accelerator, inverse_cell, species_sigma, species_const, thermal,
                                            thermal_step, nu_s)
                need_derivative = False
            if steps >= max_steps:
                status = ENDED_STEPS
                break
            remaining = time_limit - t
            if remaining <= 0.0:
                status = ENDED_TIME
                break
            speed0 = math.sqrt(vx * vx + vy * vy + vz * vz)
            reference = max(speed0, speed_floor)
            # far from every surface a step may move up to half the clearance, near one the step length
            clearance = lowest_surface(surfaces, x, y, z)[0]
            h = min(pending_h if pending != 0 else h_control, remaining, max(step_length, 0.5 * clearance) / reference)
            accel = uniform_accel if exact else math.inf  # a bound of |q E / m| over the step, if known
            if not path:
                if not exact:
                    reach = (1.0 + GROWTH) * reference * h
                    accel = abs(qm) * electric_bound(e_kind, e_par, e_meta, e_blocks, x, y, z, reach)
                if accel > 0.0:
                    h = min(h, GROWTH * reference / accel)
            # a step that moves less than the clearance cannot leave the volume: no crossing to look for
            if e_box:
                clearance = min(clearance, map_clearance(e_meta, x, y, z))
            if b_box:
                clearance = min(clearance, map_clearance(b_meta, x, y, z))
            clear = speed0 * h + 0.5 * accel * h * h < clearance
            # ---- one step: the state at its end in y1, the end derivative in k[6]
            if exact:
                px, py, pz = flown_position(x, y, z, vx, vy, vz, h, flight)
                qx, qy, qz = flown_velocity(vx, vy, vz, h, flight)
                y1[0], y1[1], y1[2], y1[3], y1[4], y1[5] = px, py, pz, qx, qy, qz
                error = 0.0
                if path:  # the optical depth by the stages' quadrature along the exact velocity
                    tau = 0.0
                    estimate = 0.0
                    for stage in range(1, 7):
                        if stage < 6:
                            sx, sy, sz = flown_velocity(vx, vy, vz, C[stage] * h, flight)
                        else:
                            sx, sy, sz = qx, qy, qz
                        k[stage, 6] = species_rates(math.sqrt(sx * sx + sy * sy + sz * sz), mass, density, nodes,
                                                    accelerator, inverse_cell, species_sigma, species_const,
                                                    thermal, thermal_step, nu_s)
                    for stage in range(6):
                        tau += B5[stage] * k[stage, 6]
                        estimate += E54[stage] * k[stage, 6]
                    estimate += E54[6] * k[5, 6]
                    y1[6] = h * tau
                    error = abs(h * estimate) / depth_tolerance
                    k[6, 6] = k[5, 6]
            elif not path:
                end_position, end_velocity, end_accel, error = field_step(
                    (x, y, z), (vx, vy, vz), (k[0, 3], k[0, 4], k[0, 5]), h, qm, e_kind, e_par, e_meta, e_values,
                    e_user, b_kind, b_par, b_meta, b_values, b_user, buffer, length, speed_floor, tolerance)
                for c in range(3):
                    y1[c] = end_position[c]
                    y1[3 + c] = end_velocity[c]
                    k[6, c] = end_velocity[c]
                    k[6, 3 + c] = end_accel[c]
            else:
                for stage in range(1, 7):
                    stage_state(y0, k, stage, h, ys, components)
                    ex, ey, ez = electric_at(e_kind, e_par, e_meta, e_values, e_user, buffer, ys[0], ys[1], ys[2])
                    bx, by, bz = magnetic_at(b_kind, b_par, b_meta, b_values, b_user, buffer, ys[0], ys[1], ys[2])
                    k[stage, 0], k[stage, 1], k[stage, 2] = ys[3], ys[4], ys[5]
                    k[stage, 3] = qm * (ex + ys[4] * bz - ys[5] * by)
                    k[stage, 4] = qm * (ey + ys[5] * bx - ys[3] * bz)
                    k[stage, 5] = qm * (ez + ys[3] * by - ys[4] * bx)
                    if path:
                        k[stage, 6] = species_rates(math.sqrt(ys[3] ** 2 + ys[4] ** 2 + ys[5] ** 2), mass, density,
                                                    nodes, accelerator, inverse_cell, species_sigma, species_const,
                                                    thermal, thermal_step, nu_s)
                    else:
                        k[stage, 6] = 0.0
                for c in range(components):
                    y1[c] = ys[c]
                error = error_norm(y0, y1, k, h, length, speed_floor, tolerance, depth_tolerance, path)
            if error > 1.0:
                h_control = h * step_factor(error)
                pending = 0
                tallies[primary, n_proc + TALLY_REJECTED] += 1.0
                continue
            # the accepted step is the controller's next one; it grows only after a step that ran to its end
            h_control = h
            steps += 1
            tallies[primary, n_proc + TALLY_STEPS] += 1.0
            # ---- where the step ends: leaving the volume, a collision, the time limit
            event = 0  # 0 none, 1 collision, 2 surface, 3 outside the map, 4 time limit
            s_event = h
            low, high = 0.0, -1.0
            for check in range(0 if clear else 2):
                s_check = 0.5 * h if check == 0 else h
                if exact:
                    cx, cy, cz = flown_position(x, y, z, vx, vy, vz, s_check, flight)
                else:
                    theta = s_check / h
                    cx, cy, cz, _, _, _ = dense_state(y0, y1, k, h, theta)
                f, _ = lowest_surface(surfaces, cx, cy, cz)
                if f < 0.0 or (e_box and not inside_map(e_meta, cx, cy, cz)) or \
                        (b_box and not inside_map(b_meta, cx, cy, cz)):
                    high = s_check
                    break
                low = s_check
            if high > 0.0:
                low = 0.0 if high == 0.5 * h else 0.5 * h
                for _ in range(BISECTIONS):
                    middle = 0.5 * (low + high)
                    if exact:
                        cx, cy, cz = flown_position(x, y, z, vx, vy, vz, middle, flight)
                    else:
                        theta = middle / h
                        cx, cy, cz, _, _, _ = dense_state(y0, y1, k, h, theta)
                    f, _ = lowest_surface(surfaces, cx, cy, cz)
                    if f < 0.0 or (e_box and not inside_map(e_meta, cx, cy, cz)) or \
                            (b_box and not inside_map(b_meta, cx, cy, cz)):
                        high = middle
                    else:
                        low = middle
                s_event = low
                if exact:
                    cx, cy, cz = flown_position(x, y, z, vx, vy, vz, high, flight)
                else:
                    theta = high / h
                    cx, cy, cz, _, _, _ = dense_state(y0, y1, k, h, theta)
                f, surface = lowest_surface(surfaces, cx, cy, cz)
                event = 2 if f < 0.0 else 3
                if event == 3:
                    surface = -1
                if not exact and low > 0.0 and pending == 0:
                    # the dense output is less accurate than a step's end: take the step again, as far as the
                    # crossing, so that the particle ends (or is reflected) with a step's accuracy
                    pending = event
                    pending_h = low
                    h = low
                    continue
            elif pending != 0 and h == pending_h:  # the step taken again ends at the crossing
                event = pending
                surface = lowest_surface(surfaces, y1[0], y1[1], y1[2])[1] if event == 2 else -1
            pending = 0
            # collisions before s_event
            chosen = -1
            species = 0
            gas_vx = gas_vy = gas_vz = 0.0
            gx = gy = gz = g_speed = energy = 0.0
            if path:
                if s_event == h:
                    reached = y1[6]
                else:
                    reached = hermite_cubic(0.0, k[0, 6], y1[6], k[6, 6], h, s_event / h)
                if reached >= tau_left:
                    # the cubic interpolant's root, refined by Newton's method on the optical depth integrated
                    # along the dense velocity (4-point Gauss-Legendre): the cubic alone ignores how the rate
                    # varies inside the step, and biased the collision times
                    s_root = depth_crossing(k[0, 6], y1[6], k[6, 6], h, tau_left, s_event, reached)
                    for _ in range(NEWTON_ITERATIONS):
                        depth = 0.0
                        for node in range(5):
                            s_node = 0.5 * s_root * (1.0 + GAUSS_NODES[node]) if node < 4 else s_root
                            if exact:
                                ux, uy, uz = flown_velocity(vx, vy, vz, s_node, flight)
                            else:
                                theta = s_node / h
                                _, _, _, ux, uy, uz = dense_state(y0, y1, k, h, theta)
                            rate = species_rates(math.sqrt(ux * ux + uy * uy + uz * uz), mass, density, nodes,
                                                 accelerator, inverse_cell, species_sigma, species_const, thermal,
                                                 thermal_step, nu_s)
                            if node < 4:
                                depth += GAUSS_WEIGHTS[node] * rate
                        depth *= 0.5 * s_root
                        s_next = s_root - (depth - tau_left) / rate if rate > 0.0 else s_root
                        s_next = min(max(s_next, 0.0), s_event)
                        if abs(s_next - s_root) <= 1e-12 * h:
                            s_root = s_next
                            break
                        s_root = s_next
                    s_event = s_root
                    event = 1
                else:
                    tau_left -= reached
            else:
                # windows of constant trial frequency along [0, s_event): in each, the rate bound at the largest
                # speed reachable in it; trials where the drawn optical depth runs out
                start = 0.0
                while start < s_event:
                    wx, wy, wz, ux, uy, uz = x, y, z, vx, vy, vz
                    if start > 0.0 and exact:
                        ux, uy, uz = flown_velocity(vx, vy, vz, start, flight)
                    elif start > 0.0:
                        wx, wy, wz, ux, uy, uz = dense_state(y0, y1, k, h, start / h)
                    speed = math.sqrt(ux * ux + uy * uy + uz * uz)
                    window_reference = max(speed, speed_floor)
                    end = s_event
                    if nu_window > 0.0:
                        end = min(end, start + WINDOW_COLLISIONS / nu_window)
                    window_accel = accel  # the step's bound, or a tighter one over the window's own reach
                    if not exact:
                        window_accel = min(accel, abs(qm) * electric_bound(
                            e_kind, e_par, e_meta, e_blocks, wx, wy, wz,
                            (1.0 + WINDOW_GROWTH) * window_reference * (end - start)))
                    if window_accel > 0.0:
                        end = min(end, start + WINDOW_GROWTH * window_reference / window_accel)
                    if end <= start:  # (a window too short to advance the time in floating point)
                        end, window_accel = s_event, accel
                    if exact and flight[12] == 0.0:  # |v + a t| is convex in t: its largest value is at an end
                        top_speed = max(speed, math.sqrt((vx + flight[0] * end) ** 2 + (vy + flight[1] * end) ** 2
                                                         + (vz + flight[2] * end) ** 2))
                    else:  # the magnetic force does no work: d|v|/dt <= |q E / m|
                        top_speed = speed + window_accel * (end - start)
                    nu_window = trial_rates(top_speed, density, gas, bound, inverse_step, sigma_max, const_max,
                                            trial_s)
                    position = start
                    while nu_window > 0.0 and position + tau_left / nu_window < end:
                        position += tau_left / nu_window
                        if exact:
                            ux, uy, uz = flown_velocity(vx, vy, vz, position, flight)
                        else:
                            _, _, _, ux, uy, uz = dense_state(y0, y1, k, h, position / h)
                        species, gas_vx, gas_vy, gas_vz, gx, gy, gz, g_speed, energy, chosen = trial_collision(
                            ux, uy, uz, nu_window, trial_s, rng, mass, density, gas, species_of, threshold,
                            const_rate, nodes, sigma, accelerator, inverse_cell)
                        if chosen >= 0:
                            break
                        tallies[primary, n_proc + TALLY_NULL] += 1.0
                        tau_left = -math.log(uniform(rng))
                    if chosen >= 0:
                        s_event = position
                        event = 1
                        break
                    tau_left -= nu_window * (end - position)
                    start = end
            if event == 0 and h >= remaining:
                event = 4
            # ---- the state at s_event; samples and the induced current on the way
            if exact:
                nx_, ny_, nz_ = flown_position(x, y, z, vx, vy, vz, s_event, flight)
                fx, fy, fz = flown_velocity(vx, vy, vz, s_event, flight)
            elif s_event == h:
                nx_, ny_, nz_, fx, fy, fz = y1[0], y1[1], y1[2], y1[3], y1[4], y1[5]
            else:
                theta = s_event / h
                nx_, ny_, nz_, fx, fy, fz = dense_state(y0, y1, k, h, theta)
            while next_sample < n_samples and sample_times[next_sample] <= t + s_event:
                s_sample = sample_times[next_sample] - t
                if exact:
                    sx, sy, sz = flown_position(x, y, z, vx, vy, vz, s_sample, flight)
                    ux, uy, uz = flown_velocity(vx, vy, vz, s_sample, flight)
                else:
                    theta = s_sample / h
                    sx, sy, sz, ux, uy, uz = dense_state(y0, y1, k, h, theta)
                add_particle(moments[g_row, next_sample], mass, sx, sy, sz, ux, uy, uz)
                next_sample += 1
            if n_signal > 0 and s_event > 0.0:
                # Simpson's rule for the integral of q E_w . v over [0, s_event]
                half = 0.5 * s_event
                if exact:
                    mx, my, mz = flown_position(x, y, z, vx, vy, vz, half, flight)
                    nx, ny, nz = flown_velocity(vx, vy, vz, half, flight)
                else:
                    theta = half / h
                    mx, my, mz, nx, ny, nz = dense_state(y0, y1, k, h, theta)
                wx, wy, wz = weighting_field(w_kind, w_par, x, y, z)
                i0 = wx * vx + wy * vy + wz * vz
                wx, wy, wz = weighting_field(w_kind, w_par, mx, my, mz)
                i1 = wx * nx + wy * ny + wz * nz
                wx, wy, wz = weighting_field(w_kind, w_par, nx_, ny_, nz_)
                i2 = wx * fx + wy * fy + wz * fz
                induced = charge * s_event * (i0 + 4.0 * i1 + i2) / 6.0
                tallies[primary, n_proc + TALLY_INDUCED] += induced
                if n_signal > 0:
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
            x, y, z, vx, vy, vz = nx_, ny_, nz_, fx, fy, fz
            t += s_event
            tallies[primary, n_proc + TALLY_TIME] += s_event
            if control[4] < points.shape[0]:
                row = points[control[4]]
                row[0], row[1], row[2], row[3], row[4] = number, t, x, y, z
                control[4] += 1
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
                    nx, ny, nz = surface_normal(surfaces, surface, x, y, z)
                    dot = vx * nx + vy * ny + vz * nz
                    vx -= 2.0 * dot * nx
                    vy -= 2.0 * dot * ny
                    vz -= 2.0 * dot * nz
                    need_derivative = True
                    continue
                status = ENDED_SURFACE
                break
            # ---- a real collision at (x, y, z) with velocity (vx, vy, vz)
            if path:
                speed = math.sqrt(vx * vx + vy * vy + vz * vz)
                total = species_rates(speed, mass, density, nodes, accelerator, inverse_cell, species_sigma,
                                      species_const, thermal, thermal_step, nu_s)
                species = chosen_species(uniform(rng) * total, nu_s)
                while True:  # the target's velocity and the process: rejection against the species' bound
                    gas_vx, gas_vy, gas_vz = target_velocity(gas, species, rng)
                    if gas[species, 1] > 0.0:
                        ceiling = density * rate_bound(species, speed + gas[species, 2], bound, inverse_step,
                                                       sigma_max, const_max)
                    else:
                        ceiling = nu_s[species]
                    gx, gy, gz = vx - gas_vx, vy - gas_vy, vz - gas_vz
                    g_speed = math.sqrt(gx * gx + gy * gy + gz * gz)
                    energy = 0.5 * mass * g_speed * g_speed
                    chosen = chosen_process(uniform(rng) * ceiling, species, g_speed, energy, density, species_of,
                                            threshold, const_rate, nodes, sigma, accelerator, inverse_cell)
                    if chosen >= 0:
                        break
            collisions += 1
            control[3] += 1
            tallies[primary, chosen] += 1.0
            process = kind[chosen]
            if process == ATTACHMENT:
                status = ENDED_ATTACHED
                break
            if process == IONIZATION:
                v1x, v1y, v1z, v2x, v2y, v2z = ionized(gas_vx, gas_vy, gas_vz, gx, gy, gz, g_speed, energy, mass,
                                                       threshold[chosen], sharing, angular[chosen],
                                                       screening[chosen], rng)
                vx, vy, vz = v1x, v1y, v1z
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
                if n_profile > 0:
                    b = profile_bin(profile_kind, profile_par, n_profile, x, y, z)
                    if b >= 0:
                        profiles[0, b] += 1.0
            else:
                loss = 0.0 if process == ELASTIC else threshold[chosen]
                vx, vy, vz = two_body(vx, vy, vz, gas_vx, gas_vy, gas_vz, gx, gy, gz, g_speed, energy, mass,
                                      gas[species, 0], loss, angular[chosen], screening[chosen], rng)
                if process == EXCITATION and n_profile > 0:
                    b = profile_bin(profile_kind, profile_par, n_profile, x, y, z)
                    if b >= 0:
                        profiles[1, b] += 1.0
            need_derivative = True
            if control[0] + 2 > stack_cap or (record_births and control[2] + 1 > births.shape[0]) \
                    or collisions >= budget:
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
                moved = -charge * (weighting_potential(w_kind, w_par, x, y, z) - phi_start)
                tallies[primary, n_proc + TALLY_WEIGHTING] += moved
                if n_signal == 0:
                    tallies[primary, n_proc + TALLY_INDUCED] += moved
                return SUSPENDED
            tau_left = -math.log(uniform(rng))  # (a suspended particle draws it when taken again)
            if control[4] < points.shape[0]:
                row = points[control[4]]
                row[0], row[1], row[2], row[3], row[4] = number, t, x, y, z
                control[4] += 1
        # ---- the particle ended: its record
        row = records[control[1]]
        row[0], row[1], row[2], row[3] = primary, status, surface, t
        row[4], row[5], row[6], row[7], row[8], row[9] = x, y, z, vx, vy, vz
        row[10] = birth
        control[1] += 1
        moved = -charge * (weighting_potential(w_kind, w_par, x, y, z) - phi_start)
        tallies[primary, n_proc + TALLY_WEIGHTING] += moved
        if n_signal == 0:  # no current recorded: the induced charge is Shockley-Ramo's, exact in a static field
            tallies[primary, n_proc + TALLY_INDUCED] += moved
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
