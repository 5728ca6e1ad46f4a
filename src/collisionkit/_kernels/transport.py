"""Numba kernels of the Monte Carlo transport engine (swarms and slabs).

Algorithm (Krasov, sec. 5.5, extended as in Skullerud, J. Phys. D 1, 1567
(1968) and Lin & Bardsley, J. Chem. Phys. 66, 435 (1977)):

* every particle carries its own random stream (xoshiro256+, state of four
  uint64 words); a kernel call advances particles ``lo..hi`` independently,
  so the result does not depend on how particles are split over threads;
* free flight is exact: constant acceleration, or gyration about B plus the
  E x B drift (the closed-form solution of dv/dt = a + v x Omega);
* collisions by the null-collision method with an exact, speed-dependent
  trial frequency, piecewise constant in time: a flight (from one real
  collision to the next) is cut into windows of about WINDOW_COLLISIONS
  trial collisions; in a window the trial frequency is the table bound
  ``B(v)`` of ``sum_j N sigma_j(eps) g`` (a running maximum over speed
  bins, so it covers every lower speed) at the largest speed the particle
  can reach in the window (exact without B: |v + a t|^2 is convex in t, so
  the largest speed is at an end of the window; with B, |v| + |a| t), plus
  the largest gas speed that can occur. One exponential optical depth is
  drawn per trial and used up window by window (the integrated hazard of a
  piecewise-constant rate). Null trials do not move the particle: it is
  moved to a real collision, or to the end of the step;
* at a trial collision the target species is chosen by its share of the
  trial frequency, a target velocity is drawn from the gas Maxwellian, and
  the process by its rate ``N sigma_j(eps) g + N k_j``; otherwise the
  collision is null;
* scattering in the centre-of-mass frame (isotropic or screened Coulomb),
  exact recoil for elastic collisions, thresholds subtracted from the
  relative kinetic energy; ionization creates a new particle (children are
  advanced within the same call and stored in the parent's child slots).
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import kernel

# process kinds
ELASTIC = 0
EXCITATION = 1
IONIZATION = 2
ATTACHMENT = 3

# angular models
ISOTROPIC = 0
SCREENED_COULOMB = 1

# energy sharing in ionization
SHARE_EQUAL = 0
SHARE_UNIFORM = 1

# field vector layout (float64, 13): acceleration, Omega = (q/m) B,
# derived: parallel acceleration, E x B drift, unit vector of Omega, omega
A_VEC = 0
OMEGA = 3

# columns of the per-particle tallies: one per process, then these
NULL_COLUMN_OFFSET = 0  # tallies[i, P]: null collisions
TIME_COLUMN_OFFSET = 1  # tallies[i, P + 1]: particle time alive in the step
BOUND_COLUMN_OFFSET = 2  # tallies[i, P + 2]: trials where the true rate exceeded the bound (checked runs)
EXTRA_COLUMNS = 3

# a flight window lasts WINDOW_COLLISIONS / (trial frequency of the previous window): longer windows mean
# fewer window updates but a looser bound (more null trials); 1.3 is the fastest on Reid's ramp at 1-12 Td
WINDOW_COLLISIONS = 1.3
# ... and at most the time in which |a| t reaches WINDOW_GROWTH times the speed (or 16 speed bins): in a strong
# field, a long window would reach speeds where the bound is far above the rate along most of the window
WINDOW_GROWTH = 0.5

_SM1 = np.uint64(0x9E3779B97F4A7C15)
_SM2 = np.uint64(0xBF58476D1CE4E5B9)
_SM3 = np.uint64(0x94D049BB133111EB)
_TWO_M53 = 1.0 / 9007199254740992.0


# ------------------------------------------------------------------ random numbers


@kernel
def _rotl(x, k):
    return (x << np.uint64(k)) | (x >> np.uint64(64 - k))


@kernel
def next_u64(state):
    """xoshiro256+ step on a length-4 uint64 state (Blackman & Vigna 2018)."""
    result = state[0] + state[3]
    t = state[1] << np.uint64(17)
    state[2] ^= state[0]
    state[3] ^= state[1]
    state[1] ^= state[2]
    state[0] ^= state[3]
    state[2] ^= t
    state[3] = _rotl(state[3], 45)
    return result


@kernel
def uniform(state):
    """A double in the open interval (0, 1) (never 0: safe for log)."""
    return (float(next_u64(state) >> np.uint64(11)) + 0.5) * _TWO_M53


@kernel
def _splitmix(x):
    x = x + _SM1
    z = x
    z = (z ^ (z >> np.uint64(30))) * _SM2
    z = (z ^ (z >> np.uint64(27))) * _SM3
    return x, z ^ (z >> np.uint64(31))


@kernel
def seed_state(seed, out):
    """Fill a length-4 xoshiro state from one uint64 seed with splitmix64."""
    x = seed
    for k in range(4):
        x, z = _splitmix(x)
        out[k] = z


@kernel
def normal_pair(state):
    """Two independent standard normal numbers (Marsaglia's polar method: no trigonometry)."""
    while True:
        u1 = 2.0 * uniform(state) - 1.0
        u2 = 2.0 * uniform(state) - 1.0
        s = u1 * u1 + u2 * u2
        if s < 1.0:
            f = math.sqrt(-2.0 * math.log(s) / s)
            return u1 * f, u2 * f


# ------------------------------------------------------------------ free flight


@kernel
def derived_field(acceleration, omega_vector):
    """Field record: a, Omega, a_parallel, E x B drift, unit Omega, |Omega|."""
    field = np.zeros(13)
    field[0:3] = acceleration
    field[3:6] = omega_vector
    w = math.sqrt(omega_vector[0] ** 2 + omega_vector[1] ** 2 + omega_vector[2] ** 2)
    field[12] = w
    if w > 0.0:
        b = omega_vector / w
        a_par = (acceleration[0] * b[0] + acceleration[1] * b[1] + acceleration[2] * b[2]) * b
        a_perp = acceleration - a_par
        field[6:9] = a_par
        # drift u = (a_perp x Omega) / omega^2 makes a_perp + u x Omega vanish
        field[9] = (a_perp[1] * omega_vector[2] - a_perp[2] * omega_vector[1]) / w**2
        field[10] = (a_perp[2] * omega_vector[0] - a_perp[0] * omega_vector[2]) / w**2
        field[11] = (a_perp[0] * omega_vector[1] - a_perp[1] * omega_vector[0]) / w**2
        # store the unit vector in place of Omega (Omega = w * b)
        field[3:6] = b
    return field


@kernel
def _flown_velocity(vx, vy, vz, dt, field):
    """Velocity after a free flight of ``dt`` from (vx, vy, vz) (the same arithmetic as :func:`fly`)."""
    w = field[12]
    if w == 0.0:
        return vx + field[0] * dt, vy + field[1] * dt, vz + field[2] * dt
    bx, by, bz = field[3], field[4], field[5]
    vb = vx * bx + vy * by + vz * bz
    wx = vx - vb * bx - field[9]
    wy = vy - vb * by - field[10]
    wz = vz - vb * bz - field[11]
    cx = wy * bz - wz * by
    cy = wz * bx - wx * bz
    cz = wx * by - wy * bx
    c = math.cos(w * dt)
    s = math.sin(w * dt)
    return (vb * bx + field[6] * dt + field[9] + wx * c + cx * s,
            vb * by + field[7] * dt + field[10] + wy * c + cy * s,
            vb * bz + field[8] * dt + field[11] + wz * c + cz * s)


@kernel
def _flown_position(x, y, z, vx, vy, vz, dt, field):
    """Position after a free flight of ``dt`` (the same arithmetic as :func:`fly`)."""
    w = field[12]
    if w == 0.0:
        half = 0.5 * dt * dt
        return x + vx * dt + field[0] * half, y + vy * dt + field[1] * half, z + vz * dt + field[2] * half
    bx, by, bz = field[3], field[4], field[5]
    vb = vx * bx + vy * by + vz * bz
    wx = vx - vb * bx - field[9]
    wy = vy - vb * by - field[10]
    wz = vz - vb * bz - field[11]
    cx = wy * bz - wz * by
    cy = wz * bx - wx * bz
    cz = wx * by - wy * bx
    s = math.sin(w * dt)
    one_minus_c = 2.0 * math.sin(0.5 * w * dt) ** 2
    return (x + (vb * bx + field[9]) * dt + 0.5 * field[6] * dt * dt + (wx * s + cx * one_minus_c) / w,
            y + (vb * by + field[10]) * dt + 0.5 * field[7] * dt * dt + (wy * s + cy * one_minus_c) / w,
            z + (vb * bz + field[11]) * dt + 0.5 * field[8] * dt * dt + (wz * s + cz * one_minus_c) / w)


@kernel
def fly(pos, vel, dt, field):
    """Exact free flight for a time ``dt`` in place (uniform a, uniform Omega)."""
    x, y, z = _flown_position(pos[0], pos[1], pos[2], vel[0], vel[1], vel[2], dt, field)
    vx, vy, vz = _flown_velocity(vel[0], vel[1], vel[2], dt, field)
    pos[0], pos[1], pos[2] = x, y, z
    vel[0], vel[1], vel[2] = vx, vy, vz


@kernel
def flight_envelope(vx, vy, vz, field):
    """Constants of a flight's speed bound in a magnetic field: (v . b, |u| + |w|, a . b).

    The exact motion (:func:`fly`) is v(t) = (v.b + (a.b) t) b + u + w(t),
    with the E x B drift u and the gyrating part w(t) both perpendicular to
    b = Omega/|Omega| and |w(t)| = |w(0)|, so
    |v(t)|^2 <= (v.b + (a.b) t)^2 + (|u| + |w|)^2. Zeros without B.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport import derived_field, flight_envelope
    >>> field = derived_field(np.array([0.0, 0.0, 1.0]), np.array([0.0, 2.0, 0.0]))
    >>> [float(round(value, 12)) for value in flight_envelope(0.0, 3.0, 0.0, field)]  # drift speed 0.5
    [3.0, 1.0, 0.0]
    """
    if field[12] == 0.0:
        return 0.0, 0.0, 0.0
    return _envelope(vx, vy, vz, field[3], field[4], field[5], field[9], field[10], field[11],
                     field[6] * field[3] + field[7] * field[4] + field[8] * field[5])


@kernel
def _envelope(vx, vy, vz, bx, by, bz, ux, uy, uz, a_par):
    """:func:`flight_envelope` from scalars (unit b, drift u, a . b): no array, so no reference counting."""
    vb = vx * bx + vy * by + vz * bz
    wx = vx - vb * bx - ux
    wy = vy - vb * by - uy
    wz = vz - vb * bz - uz
    return vb, math.sqrt(ux * ux + uy * uy + uz * uz) + math.sqrt(wx * wx + wy * wy + wz * wz), a_par


@kernel
def window_top_speed(vx, vy, vz, ax, ay, az, t, exact, vb, radius, a_par):
    """A convex-in-time bound f(t) of the speed at flight time ``t`` (see :func:`window_bound_speed`).

    Without B it is |v + a t| itself, from the components (the arithmetic
    of the flown velocity, free of the cancellation of |v|^2 + 2 a.v t +
    a^2 t^2 near a stop). With B it is sqrt((v.b + a_par t)^2 + radius^2)
    (:func:`flight_envelope`), padded by 1e-10 against the rounding of the
    gyration formula.
    """
    if exact:
        x = vx + ax * t
        y = vy + ay * t
        z = vz + az * t
        return math.sqrt(x * x + y * y + z * z)
    along = vb + a_par * t
    return math.sqrt(along * along + radius * radius) * (1.0 + 1e-10)


@kernel
def window_growth_speed(speed0, accel_mag, t, exact, radius):
    """The bound |v| + |a| t of the speed at flight time ``t`` in a magnetic field (inf without one).

    d|v|/dt = a . v/|v| <= |a|: the magnetic force does no work. Padded by
    1e-10 of the speeds involved against the rounding of the gyration formula.
    """
    if exact:
        return math.inf
    return (speed0 + accel_mag * t + radius) * (1.0 + 1e-10) - radius


@kernel
def window_bound_speed(vel, field, t1, t2):
    """Largest speed a particle starting with ``vel`` can have at times in [t1, t2] of a free flight.

    Without a magnetic field the speed is |v + a t|, whose square is convex
    in t: the maximum is at an end of the window (exact). With one, the
    smaller of two bounds: the convex bound of :func:`window_top_speed` at
    the ends of the window, and |v| + |a| t2 (:func:`window_growth_speed`).

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport import derived_field, window_bound_speed
    >>> field = derived_field(np.array([0.0, 0.0, -2.0]), np.zeros(3))
    >>> float(window_bound_speed(np.array([0.0, 0.0, 3.0]), field, 0.5, 1.0))  # |3 - 2 t| on [0.5, 1]
    2.0
    """
    speed0 = math.sqrt(vel[0] ** 2 + vel[1] ** 2 + vel[2] ** 2)
    accel_mag = math.sqrt(field[0] ** 2 + field[1] ** 2 + field[2] ** 2)
    exact = field[12] == 0.0
    vb, radius, a_par = flight_envelope(vel[0], vel[1], vel[2], field)
    s1 = window_top_speed(vel[0], vel[1], vel[2], field[0], field[1], field[2], t1, exact, vb, radius, a_par)
    s2 = window_top_speed(vel[0], vel[1], vel[2], field[0], field[1], field[2], t2, exact, vb, radius, a_par)
    return min(max(s1, s2), window_growth_speed(speed0, accel_mag, t2, exact, radius))


# ------------------------------------------------------------------ cross sections


@kernel
def node_index(energy, nodes, accelerator, accelerator_step):
    """Index i of the node interval [nodes[i], nodes[i+1]) holding ``energy``.

    -1 below the first node, len(nodes) - 1 at or above the last one.
    """
    if energy < nodes[0]:
        return -1
    cell = int(energy / accelerator_step)
    last = nodes.shape[0] - 1
    if cell >= accelerator.shape[0]:
        return last
    i = accelerator[cell]
    while i < last and nodes[i + 1] <= energy:
        i += 1
    return i


@kernel
def _node_index_fast(energy, nodes, accelerator, inverse_cell):
    """:func:`node_index` with a multiplication: ``inverse_cell`` is 1/accelerator_step rounded down by 1e-12.

    The cell is then never above int(energy / accelerator_step), and the
    search upwards from the cell's first interval stays exact.
    """
    if energy < nodes[0]:
        return -1
    x = energy * inverse_cell
    last = nodes.shape[0] - 1
    if x >= accelerator.shape[0]:
        return last
    i = accelerator[int(x)]
    while i < last and nodes[i + 1] <= energy:
        i += 1
    return i


@kernel
def cross_section(j, energy, i, nodes, sigma):
    """Linear interpolation of process ``j`` in node interval ``i``; constant outside."""
    if i < 0:
        return sigma[0, j]
    if i >= nodes.shape[0] - 1:
        return sigma[nodes.shape[0] - 1, j]
    w = (energy - nodes[i]) / (nodes[i + 1] - nodes[i])
    return sigma[i, j] + w * (sigma[i + 1, j] - sigma[i, j])


@kernel
def rate_bound(species, speed, bound, bound_step, sigma_max, const_rate):
    """Upper bound of sum_j sigma_j g + k_j of a species for relative speeds <= ``speed``."""
    k = int(speed / bound_step)
    if k < bound.shape[1]:
        return bound[species, k]
    return max(bound[species, bound.shape[1] - 1], sigma_max[species] * speed + const_rate[species])


@kernel
def _bound_fast(species, speed, bound, inverse_step, sigma_max, const_rate):
    """:func:`rate_bound` with a multiplication: ``inverse_step`` is 1/bound_step rounded up by 1e-12.

    The bin index is then never below int(speed / bound_step); a higher bin of
    the running maximum is a larger, still valid bound.
    """
    x = speed * inverse_step
    if x < bound.shape[1]:
        return bound[species, int(x)]
    return max(bound[species, bound.shape[1] - 1], sigma_max[species] * speed + const_rate[species])


@kernel
def _trial_frequencies(speed, density, gas, bound, inverse_step, sigma_max, const_max, nu_s):
    """Trial frequency per species (in ``nu_s``) and their sum for projectile speeds <= ``speed``."""
    total = 0.0
    for s in range(gas.shape[0]):
        nu = density * _bound_fast(s, speed + gas[s, 2], bound, inverse_step, sigma_max, const_max)
        nu_s[s] = nu
        total += nu
    return total


# ------------------------------------------------------------------ scattering


@kernel
def scattering_cosine(model, energy, screening, state):
    """cos(chi) in the centre-of-mass frame.

    Isotropic: uniform in [-1, 1]. Screened Coulomb (Wentzel): density
    proportional to (1 + 2 eta - cos chi)^-2 with eta = screening / (4 energy),
    sampled by inversion: cos chi = 1 + 2 eta - 2 eta (1 + eta) / (eta + U).
    """
    u = uniform(state)
    if model == ISOTROPIC or energy <= 0.0:
        return 2.0 * u - 1.0
    eta = screening / (4.0 * energy)
    c = 1.0 + 2.0 * eta - 2.0 * eta * (1.0 + eta) / (eta + u)
    return min(1.0, max(-1.0, c))


@kernel
def _rotated(ux, uy, uz, cos_chi, phi):
    """Unit vector at angle chi from the unit vector u, azimuth ``phi`` (a tuple)."""
    sin_chi = math.sqrt(max(0.0, 1.0 - cos_chi * cos_chi))
    cp = math.cos(phi)
    sp = math.sin(phi)
    if abs(uz) > 0.99999999:
        return sin_chi * cp, sin_chi * sp, cos_chi * (1.0 if uz > 0 else -1.0)
    t = math.sqrt(1.0 - uz * uz)
    return (sin_chi * (ux * uz * cp - uy * sp) / t + ux * cos_chi,
            sin_chi * (uy * uz * cp + ux * sp) / t + uy * cos_chi,
            -sin_chi * cp * t + uz * cos_chi)


@kernel
def rotate(direction, cos_chi, phi, out):
    """Unit vector at angle chi from unit ``direction``, azimuth ``phi``."""
    out[0], out[1], out[2] = _rotated(direction[0], direction[1], direction[2], cos_chi, phi)


@kernel
def _isotropic(state):
    """A uniformly distributed unit vector (Marsaglia 1972: no trigonometry), as a tuple."""
    while True:
        u1 = 2.0 * uniform(state) - 1.0
        u2 = 2.0 * uniform(state) - 1.0
        s = u1 * u1 + u2 * u2
        if s < 1.0:
            f = 2.0 * math.sqrt(1.0 - s)
            return u1 * f, u2 * f, 1.0 - 2.0 * s


@kernel
def isotropic_direction(state, out):
    """A uniformly distributed unit vector."""
    out[0], out[1], out[2] = _isotropic(state)


@kernel
def _scattered(model, energy, screening, gx, gy, gz, g_speed, state):
    """Direction of the relative velocity g after scattering (isotropic: g is not needed)."""
    if model == ISOTROPIC:
        return _isotropic(state)
    cos_chi = scattering_cosine(model, energy, screening, state)
    return _rotated(gx / g_speed, gy / g_speed, gz / g_speed, cos_chi, 2.0 * math.pi * uniform(state))


# ------------------------------------------------------------------ the swarm step
#
# The helpers below take scalars (and the random state) and return tuples:
# a numba function that is not inlined increments and decrements the
# reference count of every array it receives, which costs more than a
# collision when the argument list is long.


@kernel
def _two_body(vx, vy, vz, gas_vx, gas_vy, gas_vz, gx, gy, gz, g_speed, energy, mass, target_mass, loss, model,
              screening, state):
    """Projectile velocity after an elastic (``loss`` = 0) or inelastic two-body collision.

    The relative kinetic energy drops by ``loss`` (the threshold), the
    relative velocity turns in the centre-of-mass frame and the
    centre-of-mass velocity is kept (exact recoil).
    """
    total = mass + target_mass
    g_after = g_speed
    if loss > 0.0:
        mu = mass * target_mass / total
        g_after = math.sqrt(2.0 * max(0.0, 0.5 * mu * g_speed * g_speed - loss) / mu)
    nx, ny, nz = _scattered(model, energy, screening, gx, gy, gz, g_speed, state)
    light = mass / total
    heavy = target_mass / total
    share = heavy * g_after
    return (light * vx + heavy * gas_vx + share * nx,
            light * vy + heavy * gas_vy + share * ny,
            light * vz + heavy * gas_vz + share * nz)


@kernel
def _ionized(gas_vx, gas_vy, gas_vz, gx, gy, gz, g_speed, energy, mass, loss, sharing, model, screening, state):
    """Velocities of the scattered and the new electron after an ionizing collision (a 6-tuple).

    The energy left above the threshold ``loss`` is shared equally or
    uniformly; the scattered electron follows the angular model, the new
    one leaves isotropically, both from the target's frame.
    """
    available = energy - loss
    share = 0.5 if sharing == SHARE_EQUAL else uniform(state)
    e1 = max(0.0, share * available)
    e2 = max(0.0, available - e1)
    nx, ny, nz = _scattered(model, energy, screening, gx, gy, gz, g_speed, state)
    u1 = math.sqrt(2.0 * e1 / mass)
    cx, cy, cz = _isotropic(state)
    u2 = math.sqrt(2.0 * e2 / mass)
    return (gas_vx + u1 * nx, gas_vy + u1 * ny, gas_vz + u1 * nz,
            gas_vx + u2 * cx, gas_vy + u2 * cy, gas_vz + u2 * cz)


@kernel
def _collide(j, vel, gas_v, g, g_speed, energy, mass, target_mass, kind, threshold, angular, screening,
             sharing, state, child_vel, scratch):
    """Apply process ``j`` to ``vel`` in place; return 0 (alive), 1 (attached) or 2 (ionized: child_vel set).

    The array form of what :func:`advance_swarm` does inline; ``scratch`` is unused.
    """
    if kind[j] == ATTACHMENT:
        return 1
    if kind[j] == IONIZATION:
        v1x, v1y, v1z, v2x, v2y, v2z = _ionized(gas_v[0], gas_v[1], gas_v[2], g[0], g[1], g[2], g_speed, energy,
                                                mass, threshold[j], sharing, angular[j], screening[j], state)
        vel[0], vel[1], vel[2] = v1x, v1y, v1z
        child_vel[0], child_vel[1], child_vel[2] = v2x, v2y, v2z
        return 2
    loss = threshold[j] if kind[j] == EXCITATION else 0.0
    vel[0], vel[1], vel[2] = _two_body(vel[0], vel[1], vel[2], gas_v[0], gas_v[1], gas_v[2], g[0], g[1], g[2],
                                       g_speed, energy, mass, target_mass, loss, angular[j], screening[j], state)
    return 0


@kernel
def advance_swarm(lo, hi, pos, vel, states, alive, t_start, t_end, field, mass, density, gas, kind, species_of,
                  threshold, const_rate, angular, screening, sharing, nodes, sigma, accelerator, accelerator_step,
                  bound, bound_step, sigma_max, const_max, tallies, child_pos, child_vel, child_state, child_alive,
                  child_count, check=False, window=WINDOW_COLLISIONS, growth=WINDOW_GROWTH):
    """Advance particles lo..hi-1 (and their descendants) from t_start to t_end.

    ``tallies[i]`` receives the collisions per process, the null collisions,
    the particle time of particle i and its children and (with ``check``)
    the trials at which the true collision rate exceeded the trial bound
    (never, if the method is exact); children are stored in ``child_*[i]``
    (``child_count[i]`` of them, more than the slots means overflow and the
    step must be repeated with more slots).

    A flight runs from one real collision to the next. Trial collisions
    along it form a Poisson process whose rate is piecewise constant over
    windows of the flight (each ``window`` / its previous rate long): in a
    window, the table bound at the largest speed the particle can reach in
    it (:func:`window_bound_speed`). An exponential optical depth is drawn
    per trial and used up window after window (the integrated hazard of a
    piecewise-constant rate: exact). A null trial leaves the flight as it
    is: particles move only at real collisions and at ``t_end``.

    The particle loop is written out in this one function: a numba call
    that is not inlined costs two atomic reference-count operations per
    array argument.
    """
    n_species = gas.shape[0]
    n_proc = kind.shape[0]
    null_column = n_proc + NULL_COLUMN_OFFSET
    time_column = n_proc + TIME_COLUMN_OFFSET
    bound_column = n_proc + BOUND_COLUMN_OFFSET
    accel_mag = math.sqrt(field[0] ** 2 + field[1] ** 2 + field[2] ** 2)
    ax, ay, az = field[0], field[1], field[2]
    exact = field[12] == 0.0
    bx, by, bz, ux, uy, uz = field[3], field[4], field[5], field[9], field[10], field[11]
    a_par_field = field[6] * bx + field[7] * by + field[8] * bz
    inverse_step = (1.0 / bound_step) * (1.0 + 1e-12)
    inverse_cell = (1.0 / accelerator_step) * (1.0 - 1e-12)
    fallback = 0.01 * bound.shape[1] * bound_step / accel_mag if accel_mag > 0.0 else math.inf
    speed_floor = 16.0 * bound_step
    last_node = nodes.shape[0] - 1
    slots = child_pos.shape[1]
    child_time = np.empty(slots)
    rng = np.empty(4, np.uint64)
    nu_s = np.empty(n_species)
    for i in range(lo, hi):
        if not alive[i]:
            continue
        n_children = 0
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
            survives = True
            speed0 = math.sqrt(vx * vx + vy * vy + vz * vz)
            nu_window = _trial_frequencies(speed0, density, gas, bound, inverse_step, sigma_max, const_max, nu_s)
            while True:  # one flight, from the last real collision
                speed0 = math.sqrt(vx * vx + vy * vy + vz * vz)
                vb, radius, a_par = 0.0, 0.0, 0.0
                if not exact:
                    vb, radius, a_par = _envelope(vx, vy, vz, bx, by, bz, ux, uy, uz, a_par_field)
                horizon = t_end - t
                elapsed = 0.0  # flight time so far
                window_end = 0.0
                s_low = speed0 if exact else window_top_speed(vx, vy, vz, ax, ay, az, 0.0, exact, vb, radius, a_par)
                tau = -math.log(uniform(rng))
                landed = False  # reached t_end without a real collision
                while True:  # windows and trials of this flight
                    if elapsed >= window_end:  # open the next window
                        if accel_mag > 0.0:
                            h = window / nu_window if nu_window > 0.0 else fallback
                            h = min(h, growth * max(s_low, speed_floor) / accel_mag)
                            s_high = window_top_speed(vx, vy, vz, ax, ay, az, window_end + h, exact, vb, radius,
                                                      a_par)
                            s_window = min(max(s_low, s_high),
                                           window_growth_speed(speed0, accel_mag, window_end + h, exact, radius))
                            nu_window = _trial_frequencies(s_window, density, gas, bound, inverse_step, sigma_max,
                                                           const_max, nu_s)
                            s_low = s_high
                            window_end += h
                        else:
                            nu_window = _trial_frequencies(speed0, density, gas, bound, inverse_step, sigma_max,
                                                           const_max, nu_s)
                            window_end = math.inf
                    stop = min(window_end, horizon)
                    room = nu_window * (stop - elapsed)
                    if tau >= room:
                        if stop >= horizon:
                            landed = True
                            break
                        tau -= room
                        elapsed = window_end
                        continue
                    elapsed = min(stop, elapsed + tau / nu_window)
                    # a trial: the velocity it would have, the target species by its share of the trial frequency
                    if exact:
                        tvx, tvy, tvz = vx + ax * elapsed, vy + ay * elapsed, vz + az * elapsed
                    else:
                        tvx, tvy, tvz = _flown_velocity(vx, vy, vz, elapsed, field)
                    r = uniform(rng) * nu_window
                    s = 0
                    while s < n_species - 1 and r >= nu_s[s]:
                        r -= nu_s[s]
                        s += 1
                    gas_vx = gas_vy = gas_vz = 0.0
                    if gas[s, 1] > 0.0:
                        gas_vx, gas_vy = normal_pair(rng)
                        gas_vz, _ = normal_pair(rng)
                        gas_vx *= gas[s, 1]
                        gas_vy *= gas[s, 1]
                        gas_vz *= gas[s, 1]
                    gx, gy, gz = tvx - gas_vx, tvy - gas_vy, tvz - gas_vz
                    g_speed = math.sqrt(gx * gx + gy * gy + gz * gz)
                    energy = 0.5 * mass * g_speed * g_speed
                    # linear interpolation in node interval `node` (one division for all processes)
                    node = _node_index_fast(energy, nodes, accelerator, inverse_cell)
                    if node < 0:
                        node, w = 0, 0.0
                    elif node >= last_node:
                        node, w = last_node - 1, 1.0
                    else:
                        w = (energy - nodes[node]) / (nodes[node + 1] - nodes[node])
                    chosen = -1
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
                if exact:
                    half = 0.5 * elapsed * elapsed
                    x, y, z = x + vx * elapsed + ax * half, y + vy * elapsed + ay * half, z + vz * elapsed + az * half
                else:
                    x, y, z = _flown_position(x, y, z, vx, vy, vz, elapsed, field)
                if landed:
                    if exact:
                        vx, vy, vz = vx + ax * elapsed, vy + ay * elapsed, vz + az * elapsed
                    else:
                        vx, vy, vz = _flown_velocity(vx, vy, vz, elapsed, field)
                    t = t_end
                    break
                # a real collision, where the particle now is
                vx, vy, vz = tvx, tvy, tvz
                t += elapsed
                tallies[i, chosen] += 1.0
                process = kind[chosen]
                if process == ELASTIC or process == EXCITATION:
                    loss = threshold[chosen] if process == EXCITATION else 0.0
                    vx, vy, vz = _two_body(vx, vy, vz, gas_vx, gas_vy, gas_vz, gx, gy, gz, g_speed, energy, mass,
                                           gas[s, 0], loss, angular[chosen], screening[chosen], rng)
                elif process == ATTACHMENT:
                    survives = False
                    break
                else:
                    v1x, v1y, v1z, v2x, v2y, v2z = _ionized(gas_vx, gas_vy, gas_vz, gx, gy, gz, g_speed, energy,
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


@kernel
def group_moments(pos, vel, alive, group, n_groups, mass, moments):
    """Add per-group sums of 1, r, r^2, v, energy, r_k v_k (14 columns) to ``moments``."""
    for i in range(pos.shape[0]):
        if not alive[i]:
            continue
        row = moments[group[i]]
        row[0] += 1.0
        v2 = 0.0
        for k in range(3):
            row[1 + k] += pos[i, k]
            row[4 + k] += pos[i, k] * pos[i, k]
            row[7 + k] += vel[i, k]
            row[11 + k] += pos[i, k] * vel[i, k]
            v2 += vel[i, k] * vel[i, k]
        row[10] += 0.5 * mass * v2


@kernel
def energy_histogram(vel, alive, mass, edges_step, counts):
    """Add the particles' kinetic energies (1/2 m v^2, J) to a uniform histogram of bin width ``edges_step`` (J).

    ``counts`` holds the bins and one slot more: energies beyond the last
    bin are counted there (an overflow count, not a bin of width
    ``edges_step``).
    """
    last = counts.shape[0] - 1
    for i in range(vel.shape[0]):
        if alive[i]:
            e = 0.5 * mass * (vel[i, 0] ** 2 + vel[i, 1] ** 2 + vel[i, 2] ** 2)
            counts[min(last, int(e / edges_step))] += 1.0


@kernel
def group_sums(values, group, n_groups):
    """Per-group column sums of a 2D array."""
    out = np.zeros((n_groups, values.shape[1]))
    for i in range(values.shape[0]):
        for k in range(values.shape[1]):
            out[group[i], k] += values[i, k]
    return out


# ------------------------------------------------------------------ the slab


@kernel
def slab_batch(state, count, thickness, albedo, isotropic_incidence, rod, mass_ratio, angle_bins, energy_bins,
               out_counts, angle_hist, energy_hist):
    """Histories of ``count`` particles through a slab 0 <= x <= thickness (unit mean free path).

    Free paths s = -ln(xi) (Krasov, sec. 5.5); at a collision the particle
    is absorbed with probability 1 - albedo, else scattered isotropically in
    the centre-of-mass frame of a target of ``mass_ratio`` = M/m (inf: no
    energy loss, isotropic in the lab) or, for the rod model, forward or
    backward with probability 1/2. Energies are in units of the incident
    energy. ``out_counts`` += (transmitted, reflected, absorbed, collisions).
    """
    for _ in range(count):
        if rod:
            mu = 1.0
        elif isotropic_incidence:
            mu = math.sqrt(uniform(state))  # isotropic flux: current density 2 mu
        else:
            mu = 1.0
        x = 0.0
        energy = 1.0
        while True:
            x += mu * -math.log(uniform(state))
            if x >= thickness:
                out_counts[0] += 1.0
                angle_hist[0, min(angle_bins - 1, int(mu * angle_bins))] += 1.0
                energy_hist[0, min(energy_bins - 1, int(energy * energy_bins))] += 1.0
                break
            if x < 0.0:
                out_counts[1] += 1.0
                angle_hist[1, min(angle_bins - 1, int(-mu * angle_bins))] += 1.0
                energy_hist[1, min(energy_bins - 1, int(energy * energy_bins))] += 1.0
                break
            out_counts[3] += 1.0
            if uniform(state) >= albedo:
                out_counts[2] += 1.0
                break
            if rod:
                mu = 1.0 if uniform(state) < 0.5 else -1.0
            elif math.isinf(mass_ratio):
                mu = 2.0 * uniform(state) - 1.0
            else:
                mu, energy = _elastic_lab(mu, energy, mass_ratio, state)


@kernel
def _elastic_lab(mu, energy, a, state):
    """Direction cosine and energy after isotropic CM scattering off a target of mass a (units of m)."""
    c = 2.0 * uniform(state) - 1.0
    factor = math.sqrt(a * a + 2.0 * a * c + 1.0)
    cos_lab = (1.0 + a * c) / factor if factor > 0.0 else 1.0  # a = 1, c = -1: stopped dead (energy 0)
    new_energy = energy * (a * a + 2.0 * a * c + 1.0) / (a + 1.0) ** 2
    phi = 2.0 * math.pi * uniform(state)
    sin_lab = math.sqrt(max(0.0, 1.0 - cos_lab * cos_lab))
    new_mu = mu * cos_lab + math.sqrt(max(0.0, 1.0 - mu * mu)) * sin_lab * math.cos(phi)
    return min(1.0, max(-1.0, new_mu)), new_energy
