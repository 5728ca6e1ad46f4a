"""Ions drifting at a constant mobility: dx/dt = sign(q) K E(x), until they leave the volume.

The drift velocity follows the local field with a constant mobility K
(m^2/(V s)), the hydrodynamic limit of ion transport at low E/N (no
diffusion). Dormand-Prince steps with error control on the position
(:mod:`.integrator`), the crossing of a surface found by bisection on the
cubic Hermite interpolant of the step (x and dx/dt at both ends); the
induced current q E_w . v integrated by Simpson's rule, as for electrons.
"""

from __future__ import annotations

import math

import numpy as np

from ...._jit import borrowing_kernel, inline_kernel, kernel
from .codes import E_MAP, ENDED_OUTSIDE_FIELD, ENDED_STEPS, ENDED_SURFACE, ENDED_TIME
from .fields import electric_at, inside_map, weighting_field
from .geometry import lowest_surface
from .integrator import A, E54, hermite_cubic, step_factor

BISECTIONS = 50


@inline_kernel
def _ion_velocity(sign, mobility, e_kind, e_par, e_meta, e_values, e_user, buffer, x, y, z):
    """The ion's drift velocity at (x, y, z): v = sign(q) K E(x), a 3-tuple (the hydrodynamic limit at low E/N)."""
    ex, ey, ez = electric_at(e_kind, e_par, e_meta, e_values, e_user, buffer, x, y, z)
    return sign * mobility * ex, sign * mobility * ey, sign * mobility * ez


@inline_kernel
def _ion_stages(k, y0, ys, h, sign, mobility, e_kind, e_par, e_meta, e_values, e_user, buffer):
    """Stages 2 to 7 of a Dormand-Prince step of ``h`` from ``y0`` (``k[0]``: the velocity there), into ``k``.

    ``ys[c] = y0[c] + h sum_j A[stage, j] k[j, c]`` and ``k[stage]`` the
    drift velocity at ``ys`` (Dormand & Prince 1980, :mod:`.integrator`);
    after the last stage ``ys`` holds the 5th-order end of the step and
    ``k[6]`` the velocity there.
    """
    for stage in range(1, 7):
        for c in range(3):
            total = 0.0
            for j in range(stage):
                total += A[stage, j] * k[j, c]
            ys[c] = y0[c] + h * total
        k[stage, 0], k[stage, 1], k[stage, 2] = _ion_velocity(sign, mobility, e_kind, e_par, e_meta, e_values,
                                                              e_user, buffer, ys[0], ys[1], ys[2])


@inline_kernel
def _ion_step_error(k, h, tolerance, length):
    """The error norm of a step: max over x, y, z of |h sum_j E54[j] k[j, c]| / (tolerance length); <= 1 accepts it.

    ``E54`` are the differences of the 5th- and 4th-order weights of
    Dormand & Prince (1980) (:mod:`.integrator`).
    """
    worst = 0.0
    for c in range(3):
        total = 0.0
        for j in range(7):
            total += E54[j] * k[j, c]
        worst = max(worst, abs(h * total) / (tolerance * length))
    return worst


@inline_kernel
def _ion_position(y0, k, ys, h, theta):
    """The position at ``theta h`` into the step: the cubic Hermite interpolant of x and dx/dt at both ends."""
    return (hermite_cubic(y0[0], k[0, 0], ys[0], k[6, 0], h, theta),
            hermite_cubic(y0[1], k[0, 1], ys[1], k[6, 1], h, theta),
            hermite_cubic(y0[2], k[0, 2], ys[2], k[6, 2], h, theta))


@inline_kernel
def _ion_outside(surfaces, e_box, e_meta, x, y, z):
    """Whether (x, y, z) is outside the volume: behind a surface, or outside the field map (``e_box``)."""
    f, _ = lowest_surface(surfaces, x, y, z)
    return f < 0.0 or (e_box and not inside_map(e_meta, x, y, z))


@inline_kernel
def _ion_exit(y0, k, ys, h, surfaces, e_box, e_meta):
    """Where the step leaves the volume, if it does: ``(s_event, high, x, y, z)``.

    The interpolant is checked at the step's middle and end; ``high`` is
    the first of them outside (-1.0 if neither), then ``BISECTIONS``
    halvings of the interval give ``s_event``, the last time found inside
    (``h`` if the step stays inside). (x, y, z) is the last point checked,
    where the caller finds the surface crossed.
    """
    low, high = 0.0, -1.0
    cx = cy = cz = 0.0
    for check in range(2):
        theta = 0.5 if check == 0 else 1.0
        cx, cy, cz = _ion_position(y0, k, ys, h, theta)
        if _ion_outside(surfaces, e_box, e_meta, cx, cy, cz):
            high = theta * h
            break
    s_event = h
    if high > 0.0:
        low = 0.0 if high == 0.5 * h else 0.5 * h
        for _ in range(BISECTIONS):
            middle = 0.5 * (low + high)
            cx, cy, cz = _ion_position(y0, k, ys, h, middle / h)
            if _ion_outside(surfaces, e_box, e_meta, cx, cy, cz):
                high = middle
            else:
                low = middle
        s_event = low
    return s_event, high, cx, cy, cz


@inline_kernel
def _ion_induced_charge(y0, k, ys, h, theta, s_event, x, y, z, nx, ny, nz, vx, vy, vz, sign, mobility, charge,
                        e_kind, e_par, e_meta, e_values, e_user, buffer, w_kind, w_par):
    """The charge induced on the readout over the step's first ``s_event``: Simpson's rule for q E_w . v dt.

    q s (i0 + 4 i1 + i2) / 6 with i = E_w . v at the start (x, y, z), the
    middle and the end (nx, ny, nz) (Shockley 1938, Ramo 1939: the current
    i = q E_w . v).
    """
    mx, my, mz = _ion_position(y0, k, ys, h, 0.5 * theta)
    ex, ey, ez = electric_at(e_kind, e_par, e_meta, e_values, e_user, buffer, mx, my, mz)
    wx, wy, wz = weighting_field(w_kind, w_par, x, y, z)
    i0 = wx * k[0, 0] + wy * k[0, 1] + wz * k[0, 2]
    wx, wy, wz = weighting_field(w_kind, w_par, mx, my, mz)
    i1 = sign * mobility * (wx * ex + wy * ey + wz * ez)
    wx, wy, wz = weighting_field(w_kind, w_par, nx, ny, nz)
    i2 = wx * vx + wy * vy + wz * vz
    return charge * s_event * (i0 + 4.0 * i1 + i2) / 6.0


@inline_kernel
def _bin_signal(signal, t, s_event, signal_start, signal_step, charge_moved):
    """Add a step's induced charge to the time bin of its middle, ``floor((t + s/2 - start) / step)``, if any."""
    b = int(math.floor((t + 0.5 * s_event - signal_start) / signal_step))
    if 0 <= b < signal.shape[0]:
        signal[b] += charge_moved


@inline_kernel
def _drift_ion(primary, t, x, y, z, k, y0, ys, buffer, induced, signal, e_kind, e_par, e_meta, e_values, e_user,
               w_kind, w_par, surfaces, sign, mobility, charge, tolerance, length, time_limit, max_steps,
               signal_start, signal_step):
    """Drift one ion from (x, y, z) at ``t`` until it leaves the volume, the time limit or ``max_steps``.

    Returns ``(status, surface, t, x, y, z, steps)``; ``k[0]`` holds its
    last velocity. The step grows and shrinks by :func:`.integrator.step_factor`
    of the error norm; its first is the time to drift 1e-3 ``length``.
    """
    e_box = e_kind == E_MAP
    k[0, 0], k[0, 1], k[0, 2] = _ion_velocity(sign, mobility, e_kind, e_par, e_meta, e_values, e_user, buffer, x, y, z)
    speed = math.sqrt(k[0, 0] ** 2 + k[0, 1] ** 2 + k[0, 2] ** 2)
    h = 1e-3 * length / speed if speed > 0.0 else time_limit
    status = ENDED_STEPS
    surface = -1
    steps = 0
    while steps < max_steps:
        remaining = time_limit - t
        if remaining <= 0.0:
            status = ENDED_TIME
            break
        h = min(h, remaining)
        y0[0], y0[1], y0[2] = x, y, z
        _ion_stages(k, y0, ys, h, sign, mobility, e_kind, e_par, e_meta, e_values, e_user, buffer)
        worst = _ion_step_error(k, h, tolerance, length)
        if worst > 1.0:
            h *= step_factor(worst)
            continue
        steps += 1
        # the end of the step: ys (stage 6 is the 5th-order solution), derivative k[6]
        s_event, high, cx, cy, cz = _ion_exit(y0, k, ys, h, surfaces, e_box, e_meta)
        theta = s_event / h
        nx, ny, nz = _ion_position(y0, k, ys, h, theta)
        vx, vy, vz = _ion_velocity(sign, mobility, e_kind, e_par, e_meta, e_values, e_user, buffer, nx, ny, nz)
        if w_kind != 0 and s_event > 0.0:
            charge_moved = _ion_induced_charge(y0, k, ys, h, theta, s_event, x, y, z, nx, ny, nz, vx, vy, vz, sign,
                                               mobility, charge, e_kind, e_par, e_meta, e_values, e_user, buffer,
                                               w_kind, w_par)
            induced[primary] += charge_moved
            if signal.shape[0] > 0:
                _bin_signal(signal, t, s_event, signal_start, signal_step, charge_moved)
        x, y, z = nx, ny, nz
        t += s_event
        if high > 0.0:
            f, surface = lowest_surface(surfaces, cx, cy, cz)
            status = ENDED_SURFACE if f < 0.0 else ENDED_OUTSIDE_FIELD
            break
        k[0, 0], k[0, 1], k[0, 2] = vx, vy, vz
        h *= step_factor(worst)
    return status, surface, t, x, y, z, steps


@kernel
def drift_ions(births, records, induced, signal, e_kind, e_par, e_meta, e_values, e_user, w_kind, w_par, surfaces,
               mobility, charge, tolerance, length, time_limit, max_steps, signal_start, signal_step):
    """Drift every ion of ``births`` (rows: primary, time, x, y, z) to the end; one end record each.

    ``records`` receives (primary, status, surface, time, x, y, z, vx, vy,
    vz, birth); ``induced[primary]`` the integral of the induced current
    (C); ``signal`` the induced current binned in time (C per bin). An ion
    ends at the first surface it crosses, whatever the surface does to
    electrons (ions follow field lines, which end on electrodes). Returns
    the number of steps taken.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.tracking import codes
    >>> from collisionkit._kernels.transport.tracking.ions import drift_ions
    >>> from numba import cfunc, types
    >>> births = np.array([[0.0, 0.0, 0.0, 0.0, 0.5e-3]])
    >>> records = np.zeros((1, codes.RECORD_COLUMNS))
    >>> plane = np.array([[codes.PLANE, codes.ABSORB, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0]])
    >>> par = np.array([1e-3, 100.0, 0, 0, 0, 0, 0, 0])  # 1 mm gap, 100 V: E = -1e5 V/m along z
    >>> none = cfunc(types.void(types.float64, types.float64, types.float64, types.CPointer(types.float64)))(
    ...     lambda x, y, z, out: None)
    >>> steps = drift_ions(births, records, np.zeros(1), np.zeros(0), codes.E_PLATES, par, np.zeros(12),
    ...                    np.zeros((2, 2, 2, 3)), none, codes.W_NONE, np.zeros(8), plane, 1e-4, 1.602e-19,
    ...                    1e-8, 1e-3, 1.0, 100000, 0.0, 1.0)
    >>> round(float(records[0, 3]) / 5e-5, 6)  # 0.5 mm at 1e-4 * 1e5 = 10 m/s
    1.0
    """
    return _drift_all_ions(births, records, induced, signal, e_kind, e_par, e_meta, e_values, e_user, w_kind, w_par,
                           surfaces, mobility, charge, tolerance, length, time_limit, max_steps, signal_start,
                           signal_step, np.zeros((7, 3)), np.zeros(3), np.zeros(3), np.zeros(3))


@borrowing_kernel
def _drift_all_ions(births, records, induced, signal, e_kind, e_par, e_meta, e_values, e_user, w_kind, w_par,
                    surfaces, mobility, charge, tolerance, length, time_limit, max_steps, signal_start, signal_step, k,
                    y0, ys, buffer):
    """:func:`drift_ions`' loop over the ions, compiled without reference counting (:func:`collisionkit._jit.
    borrowing_kernel`: with reference counting, the arrays handed to the inlined helpers made the drift about 30 %
    slower, measured); its scratch arrays (``k``: 7 x 3, ``y0``, ``ys``, ``buffer``: 3) come from the caller."""
    sign = 1.0 if charge > 0.0 else -1.0
    total_steps = 0
    for i in range(births.shape[0]):
        primary = int(births[i, 0])
        birth = births[i, 1]
        status, surface, t, x, y, z, steps = _drift_ion(
            primary, birth, births[i, 2], births[i, 3], births[i, 4], k, y0, ys, buffer, induced, signal, e_kind,
            e_par, e_meta, e_values, e_user, w_kind, w_par, surfaces, sign, mobility, charge, tolerance, length,
            time_limit, max_steps, signal_start, signal_step)
        total_steps += steps
        row = records[i]
        row[0], row[1], row[2], row[3] = primary, status, surface, t
        row[4], row[5], row[6], row[7], row[8], row[9] = x, y, z, k[0, 0], k[0, 1], k[0, 2]
        row[10] = birth
    return total_steps
