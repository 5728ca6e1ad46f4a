"""
irfpy stationary-target scan
============================

A particle of speed 1 hits a particle at rest. The velocities after the
collision depend only on the mass ratio and on the impact parameter ``d``
relative to the collision length ``r1 + r2``: V1, W1 (along and across the
incoming direction, for particle 1) and V2, W2 (for the target). These are
the outputs of ``irfpy.util.collision.binary_collision_stationary``, which
:mod:`collisionkit.compat.irfpy` reproduces with the same arguments.

Head-on (d = 0) equal masses exchange velocities; at grazing incidence
(d -> r1 + r2) nothing happens.
"""

import matplotlib.pyplot as plt
import numpy as np

from collisionkit import plotting
from collisionkit.compat.irfpy import binary_collision_stationary

fig, axes = plt.subplots(1, 3, figsize=(12, 3.8), sharey=True, layout="constrained")
for ax, ratio in zip(axes, (0.5, 1.0, 4.0)):
    plotting.plot_stationary_scan(mass_ratio=ratio, ax=ax)

# %%
# The numbers at a few impact parameters, and the two conservation laws.

d = np.array([0.0, 0.25, 0.5, 0.75, 0.99])
m1, m2 = 1.0, 4.0
V1, W1, V2, W2 = binary_collision_stationary(m1, 1.0, m2, d, 1.0)
print("  d      V1        W1        V2        W2      momentum  energy")
for row in zip(d, V1, W1, V2, W2):
    di, v1, w1, v2, w2 = row
    momentum = m1 * v1 + m2 * v2
    energy = 0.5 * m1 * (v1**2 + w1**2) + 0.5 * m2 * (v2**2 + w2**2)
    print(f"{di:5.2f} {v1:9.5f} {w1:9.5f} {v2:9.5f} {w2:9.5f} {momentum:9.6f} {energy:8.6f}")
