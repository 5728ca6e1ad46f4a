"""
Slab transmission and reflection
================================

A beam enters a slab of thickness d (in mean free paths). Each particle flies
a random free path s = -lambda ln(xi), scatters isotropically with
probability omega (the single-scattering albedo) or is absorbed, and is
followed until it leaves: through x > d (transmitted) or back through x < 0
(reflected), as in Krasov's section 5.5.

Two exact results check the Monte Carlo: in the one-dimensional rod model
with pure scattering the transmission is T = 1 / (1 + tau/2), and with no
scattering at all (omega = 0) a normal beam is transmitted with probability
exp(-tau). Without absorption R + T = 1.
"""

import matplotlib.pyplot as plt
import numpy as np

from collisionkit import transport

thickness = np.array([0.25, 0.5, 1.0, 2.0, 4.0, 8.0])
rod = [transport.simulate_slab(tau, 1.0, model="rod", particles=20_000, seed=1) for tau in thickness]
absorbing = [transport.simulate_slab(tau, 0.0, particles=20_000, seed=2) for tau in thickness]
isotropic = [transport.simulate_slab(tau, 1.0, particles=20_000, seed=3) for tau in thickness]

fig, ax = plt.subplots(layout="constrained")
fine = np.linspace(0.0, 8.0, 200)
ax.plot(fine, 1 / (1 + fine / 2), "k-", lw=1, label="rod model: 1 / (1 + tau/2)")
ax.plot(fine, np.exp(-fine), "k--", lw=1, label="pure absorption: exp(-tau)")
for results, label in ((rod, "rod, omega = 1"), (absorbing, "3D, omega = 0"), (isotropic, "3D, omega = 1")):
    ax.errorbar(
        thickness,
        [r.transmission for r in results],
        yerr=[r.transmission_error for r in results],
        fmt="o",
        ms=4,
        label=f"Monte Carlo: {label}",
    )
ax.set_xlabel("thickness tau (mean free paths)")
ax.set_ylabel("transmission T")
ax.legend()
worst = max(abs(r.transmission + r.reflection - 1) for r in isotropic)
print(f"largest |R + T - 1| without absorption: {worst:.1e}")
plt.show()
