"""
Rutherford scattering
=====================

Charged particles fired at a nucleus with impact parameter *b* are deflected
by the centre-of-mass angle :math:`\\chi` with
:math:`\\tan(\\chi/2) = k/(\\mu v^2 b)` (:func:`collisionkit.scattering.rutherford_deflection`),
where :math:`k = q_1 q_2/(4\\pi\\varepsilon_0)`. A beam spread evenly over
the impact parameters then scatters with Rutherford's differential cross
section

.. math:: \\frac{d\\sigma}{d\\Omega} = \\left(\\frac{k}{2\\mu v^2}\\right)^2 \\frac{1}{\\sin^4(\\chi/2)}

(Landau & Lifshitz, Mechanics, section 19). Here a Monte Carlo beam is
compared with the formula.
"""

import matplotlib.pyplot as plt
import numpy as np

from collisionkit import plotting, scattering

k, mu, v = 1.0, 1.0, 1.0
a = k / (mu * v**2)
rng = np.random.default_rng(5)
b_max = 6 * a  # deflections below 2 arctan(1/6) = 19 degrees are left out
b = b_max * np.sqrt(rng.uniform(size=1_000_000))  # uniform over the beam's disc
chi = scattering.rutherford_deflection(b, k, mu, v)

edges = np.linspace(np.radians(20), np.radians(160), 29)
counts, _ = np.histogram(chi, edges)
solid_angle = 2 * np.pi * (np.cos(edges[:-1]) - np.cos(edges[1:]))
measured = counts / len(b) * np.pi * b_max**2 / solid_angle  # flux times area / solid angle
centres = 0.5 * (edges[1:] + edges[:-1])
theory = scattering.rutherford_differential_cross_section(centres, k, mu, v)

fig, ax = plt.subplots(layout="constrained")
ax.semilogy(np.degrees(centres), measured, "o", ms=4, label="Monte Carlo beam")
ax.semilogy(np.degrees(centres), theory, "k-", label="Rutherford")
ax.set_xlabel(r"CM deflection $\chi$ (degrees)")
ax.set_ylabel(r"$d\sigma/d\Omega$")
ax.legend()
print("largest relative difference:", f"{np.max(np.abs(measured / theory - 1)):.3f}",
      "(counting noise of", f"{1 / np.sqrt(counts.min()):.3f})")

# %%
# Scattered beyond 90 degrees: the cross section :math:`\pi a^2 \cot^2(\chi/2)`.

above = float(scattering.rutherford_cross_section_above(np.pi / 2, k, mu, v))
fraction = np.mean(chi > np.pi / 2) * np.pi * b_max**2
print(f"sigma(chi > 90 deg) = {above:.4f}, Monte Carlo {fraction:.4f}")

# %%
# The deflection law itself, for hard spheres and for both signs of the force.

ax = plotting.plot_deflection_laws(sigma=1.0, coulomb_length=0.25)
