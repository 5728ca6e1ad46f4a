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

from ...._jit import kernel
from .codes import E_MAP, ENDED_OUTSIDE_FIELD, ENDED_STEPS, ENDED_SURFACE, ENDED_TIME
from .fields import electric_at, inside_map, weighting_field
from .geometry import lowest_surface
from .integrator import A, E54, hermite_cubic, step_factor

BISECTIONS = 50


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
    sign = 1.0 if charge > 0.0 else -1.0
    k = np.zeros((7, 3))
    y0 = np.zeros(3)
    ys = np.zeros(3)
    buffer = np.zeros(3)
    n_signal = signal.shape[0]
    e_box = e_kind == E_MAP
    total_steps = 0
    for i in range(births.shape[0]):
        primary = int(births[i, 0])
        t = births[i, 1]
        birth = t
        x, y, z = births[i, 2], births[i, 3], births[i, 4]
        ex, ey, ez = electric_at(e_kind, e_par, e_meta, e_values, e_user, buffer, x, y, z)
        k[0, 0], k[0, 1], k[0, 2] = sign * mobility * ex, sign * mobility * ey, sign * mobility * ez
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
            for stage in range(1, 7):
                for c in range(3):
                    total = 0.0
                    for j in range(stage):
                        total += A[stage, j] * k[j, c]
                    ys[c] = y0[c] + h * total
                ex, ey, ez = electric_at(e_kind, e_par, e_meta, e_values, e_user, buffer, ys[0], ys[1], ys[2])
                k[stage, 0], k[stage, 1], k[stage, 2] = sign * mobility * ex, sign * mobility * ey, sign * mobility * ez
            worst = 0.0
            for c in range(3):
                total = 0.0
                for j in range(7):
                    total += E54[j] * k[j, c]
                worst = max(worst, abs(h * total) / (tolerance * length))
            if worst > 1.0:
                h *= step_factor(worst)
                continue
            steps += 1
            # the end of the step: ys (stage 6 is the 5th-order solution), derivative k[6]
            low, high = 0.0, -1.0
            for check in range(2):
                theta = 0.5 if check == 0 else 1.0
                cx = hermite_cubic(y0[0], k[0, 0], ys[0], k[6, 0], h, theta)
                cy = hermite_cubic(y0[1], k[0, 1], ys[1], k[6, 1], h, theta)
                cz = hermite_cubic(y0[2], k[0, 2], ys[2], k[6, 2], h, theta)
                f, _ = lowest_surface(surfaces, cx, cy, cz)
                if f < 0.0 or (e_box and not inside_map(e_meta, cx, cy, cz)):
                    high = theta * h
                    break
            s_event = h
            if high > 0.0:
                low = 0.0 if high == 0.5 * h else 0.5 * h
                for _ in range(BISECTIONS):
                    middle = 0.5 * (low + high)
                    cx = hermite_cubic(y0[0], k[0, 0], ys[0], k[6, 0], h, middle / h)
                    cy = hermite_cubic(y0[1], k[0, 1], ys[1], k[6, 1], h, middle / h)
                    cz = hermite_cubic(y0[2], k[0, 2], ys[2], k[6, 2], h, middle / h)
                    f, _ = lowest_surface(surfaces, cx, cy, cz)
                    if f < 0.0 or (e_box and not inside_map(e_meta, cx, cy, cz)):
                        high = middle
                    else:
                        low = middle
                s_event = low
            theta = s_event / h
            nx = hermite_cubic(y0[0], k[0, 0], ys[0], k[6, 0], h, theta)
            ny = hermite_cubic(y0[1], k[0, 1], ys[1], k[6, 1], h, theta)
            nz = hermite_cubic(y0[2], k[0, 2], ys[2], k[6, 2], h, theta)
            ex, ey, ez = electric_at(e_kind, e_par, e_meta, e_values, e_user, buffer, nx, ny, nz)
            vx, vy, vz = sign * mobility * ex, sign * mobility * ey, sign * mobility * ez
            if w_kind != 0 and s_event > 0.0:
                mx = hermite_cubic(y0[0], k[0, 0], ys[0], k[6, 0], h, 0.5 * theta)
                my = hermite_cubic(y0[1], k[0, 1], ys[1], k[6, 1], h, 0.5 * theta)
                mz = hermite_cubic(y0[2], k[0, 2], ys[2], k[6, 2], h, 0.5 * theta)
                ex, ey, ez = electric_at(e_kind, e_par, e_meta, e_values, e_user, buffer, mx, my, mz)
                wx, wy, wz = weighting_field(w_kind, w_par, x, y, z)
                i0 = wx * k[0, 0] + wy * k[0, 1] + wz * k[0, 2]
                wx, wy, wz = weighting_field(w_kind, w_par, mx, my, mz)
                i1 = sign * mobility * (wx * ex + wy * ey + wz * ez)
                wx, wy, wz = weighting_field(w_kind, w_par, nx, ny, nz)
                i2 = wx * vx + wy * vy + wz * vz
                charge_moved = charge * s_event * (i0 + 4.0 * i1 + i2) / 6.0
                induced[primary] += charge_moved
                if n_signal > 0:
                    b = int(math.floor((t + 0.5 * s_event - signal_start) / signal_step))
                    if 0 <= b < n_signal:
                        signal[b] += charge_moved
            x, y, z = nx, ny, nz
            t += s_event
            if high > 0.0:
                f, surface = lowest_surface(surfaces, cx, cy, cz)
                status = ENDED_SURFACE if f < 0.0 else ENDED_OUTSIDE_FIELD
                break
            k[0, 0], k[0, 1], k[0, 2] = vx, vy, vz
            h *= step_factor(worst)
        total_steps += steps
        row = records[i]
        row[0], row[1], row[2], row[3] = primary, status, surface, t
        row[4], row[5], row[6], row[7], row[8], row[9] = x, y, z, k[0, 0], k[0, 1], k[0, 2]
        row[10] = birth
    return total_steps
