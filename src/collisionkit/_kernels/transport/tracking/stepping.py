"""One step of a tracked particle: its length, the motion over it, the state along it, where it leaves the volume.

The helpers of :func:`.track.track_particles`, inlined into it. A step
from (x, y, z), (vx, vy, vz) is either the exact flight of :mod:`..flight`
in uniform fields (``exact``) or a Dormand-Prince 5(4) step of
:mod:`.integrator` (the null-collision method's scalar form,
:mod:`.motion`, or the array form with the optical depth as a seventh
component for the path-length method), whose state along the step is the
dense output.
"""

from __future__ import annotations

import math

from ...._jit import inline_kernel
from ..flight import flown_position, flown_velocity
from .fields import electric_at, electric_bound, inside_map, magnetic_at, map_clearance
from .geometry import lowest_surface
from .integrator import B5, C, E54, dense_state, error_norm, stage_state
from .motion import field_step
from .rates import species_rates

GROWTH = 1.0  # null collisions: a step lasts at most the time in which a|t| reaches GROWTH times the speed
BISECTIONS = 50  # halvings of a step to find where it leaves the volume


@inline_kernel
def start_derivative(x, y, z, vx, vy, vz, exact, path, qm, y0, k, electric, e_user, magnetic, b_user, buffer, rates):
    """The state ``y0`` and its derivative ``k[0]`` at the start of a step, after a collision or a reflection.

    ``electric`` and ``magnetic``: (kind, parameters, map header, map
    values) of E and B; ``rates``: the arguments of
    :func:`.rates.species_rates` after the speed.

    dr/dt = v, dv/dt = (q/m)(E + v x B) (not needed by the exact flight)
    and, for the path-length method, d(tau)/dt = nu(|v|), the sum of the
    species' collision frequencies (:func:`.rates.species_rates`).
    """
    e_kind, e_par, e_meta, e_values = electric
    b_kind, b_par, b_meta, b_values = magnetic
    mass, density, nodes, accelerator, inverse_cell, species_sigma, species_const, thermal, thermal_step, nu_s = rates
    y0[0], y0[1], y0[2], y0[3], y0[4], y0[5], y0[6] = x, y, z, vx, vy, vz, 0.0
    if not exact:
        ex, ey, ez = electric_at(e_kind, e_par, e_meta, e_values, e_user, buffer, x, y, z)
        bx, by, bz = magnetic_at(b_kind, b_par, b_meta, b_values, b_user, buffer, x, y, z)
        k[0, 0], k[0, 1], k[0, 2] = vx, vy, vz
        k[0, 3] = qm * (ex + vy * bz - vz * by)
        k[0, 4] = qm * (ey + vz * bx - vx * bz)
        k[0, 5] = qm * (ez + vx * by - vy * bx)
    if path:
        k[0, 6] = species_rates(math.sqrt(vx * vx + vy * vy + vz * vz), mass, density, nodes, accelerator,
                                inverse_cell, species_sigma, species_const, thermal, thermal_step, nu_s)


@inline_kernel
def step_length_limits(x, y, z, speed0, h_wanted, remaining, step_length, speed_floor, surfaces, exact, path,
                       uniform_accel, qm, e_kind, e_par, e_meta, e_blocks, e_box, b_box, b_meta):
    """The next step's length ``h``, a bound ``accel`` of |qE/m| over it and whether it surely stays inside.

    Returns ``(h, accel, clear)``. ``h`` is the wanted step (the error
    control's, or the one retaken to a crossing), at most the time left
    and the time to move max(step length, half the clearance) at
    max(|v|, speed floor); with null collisions also at most GROWTH |v| /
    accel (the trial bound assumes |a| t small against the speed). A step
    moving less than the clearance (|v| h + accel h^2 / 2 below it, with
    the field maps' own clearance) cannot leave the volume (``clear``).
    """
    reference = max(speed0, speed_floor)
    # far from every surface a step may move up to half the clearance, near one the step length
    clearance = lowest_surface(surfaces, x, y, z)[0]
    h = min(h_wanted, remaining, max(step_length, 0.5 * clearance) / reference)
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
    return h, accel, clear


@inline_kernel
def exact_step(x, y, z, vx, vy, vz, h, flight, path, y1, k, rates, depth_tolerance):
    """The exact flight of ``h`` in uniform fields into ``y1``; returns the error norm (0 without optical depth).

    With the path-length method the optical depth over the step is the
    Dormand-Prince quadrature of nu(|v(t)|) at the stages' times along the
    exact velocity, tau = h sum_i B5[i] nu_i, its error h sum_i E54[i] nu_i
    against ``depth_tolerance`` (Dormand & Prince 1980).
    """
    mass, density, nodes, accelerator, inverse_cell, species_sigma, species_const, thermal, thermal_step, nu_s = rates
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
            k[stage, 6] = species_rates(math.sqrt(sx * sx + sy * sy + sz * sz), mass, density, nodes, accelerator,
                                        inverse_cell, species_sigma, species_const, thermal, thermal_step, nu_s)
        for stage in range(6):
            tau += B5[stage] * k[stage, 6]
            estimate += E54[stage] * k[stage, 6]
        estimate += E54[6] * k[5, 6]
        y1[6] = h * tau
        error = abs(h * estimate) / depth_tolerance
        k[6, 6] = k[5, 6]
    return error


@inline_kernel
def integrated_step(x, y, z, vx, vy, vz, h, path, components, qm, y0, y1, k, ys, electric, e_user, magnetic, b_user,
                    buffer, rates, length, speed_floor, tolerance, depth_tolerance):
    """A Dormand-Prince 5(4) step of ``h`` from (x, y, z), (vx, vy, vz) (also in ``y0``) into ``y1`` (the end
    derivative in ``k[6]``); returns the error norm.

    The null-collision method takes the scalar step of :mod:`.motion`; the
    path-length method the array form of :mod:`.integrator`, with
    d(tau)/dt = nu(|v|) as a seventh component (Dormand & Prince 1980).
    """
    e_kind, e_par, e_meta, e_values = electric
    b_kind, b_par, b_meta, b_values = magnetic
    mass, density, nodes, accelerator, inverse_cell, species_sigma, species_const, thermal, thermal_step, nu_s = rates
    if not path:
        end_position, end_velocity, end_accel, error = field_step(
            (x, y, z), (vx, vy, vz), (k[0, 3], k[0, 4], k[0, 5]), h, qm, e_kind, e_par, e_meta, e_values, e_user,
            b_kind, b_par, b_meta, b_values, b_user, buffer, length, speed_floor, tolerance)
        for c in range(3):
            y1[c] = end_position[c]
            y1[3 + c] = end_velocity[c]
            k[6, c] = end_velocity[c]
            k[6, 3 + c] = end_accel[c]
        return error
    for stage in range(1, 7):
        stage_state(y0, k, stage, h, ys, components)
        ex, ey, ez = electric_at(e_kind, e_par, e_meta, e_values, e_user, buffer, ys[0], ys[1], ys[2])
        bx, by, bz = magnetic_at(b_kind, b_par, b_meta, b_values, b_user, buffer, ys[0], ys[1], ys[2])
        k[stage, 0], k[stage, 1], k[stage, 2] = ys[3], ys[4], ys[5]
        k[stage, 3] = qm * (ex + ys[4] * bz - ys[5] * by)
        k[stage, 4] = qm * (ey + ys[5] * bx - ys[3] * bz)
        k[stage, 5] = qm * (ez + ys[3] * by - ys[4] * bx)
        k[stage, 6] = species_rates(math.sqrt(ys[3] ** 2 + ys[4] ** 2 + ys[5] ** 2), mass, density, nodes,
                                    accelerator, inverse_cell, species_sigma, species_const, thermal, thermal_step,
                                    nu_s)
    for c in range(components):
        y1[c] = ys[c]
    return error_norm(y0, y1, k, h, length, speed_floor, tolerance, depth_tolerance, path)


@inline_kernel
def position_on_step(s, exact, x, y, z, vx, vy, vz, flight, y0, y1, k, h):
    """The position ``s`` into the step: the exact flight's, or the dense output's at theta = s / h."""
    if exact:
        return flown_position(x, y, z, vx, vy, vz, s, flight)
    theta = s / h
    cx, cy, cz, _, _, _ = dense_state(y0, y1, k, h, theta)
    return cx, cy, cz


@inline_kernel
def state_on_step(s, exact, x, y, z, vx, vy, vz, flight, y0, y1, k, h):
    """Position and velocity ``s`` into the step (a 6-tuple): the exact flight's, or the dense output's."""
    if exact:
        px, py, pz = flown_position(x, y, z, vx, vy, vz, s, flight)
        ux, uy, uz = flown_velocity(vx, vy, vz, s, flight)
        return px, py, pz, ux, uy, uz
    theta = s / h
    return dense_state(y0, y1, k, h, theta)


@inline_kernel
def outside_volume(surfaces, e_box, e_meta, b_box, b_meta, x, y, z):
    """Whether (x, y, z) is outside the volume: behind a surface (signed distance < 0) or outside a field map."""
    f, _ = lowest_surface(surfaces, x, y, z)
    return f < 0.0 or (e_box and not inside_map(e_meta, x, y, z)) or (b_box and not inside_map(b_meta, x, y, z))


@inline_kernel
def volume_exit(clear, exact, x, y, z, vx, vy, vz, flight, y0, y1, k, h, surfaces, e_box, e_meta, b_box, b_meta):
    """Where the step leaves the volume, if it does: ``(event, s_event, surface)``.

    ``event`` 0 if the step stays inside (``s_event = h``); else 2 (a
    surface, ``surface`` its index) or 3 (outside a field map, surface -1),
    found from the step's middle and end, then ``BISECTIONS`` halvings:
    ``s_event`` is the last time found inside, the surface the one
    crossed at the first time found outside. A ``clear`` step is not checked.
    """
    low, high = 0.0, -1.0
    for check in range(0 if clear else 2):
        s_check = 0.5 * h if check == 0 else h
        cx, cy, cz = position_on_step(s_check, exact, x, y, z, vx, vy, vz, flight, y0, y1, k, h)
        if outside_volume(surfaces, e_box, e_meta, b_box, b_meta, cx, cy, cz):
            high = s_check
            break
        low = s_check
    if not high > 0.0:
        return 0, h, -1
    low = 0.0 if high == 0.5 * h else 0.5 * h
    for _ in range(BISECTIONS):
        middle = 0.5 * (low + high)
        cx, cy, cz = position_on_step(middle, exact, x, y, z, vx, vy, vz, flight, y0, y1, k, h)
        if outside_volume(surfaces, e_box, e_meta, b_box, b_meta, cx, cy, cz):
            high = middle
        else:
            low = middle
    cx, cy, cz = position_on_step(high, exact, x, y, z, vx, vy, vz, flight, y0, y1, k, h)
    f, surface = lowest_surface(surfaces, cx, cy, cz)
    event = 2 if f < 0.0 else 3
    if event == 3:
        surface = -1
    return event, low, surface
