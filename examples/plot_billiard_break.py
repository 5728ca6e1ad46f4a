"""
Billiard break
==============

A cue ball hits a triangular rack of 15 balls on a table with cushions. The
table is a :class:`collisionkit.edmd.HardSphereSystem` in two dimensions with
hard walls on both axes (``periodic=False``); the event-driven engine finds
each ball-ball and ball-cushion contact exactly and resolves it along the line
of centres. Balls lose a little energy in each contact (restitution 0.95,
cushions 0.8).
"""

import matplotlib.pyplot as plt
import numpy as np

from collisionkit.edmd import HardSphereSystem

radius = 0.5
table = np.array([36.0, 18.0])
spacing = 2 * radius * 1.001  # a hair apart: hard spheres may not overlap

rack = []
for row in range(5):
    for k in range(row + 1):
        rack.append([24.0 + row * spacing * np.sqrt(3) / 2, table[1] / 2 + (k - row / 2) * spacing])
positions = np.array([[8.0, table[1] / 2 + 0.05], *rack])  # the cue ball first, slightly off centre
velocities = np.zeros_like(positions)
velocities[0] = [12.0, 0.0]
species = np.array([0] + [1] * 15)

system = HardSphereSystem(positions, velocities, radius, table, periodic=False, species=species,
                          restitution=0.95, wall_restitution=0.8)
print(system)

# %%
# Run the break in small time steps and record the paths.

steps, dt = 120, 0.04
paths = [system.positions().copy()]
for _ in range(steps):
    system.run(time=dt)
    paths.append(system.positions().copy())
paths = np.array(paths)
print(f"after t = {steps * dt:g}: {system.collisions} contacts, "
      f"kinetic energy {system.kinetic_energy():.2f} of {0.5 * 12.0**2:.2f}")

fig, ax = plt.subplots(figsize=(8, 4.5), layout="constrained")
ax.add_patch(plt.Rectangle((0, 0), *table, color="#1b6e3a"))
for ball in range(len(positions)):
    colour = "white" if ball == 0 else f"C{ball % 10}"
    ax.plot(paths[:, ball, 0], paths[:, ball, 1], color=colour, lw=1, alpha=0.8)
    ax.add_patch(plt.Circle(paths[-1, ball], radius, color=colour, ec="k", lw=0.5))
ax.set_xlim(0, table[0])
ax.set_ylim(0, table[1])
ax.set_aspect("equal")
ax.set_title("billiard break: paths and final positions")
