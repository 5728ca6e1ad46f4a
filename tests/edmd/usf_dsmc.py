"""An independent reference for sheared granular gases: DSMC of the Boltzmann equation's uniform shear flow.

NumPy only, nothing shared with the event-driven engine: the tests of sheared inelastic spheres and discs
compare the engine's steady state with this solution of the Boltzmann equation (exact up to its statistics)
as well as with Grad's approximate one (collisionkit.edmd.granular_shear_flow).
"""
from __future__ import annotations

import math

import numpy as np


def usf_dsmc(restitution, shear_rate, density, dim=3, particles=10_000, relax=40.0, measure=200.0, blocks=20,
             safety=0.5, thermostat=False, seed=1, start_kT=1.0):
    r"""Steady kT and shear viscosity -P_xy / a of the homogeneous uniform shear flow, by DSMC.

    The Boltzmann equation of inelastic hard spheres (d = 3) or discs (d = 2) of unit diameter and mass in
    the uniform shear flow u_x = a y is homogeneous in the peculiar velocities V, which stream as
    dV_x/dt = -a V_y between collisions (exact over a step). Collisions: each step the particles are paired
    at random (N/2 disjoint pairs, each standing for the N - 1 partners of its first particle), and a pair
    collides with probability (N - 1)/N n S_d (g.s)+ dt, s uniform on the unit sphere (S_d its area), with
    V_1,2' = V_1,2 -+ (1 + alpha)/2 (g.s) s: the collision rate of the Boltzmann equation per pair,
    n sigma^(d-1) int ds (g.s)+ (Bird's no-time-counter idea with Bernoulli trials). dt is set each step so
    that the largest possible probability is ``safety``. ``thermostat`` rescales V to kT = 1 each step.
    The start is Maxwellian at ``start_kT``. Returns (kT, error, viscosity, error) over ``measure`` collisions per particle after ``relax``.
    """
    rng = np.random.default_rng(seed)
    velocities = math.sqrt(start_kT) * rng.standard_normal((particles, dim))
    velocities -= velocities.mean(axis=0)
    sphere_area = 4 * math.pi if dim == 3 else 2 * math.pi
    collisions, samples, weights = 0, [], []
    while collisions < (relax + measure) * particles:
        speed = math.sqrt(np.max(np.sum(velocities**2, axis=1)))
        dt = safety / (density * sphere_area * 2 * speed)
        velocities[:, 0] -= shear_rate * velocities[:, 1] * dt
        order = rng.permutation(particles)
        first, second = order[0::2], order[1::2]
        normals = rng.standard_normal((first.size, dim))
        normals /= np.linalg.norm(normals, axis=1)[:, None]
        approach = np.einsum("ij,ij->i", velocities[first] - velocities[second], normals)
        chance = (particles - 1) / particles * density * sphere_area * np.maximum(approach, 0.0) * dt
        hit = rng.random(first.size) < chance
        kick = ((1 + restitution) / 2 * approach[hit])[:, None] * normals[hit]
        velocities[first[hit]] -= kick
        velocities[second[hit]] += kick
        collisions += 2 * int(np.count_nonzero(hit))
        if thermostat:
            velocities /= math.sqrt(np.mean(velocities**2))
        if collisions >= relax * particles:
            samples.append((np.mean(velocities**2), np.mean(velocities[:, 0] * velocities[:, 1])))
            weights.append(dt)
    samples, weights = np.array(samples), np.array(weights)
    means = np.array([np.average(samples[part], axis=0, weights=weights[part])
                      for part in np.array_split(np.arange(len(weights)), blocks)])
    value, error = means.mean(axis=0), means.std(axis=0, ddof=1) / math.sqrt(blocks)
    return value[0], error[0], -density * value[1] / shear_rate, density * error[1] / shear_rate
