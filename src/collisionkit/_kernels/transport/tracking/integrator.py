"""The Dormand-Prince 5(4) step with error control, and the dense output of an accepted step.

State y = (x, y, z, vx, vy, vz, tau): position, velocity and the optical
depth ``tau`` gathered since the start of the step (Krasov's path length in
its energy-dependent form, d tau/dt = nu(|v|); zero in the null-collision
method). Coefficients: Dormand & Prince, J. Comput. Appl. Math. 6, 19 (1980)
(the 5th-order solution is propagated, the 4th-order one estimates the
error; the last stage is the derivative at the new point, reused as the
first stage of the next step).

Dense output (from the two ends of the step alone, an independent
construction): the position is the quintic Hermite interpolant of x, v and
a = dv/dt at both ends (local error O(h^6)), the velocity its derivative
(O(h^5)), the optical depth the cubic Hermite interpolant of tau and nu.
"""

from __future__ import annotations

import math

import numpy as np

from ...._jit import inline_kernel

C = np.array([0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0])
A = np.array([
    [0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0, 0.0, 0.0],
    [9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0, 0.0],
    [35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0],
])
A21 = 1.0 / 5.0
A31, A32 = 3.0 / 40.0, 9.0 / 40.0
A41, A42, A43 = 44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0
A51, A52, A53, A54 = 19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0
A61, A62, A63, A64, A65 = 9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0
A71, A73, A74, A75, A76 = 35.0 / 384.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0
B5 = np.array([35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0, 0.0])
# 5th minus 4th order weights: the error estimate
E54 = np.array([71.0 / 57600.0, 0.0, -71.0 / 16695.0, 71.0 / 1920.0, -17253.0 / 339200.0, 22.0 / 525.0, -1.0 / 40.0])

E1, E3, E4, E5, E6, E7 = (71.0 / 57600.0, -71.0 / 16695.0, 71.0 / 1920.0, -17253.0 / 339200.0, 22.0 / 525.0,
                          -1.0 / 40.0)
SAFETY = 0.9
SHRINK = 0.2  # a step shrinks at most this much, and grows at most GROW times, per try
GROW = 5.0
LOWEST_ERROR = (GROW / SAFETY) ** -5.0  # error norms beyond these give the limits of the step factor
HIGHEST_ERROR = (SHRINK / SAFETY) ** -5.0


@inline_kernel
def step_factor(error):
    """The factor of the next step size for an error norm (1 = on tolerance): 0.9 error^(-1/5), in [0.2, 5]."""
    if error <= LOWEST_ERROR:
        return GROW
    if error >= HIGHEST_ERROR:
        return SHRINK
    return SAFETY * math.exp(-0.2 * math.log(error))  # (pow() costs as much as the rest of a step's bookkeeping)


@inline_kernel
def stage_state(y0, k, stage, h, out, components=7):
    """The state at which stage ``stage`` (1..6) evaluates the derivative: y0 + h sum_j A[stage, j] k[j] (its first
    ``components`` components: 6 without the optical depth)."""
    # written out, the stage chosen once outside the loop: a loop over the tableau costs more than the arithmetic
    if stage == 1:
        for c in range(components):
            out[c] = y0[c] + h * (A21 * k[0, c])
    elif stage == 2:
        for c in range(components):
            out[c] = y0[c] + h * (A31 * k[0, c] + A32 * k[1, c])
    elif stage == 3:
        for c in range(components):
            out[c] = y0[c] + h * (A41 * k[0, c] + A42 * k[1, c] + A43 * k[2, c])
    elif stage == 4:
        for c in range(components):
            out[c] = y0[c] + h * (A51 * k[0, c] + A52 * k[1, c] + A53 * k[2, c] + A54 * k[3, c])
    elif stage == 5:
        for c in range(components):
            out[c] = y0[c] + h * (A61 * k[0, c] + A62 * k[1, c] + A63 * k[2, c] + A64 * k[3, c] + A65 * k[4, c])
    else:
        for c in range(components):
            out[c] = y0[c] + h * (A71 * k[0, c] + A73 * k[2, c] + A74 * k[3, c] + A75 * k[4, c] + A76 * k[5, c])


@inline_kernel
def combine(y0, k, h, y1):
    """The 5th-order solution, in ``y1``, from the first six stages."""
    for c in range(7):
        total = 0.0
        for j in range(6):
            total += B5[j] * k[j, c]
        y1[c] = y0[c] + h * total


@inline_kernel
def error_norm(y0, y1, k, h, position_scale, speed_floor, tolerance, depth_tolerance, with_tau):
    """The max norm of the error estimate scaled by the tolerances (<= 1: the step is accepted).

    Position components against ``tolerance * position_scale``, velocity
    ones against ``tolerance * max(|v0|, |v1|, speed_floor)``, the optical
    depth against ``depth_tolerance`` (absolute).
    """
    speed = max(speed_floor, math.sqrt(max(y0[3] * y0[3] + y0[4] * y0[4] + y0[5] * y0[5],
                                           y1[3] * y1[3] + y1[4] * y1[4] + y1[5] * y1[5])))
    worst = 0.0
    last = 7 if with_tau else 6
    for c in range(last):
        total = (E1 * k[0, c] + E3 * k[2, c] + E4 * k[3, c] + E5 * k[4, c] + E6 * k[5, c] + E7 * k[6, c])
        scale = tolerance * (position_scale if c < 3 else speed) if c < 6 else depth_tolerance
        worst = max(worst, abs(h * total) / scale)
    return worst


@inline_kernel
def hermite_position(x0, v0, a0, x1, v1, a1, h, theta):
    """Quintic Hermite interpolant at theta = s/h of x, v = x' and a = x'' given at both ends: (x, v)."""
    t2 = theta * theta
    t3 = t2 * theta
    t4 = t3 * theta
    t5 = t4 * theta
    h00 = 1.0 - 10.0 * t3 + 15.0 * t4 - 6.0 * t5
    h10 = theta - 6.0 * t3 + 8.0 * t4 - 3.0 * t5
    h20 = 0.5 * (t2 - 3.0 * t3 + 3.0 * t4 - t5)
    h01 = 10.0 * t3 - 15.0 * t4 + 6.0 * t5
    h11 = -4.0 * t3 + 7.0 * t4 - 3.0 * t5
    h21 = 0.5 * (t3 - 2.0 * t4 + t5)
    d00 = -30.0 * t2 + 60.0 * t3 - 30.0 * t4
    d10 = 1.0 - 18.0 * t2 + 32.0 * t3 - 15.0 * t4
    d20 = 0.5 * (2.0 * theta - 9.0 * t2 + 12.0 * t3 - 5.0 * t4)
    d11 = -12.0 * t2 + 28.0 * t3 - 15.0 * t4
    d21 = 0.5 * (3.0 * t2 - 8.0 * t3 + 5.0 * t4)
    position = h00 * x0 + h * (h10 * v0 + h * h20 * a0) + h01 * x1 + h * (h11 * v1 + h * h21 * a1)
    velocity = d00 * (x0 - x1) / h + d10 * v0 + h * d20 * a0 + d11 * v1 + h * d21 * a1
    return position, velocity


@inline_kernel
def dense_state(y0, y1, k, h, theta):
    """Position and velocity (a 6-tuple) of the step's dense output at theta = s/h: the quintic Hermite interpolant
    of :func:`hermite_position` for the three axes, its basis computed once (y: states, k[0] and k[6]: derivatives
    at the ends)."""
    t2 = theta * theta
    t3 = t2 * theta
    t4 = t3 * theta
    t5 = t4 * theta
    h00 = 1.0 - 10.0 * t3 + 15.0 * t4 - 6.0 * t5
    h10 = h * (theta - 6.0 * t3 + 8.0 * t4 - 3.0 * t5)
    h20 = h * h * 0.5 * (t2 - 3.0 * t3 + 3.0 * t4 - t5)
    h01 = 10.0 * t3 - 15.0 * t4 + 6.0 * t5
    h11 = h * (-4.0 * t3 + 7.0 * t4 - 3.0 * t5)
    h21 = h * h * 0.5 * (t3 - 2.0 * t4 + t5)
    d00 = (-30.0 * t2 + 60.0 * t3 - 30.0 * t4) / h
    d10 = 1.0 - 18.0 * t2 + 32.0 * t3 - 15.0 * t4
    d20 = h * 0.5 * (2.0 * theta - 9.0 * t2 + 12.0 * t3 - 5.0 * t4)
    d11 = -12.0 * t2 + 28.0 * t3 - 15.0 * t4
    d21 = h * 0.5 * (3.0 * t2 - 8.0 * t3 + 5.0 * t4)
    x = h00 * y0[0] + h10 * y0[3] + h20 * k[0, 3] + h01 * y1[0] + h11 * y1[3] + h21 * k[6, 3]
    y = h00 * y0[1] + h10 * y0[4] + h20 * k[0, 4] + h01 * y1[1] + h11 * y1[4] + h21 * k[6, 4]
    z = h00 * y0[2] + h10 * y0[5] + h20 * k[0, 5] + h01 * y1[2] + h11 * y1[5] + h21 * k[6, 5]
    vx = d00 * (y0[0] - y1[0]) + d10 * y0[3] + d20 * k[0, 3] + d11 * y1[3] + d21 * k[6, 3]
    vy = d00 * (y0[1] - y1[1]) + d10 * y0[4] + d20 * k[0, 4] + d11 * y1[4] + d21 * k[6, 4]
    vz = d00 * (y0[2] - y1[2]) + d10 * y0[5] + d20 * k[0, 5] + d11 * y1[5] + d21 * k[6, 5]
    return x, y, z, vx, vy, vz


@inline_kernel
def hermite_cubic(y0, d0, y1, d1, h, theta):
    """Cubic Hermite interpolant at theta = s/h of a value and its derivative given at both ends."""
    t2 = theta * theta
    t3 = t2 * theta
    return ((2.0 * t3 - 3.0 * t2 + 1.0) * y0 + (t3 - 2.0 * t2 + theta) * h * d0 + (3.0 * t2 - 2.0 * t3) * y1
            + (t3 - t2) * h * d1)


@inline_kernel
def depth_crossing(nu0, depth1, nu1, h, target, s_high, depth_high):
    """The time s in (0, s_high] at which the cubic Hermite optical depth (0 at s = 0, ``depth1`` at h, rates nu0,
    nu1 at the ends) reaches ``target`` (<= ``depth_high``, its value at ``s_high``).

    Newton's method on the cubic from the secant guess, kept inside the
    bracket (a step out of it bisects); to 1e-13 of the step.
    """
    low, high = 0.0, s_high
    f_low, f_high = -target, depth_high - target
    s = s_high * (-f_low) / (f_high - f_low) if f_high > f_low else 0.5 * s_high
    for _ in range(60):
        theta = s / h
        t2 = theta * theta
        t3 = t2 * theta
        f = (t3 - 2.0 * t2 + theta) * h * nu0 + (3.0 * t2 - 2.0 * t3) * depth1 + (t3 - t2) * h * nu1 - target
        if f >= 0.0:
            high = s
        else:
            low = s
        slope = ((3.0 * t2 - 4.0 * theta + 1.0) * nu0 + (6.0 * theta - 6.0 * t2) * depth1 / h
                 + (3.0 * t2 - 2.0 * theta) * nu1)
        s_next = s - f / slope if slope > 0.0 else 0.5 * (low + high)
        if not (low < s_next < high):
            s_next = 0.5 * (low + high)
        if abs(s_next - s) <= 1e-13 * h:
            return s_next
        if high - low <= 1e-13 * h:
            return high
        s = s_next
    return high
