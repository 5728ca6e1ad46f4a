"""Numba kernels of the Monte Carlo transport engine (swarms and slabs).

Algorithm (Krasov, sec. 5.5, extended as in Skullerud, J. Phys. D 1, 1567
(1968) and Lin & Bardsley, J. Chem. Phys. 66, 435 (1977)):

* every particle carries its own random stream (xoshiro256+, state of four
  uint64 words); a kernel call advances particles ``lo..hi`` independently,
  so the result does not depend on how particles are split over threads;
* free flight is exact: constant acceleration, or gyration about B plus the
  E x B drift (the closed-form solution of dv/dt = a + v x Omega);
* collisions by the null-collision method with an exact, speed-dependent
  trial frequency: within a window ``Tw`` the speed cannot exceed
  ``|v| + |a| Tw``, and the trial frequency is the table bound ``B(v)`` of
  ``sum_j N sigma_j(eps) g`` over all speeds up to that value (plus the
  largest gas speed that can occur). A trial time beyond the window only
  moves the particle (exponential times are memoryless);
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
EXTRA_COLUMNS = 2

# a trial window is WINDOW_COLLISIONS / (trial frequency at the current speed)
WINDOW_COLLISIONS = 0.7

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
    """Two independent standard normal numbers (Box-Muller)."""
    r = math.sqrt(-2.0 * math.log(uniform(state)))
    phi = 2.0 * math.pi * uniform(state)
    return r * math.cos(phi), r * math.sin(phi)


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
def fly(pos, vel, dt, field):
    """Exact free flight for a time ``dt`` in place (uniform a, uniform Omega)."""
    w = field[12]
    if w == 0.0:
        for k in range(3):
            pos[k] += vel[k] * dt + 0.5 * field[k] * dt * dt
            vel[k] += field[k] * dt
        return
    bx, by, bz = field[3], field[4], field[5]
    vb = vel[0] * bx + vel[1] * by + vel[2] * bz
    # gyrating part w = v - v_par - u_drift, rotated: w c + (w x b) s
    wx = vel[0] - vb * bx - field[9]
    wy = vel[1] - vb * by - field[10]
    wz = vel[2] - vb * bz - field[11]
    cx = wy * bz - wz * by
    cy = wz * bx - wx * bz
    cz = wx * by - wy * bx
    c = math.cos(w * dt)
    s = math.sin(w * dt)
    one_minus_c = 2.0 * math.sin(0.5 * w * dt) ** 2
    pos[0] += (vb * bx + field[9]) * dt + 0.5 * field[6] * dt * dt + (wx * s + cx * one_minus_c) / w
    pos[1] += (vb * by + field[10]) * dt + 0.5 * field[7] * dt * dt + (wy * s + cy * one_minus_c) / w
    pos[2] += (vb * bz + field[11]) * dt + 0.5 * field[8] * dt * dt + (wz * s + cz * one_minus_c) / w
    vel[0] = vb * bx + field[6] * dt + field[9] + wx * c + cx * s
    vel[1] = vb * by + field[7] * dt + field[10] + wy * c + cy * s
    vel[2] = vb * bz + field[8] * dt + field[11] + wz * c + cz * s


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
def rotate(direction, cos_chi, phi, out):
    """Unit vector at angle chi from unit ``direction``, azimuth ``phi``."""
    sin_chi = math.sqrt(max(0.0, 1.0 - cos_chi * cos_chi))
    ux, uy, uz = direction[0], direction[1], direction[2]
    cp = math.cos(phi)
    sp = math.sin(phi)
    if abs(uz) > 0.99999999:
        out[0] = sin_chi * cp
        out[1] = sin_chi * sp
        out[2] = cos_chi * (1.0 if uz > 0 else -1.0)
        return
    t = math.sqrt(1.0 - uz * uz)
    out[0] = sin_chi * (ux * uz * cp - uy * sp) / t + ux * cos_chi
    out[1] = sin_chi * (uy * uz * cp + ux * sp) / t + uy * cos_chi
    out[2] = -sin_chi * cp * t + uz * cos_chi


@kernel
def isotropic_direction(state, out):
    """A uniformly distributed unit vector."""
    c = 2.0 * uniform(state) - 1.0
    s = math.sqrt(max(0.0, 1.0 - c * c))
    phi = 2.0 * math.pi * uniform(state)
    out[0] = s * math.cos(phi)
    out[1] = s * math.sin(phi)
    out[2] = c


# ------------------------------------------------------------------ the swarm step


@kernel
def _collide(j, vel, gas_v, g, g_speed, energy, mass, target_mass, kind, threshold, angular, screening,
             sharing, state, child_vel, scratch):
    """Apply process ``j`` to ``vel`` in place; return 0 (alive), 1 (attached) or 2 (ionized: child_vel set)."""
    if kind[j] == ATTACHMENT:
        return 1
    gx, gy, gz = g[0] / g_speed, g[1] / g_speed, g[2] / g_speed
    scratch[0], scratch[1], scratch[2] = gx, gy, gz
    direction = scratch[0:3]
    new_dir = scratch[3:6]
    if kind[j] == IONIZATION:
        available = energy - threshold[j]
        share = 0.5 if sharing == SHARE_EQUAL else uniform(state)
        e1 = max(0.0, share * available)
        e2 = max(0.0, available - e1)
        cos_chi = scattering_cosine(angular[j], energy, screening[j], state)
        rotate(direction, cos_chi, 2.0 * math.pi * uniform(state), new_dir)
        u1 = math.sqrt(2.0 * e1 / mass)
        isotropic_direction(state, scratch[6:9])
        u2 = math.sqrt(2.0 * e2 / mass)
        for k in range(3):
            vel[k] = gas_v[k] + u1 * new_dir[k]
            child_vel[k] = gas_v[k] + u2 * scratch[6 + k]
        return 2
    mu = mass * target_mass / (mass + target_mass)
    relative_energy = 0.5 * mu * g_speed * g_speed
    if kind[j] == EXCITATION:
        relative_energy = max(0.0, relative_energy - threshold[j])
    g_after = math.sqrt(2.0 * relative_energy / mu)
    cos_chi = scattering_cosine(angular[j], energy, screening[j], state)
    rotate(direction, cos_chi, 2.0 * math.pi * uniform(state), new_dir)
    share = target_mass / (mass + target_mass)
    for k in range(3):
        centre = (mass * vel[k] + target_mass * gas_v[k]) / (mass + target_mass)
        vel[k] = centre + share * g_after * new_dir[k]
    return 0


@kernel
def _advance_one(pos, vel, state, t_start, t_end, field, accel_mag, mass, density, gas, kind, species_of, threshold,
                 const_rate, angular, screening, sharing, nodes, sigma, accelerator, accelerator_step, bound,
                 bound_step, sigma_max, const_max, tally, child_pos, child_vel, child_time, child_state, n_children,
                 scratch):
    """Advance one particle from t_start to t_end; return (alive, n_children)."""
    n_species = gas.shape[0]
    n_proc = kind.shape[0]
    t = t_start
    nu_s = scratch[16:16 + n_species]
    gas_v = scratch[9:12]
    g = scratch[12:15]
    while True:
        speed = math.sqrt(vel[0] ** 2 + vel[1] ** 2 + vel[2] ** 2)
        nu_here = 0.0
        for s in range(n_species):
            nu_here += density * rate_bound(s, speed + gas[s, 2], bound, bound_step, sigma_max, const_max)
        window = math.inf
        reach = speed
        if accel_mag > 0.0:
            window = WINDOW_COLLISIONS / nu_here if nu_here > 0.0 else 0.01 * bound_step * bound.shape[1] / accel_mag
            reach = speed + accel_mag * window
        nu_trial = 0.0
        for s in range(n_species):
            nu_s[s] = density * rate_bound(s, reach + gas[s, 2], bound, bound_step, sigma_max, const_max)
            nu_trial += nu_s[s]
        flight = -math.log(uniform(state)) / nu_trial if nu_trial > 0.0 else math.inf
        step = min(flight, window)
        if t + step >= t_end:
            fly(pos, vel, t_end - t, field)
            tally[n_proc + TIME_COLUMN_OFFSET] += t_end - t
            return True, n_children
        fly(pos, vel, step, field)
        tally[n_proc + TIME_COLUMN_OFFSET] += step
        t += step
        if flight > window:
            continue
        # choose the target species by its share of the trial frequency
        r = uniform(state) * nu_trial
        s = 0
        while s < n_species - 1 and r >= nu_s[s]:
            r -= nu_s[s]
            s += 1
        if gas[s, 1] > 0.0:
            gas_v[0], gas_v[1] = normal_pair(state)
            gas_v[2], _ = normal_pair(state)
            for k in range(3):
                gas_v[k] *= gas[s, 1]
        else:
            gas_v[0] = 0.0
            gas_v[1] = 0.0
            gas_v[2] = 0.0
        for k in range(3):
            g[k] = vel[k] - gas_v[k]
        g_speed = math.sqrt(g[0] ** 2 + g[1] ** 2 + g[2] ** 2)
        energy = 0.5 * mass * g_speed * g_speed
        i = node_index(energy, nodes, accelerator, accelerator_step)
        chosen = -1
        cumulative = 0.0
        for j in range(n_proc):
            if species_of[j] != s:
                continue
            rate = const_rate[j]
            if energy >= threshold[j]:
                rate += cross_section(j, energy, i, nodes, sigma) * g_speed
            cumulative += density * rate
            if r < cumulative:
                chosen = j
                break
        if chosen < 0:
            tally[n_proc + NULL_COLUMN_OFFSET] += 1.0
            continue
        tally[chosen] += 1.0
        outcome = _collide(chosen, vel, gas_v, g, g_speed, energy, mass, gas[s, 0], kind, threshold, angular,
                           screening, sharing, state, scratch[20 + n_species:23 + n_species], scratch)
        if outcome == 1:
            return False, n_children
        if outcome == 2:
            if n_children >= child_pos.shape[0]:
                return True, n_children + 1  # overflow: the caller retries with more slots
            for k in range(3):
                child_pos[n_children, k] = pos[k]
                child_vel[n_children, k] = scratch[20 + n_species + k]
            child_time[n_children] = t
            seed_state(next_u64(state), child_state[n_children])
            n_children += 1


@kernel
def advance_swarm(lo, hi, pos, vel, states, alive, t_start, t_end, field, mass, density, gas, kind, species_of,
                  threshold, const_rate, angular, screening, sharing, nodes, sigma, accelerator, accelerator_step,
                  bound, bound_step, sigma_max, const_max, tallies, child_pos, child_vel, child_state, child_alive,
                  child_count):
    """Advance particles lo..hi-1 (and their descendants) from t_start to t_end.

    ``tallies[i]`` receives the collisions per process, the null collisions
    and the particle time of particle i and its children; children are
    stored in ``child_*[i]`` (``child_count[i]`` of them, more than the slots
    means overflow and the step must be repeated with more slots).
    """
    accel_mag = math.sqrt(field[0] ** 2 + field[1] ** 2 + field[2] ** 2)
    slots = child_pos.shape[1]
    child_time = np.empty(slots)
    scratch = np.zeros(32 + gas.shape[0])
    for i in range(lo, hi):
        if not alive[i]:
            continue
        ok, n = _advance_one(pos[i], vel[i], states[i], t_start, t_end, field, accel_mag, mass, density, gas, kind,
                             species_of, threshold, const_rate, angular, screening, sharing, nodes, sigma,
                             accelerator, accelerator_step, bound, bound_step, sigma_max, const_max, tallies[i],
                             child_pos[i], child_vel[i], child_time, child_state[i], 0, scratch)
        alive[i] = ok
        c = 0
        while c < n and n <= slots:
            child_ok, n = _advance_one(child_pos[i, c], child_vel[i, c], child_state[i, c], child_time[c], t_end,
                                       field, accel_mag, mass, density, gas, kind, species_of, threshold,
                                       const_rate, angular, screening, sharing, nodes, sigma, accelerator,
                                       accelerator_step, bound, bound_step, sigma_max, const_max, tallies[i],
                                       child_pos[i], child_vel[i], child_time, child_state[i], n, scratch)
            child_alive[i, c] = child_ok
            c += 1
        child_count[i] = n


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
    """Add the particles' kinetic energies to a uniform histogram (overflow in the last bin)."""
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
    cos_lab = (1.0 + a * c) / factor
    new_energy = energy * (a * a + 2.0 * a * c + 1.0) / (a + 1.0) ** 2
    phi = 2.0 * math.pi * uniform(state)
    sin_lab = math.sqrt(max(0.0, 1.0 - cos_lab * cos_lab))
    new_mu = mu * cos_lab + math.sqrt(max(0.0, 1.0 - mu * mu)) * sin_lab * math.cos(phi)
    return min(1.0, max(-1.0, new_mu)), new_energy
