"""
Granular cooling (Haff's law)
=============================

Grains lose energy in every collision: with a coefficient of normal
restitution *e* a contact removes :math:`\\mu(1-e^2)u_n^2/2`. A homogeneous
granular gas therefore cools. On average a pair collision removes the
fraction :math:`(1-e^2)/d` of the kinetic energy of two particles, so the
temperature falls with the number of collisions *C* as

.. math:: T = T_0 \\exp\\left(-\\frac{2(1-e^2)\\,C}{dN}\\right),

and since the collision frequency grows as :math:`\\sqrt{T}`, in time as
Haff's law (P. K. Haff, J. Fluid Mech. 134, 401 (1983))

.. math:: T(t) = \\frac{T_0}{(1 + t/\\tau)^2}, \\qquad
          \\tau = \\frac{2d}{(1-e^2)\\,\\omega_0},

with :math:`\\omega_0` the initial collision frequency per particle (here from
the Enskog relation and the Carnahan-Starling pressure).
"""

import matplotlib.pyplot as plt
import numpy as np

from collisionkit import edmd

e, eta, dim = 0.9, 0.1, 3
positions, box = edmd.lattice("fcc", 4, eta)  # N = 256
velocities = edmd.maxwell_boltzmann(np.ones(len(positions)), dim, kT=1.0, seed=3)
elastic = edmd.HardSphereSystem(positions, velocities, 0.5, box)
elastic.run(collisions=20 * elastic.count)  # melt the lattice first
system = edmd.HardSphereSystem(elastic.positions(), elastic.velocities(), 0.5, box, restitution=e)
t0 = system.temperature()

times, temperatures, collisions = [0.0], [t0], [0]
for _ in range(12):
    system.run(collisions=system.count // 2)
    times.append(system.elapsed + system.time)
    temperatures.append(system.temperature())
    collisions.append(system.collisions)
times, temperatures, collisions = map(np.array, (times, temperatures, collisions))

omega0 = float(edmd.enskog_collision_frequency(edmd.carnahan_starling(eta), dim, kT=t0))
tau = 2 * dim / ((1 - e**2) * omega0)
haff = t0 / (1 + times / tau) ** 2
by_collisions = t0 * np.exp(-2 * (1 - e**2) * collisions / (dim * system.count))
print(f"tau = {tau:.3f}; after {collisions[-1]} collisions T/T0 = {temperatures[-1] / t0:.4f}, "
      f"Haff {haff[-1] / t0:.4f}, collision count law {by_collisions[-1] / t0:.4f}")

fig, ax = plt.subplots(layout="constrained")
ax.plot(times, temperatures / t0, "o", label=f"EDMD, N = {system.count}, e = {e}")
fine = np.linspace(0, times[-1], 200)
ax.plot(fine, 1 / (1 + fine / tau) ** 2, "k-", label=r"Haff: $1/(1+t/\tau)^2$")
ax.set_xlabel("time")
ax.set_ylabel("$T/T_0$")
ax.set_yscale("log")
ax.legend()
