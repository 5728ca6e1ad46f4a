"""
Square-well gas against its virial expansion
============================================

Square wells add an attraction of depth :math:`\\epsilon` out to
:math:`\\lambda` contact distances to hard spheres
(``HardSphereSystem(..., well_width=1.5)``). In a dilute gas the pressure and
the potential energy follow the virial expansion, here to second order with
the exact :math:`B_2` and Kihara's :math:`B_3`
(:func:`collisionkit.edmd.square_well_low_density`):

.. math:: Z = 1 + B_2 \\rho + B_3 \\rho^2, \\qquad
          \\frac{U}{N} = \\epsilon\\, e^{\\epsilon / kT} \\left[\\rho \\frac{dB_2}{dx}
          + \\frac{\\rho^2}{2} \\frac{dB_3}{dx}\\right], \\quad x = e^{\\epsilon/kT} - 1.

Each run keeps its total energy (kinetic plus potential), so its temperature
is an outcome: the time-mean kT the measurement reports, at which the
theory is taken; the terms of third order left out grow as kT falls (at kT
= 1.5 they show at a few errors). 864 spheres at :math:`\\rho \\sigma^3 = 0.05`, about a second a point.
"""

import math

import matplotlib.pyplot as plt
import numpy as np

from collisionkit import edmd

density, width = 0.05, 1.5
positions, box = edmd.lattice("fcc", 6, math.pi / 6 * density)
measured = []
for seed, start in enumerate((1.2, 1.6, 2.4, 4.0)):  # kT of the initial velocities
    velocities = edmd.maxwell_boltzmann(np.ones(len(positions)), 3, kT=start, seed=seed)
    system = edmd.HardSphereSystem(positions, velocities, 0.5, box, well_width=width)
    system.run(collisions=40 * system.count)  # equilibrate: pairs fall into their wells, the gas warms up
    m = edmd.measure(system, collisions=400 * system.count, blocks=10)
    measured.append(m)
    z, energy = edmd.square_well_low_density(density, m.temperature_mean, width)
    print(f"kT = {m.temperature_mean:.3f}: Z = {m.compressibility_factor:.4f} +- {m.compressibility_factor_error:.4f} "
          f"(virial {z:.4f}), U/N = {m.potential_energy:.4f} +- {m.potential_energy_error:.4f} (virial {energy:.4f})")

temperatures = np.linspace(1.0, 5.0, 200)
theory = np.array([edmd.square_well_low_density(density, kT, width) for kT in temperatures])
fig, axes = plt.subplots(1, 2, figsize=(9, 3.6), layout="constrained")
for ax, column, name, error in ((axes[0], 0, "compressibility_factor", "Z = PV / NkT"),
                                (axes[1], 1, "potential_energy", "U / N epsilon")):
    ax.plot(temperatures, theory[:, column], label="virial expansion to $B_3$")
    ax.errorbar([m.temperature_mean for m in measured], [getattr(m, name) for m in measured],
                yerr=[getattr(m, f"{name}_error") for m in measured], fmt="o", label="event-driven MD")
    ax.set_xlabel("kT / epsilon")
    ax.set_ylabel(error)
    ax.legend()
fig.suptitle(f"square wells, lambda = {width}, rho sigma^3 = {density}")
