"""
A hyperbolic stellar flyby
==========================

Two stars approach from far apart with relative speed :math:`v_\\infty`, swing
past each other at periastron :math:`r_p` and leave on a hyperbola. The
StarCrash set-up (J. Faber, StarCrash user manual, 2003, eqs. 34-39) places
them at separation :math:`r_0` with

.. math:: v_0 = \\sqrt{v_\\infty^2 + 2GM_T/r_0}, \\quad
          v_p = \\sqrt{v_\\infty^2 + 2GM_T/r_p}, \\quad
          b = \\frac{v_p r_p}{v_\\infty}, \\quad v_t = \\frac{v_\\infty b}{r_0},

and :func:`collisionkit.encounters.starcrash_initial_conditions` computes all
of them; the orbit is then propagated exactly (universal variables), and the
deflection follows Rutherford's formula :math:`\\tan(\\chi/2) = GM_T/(b v_\\infty^2)`.
"""

import math

import matplotlib.pyplot as plt
import numpy as np

from collisionkit import encounters, plotting

ic = encounters.starcrash_initial_conditions(m1=1.0, m2=0.5, rp=1.0, v_inf=0.5, sep0=10.0)
print(f"v0 = {ic.v0:.6f}, vp = {ic.vp:.6f}, b = {ic.impact_parameter:.6f}, vt = {ic.vt:.6f}, vr = {ic.vr:.6f}")
orbit = ic.orbit
chi = 2 * math.atan(ic.G * ic.total_mass / (ic.impact_parameter * ic.v_inf**2))
print(f"e = {orbit.eccentricity:.6f}; deflection {math.degrees(orbit.deflection_angle):.4f} deg "
      f"(Rutherford {math.degrees(chi):.4f} deg)")

ax = plotting.plot_encounter(ic)

# %%
# Separation and relative speed along the way: energy conservation,
# :math:`v^2/2 - GM_T/r = v_\infty^2/2`, holds at every time.

t = np.linspace(-ic.time_to_periastron, ic.time_to_periastron, 400)
positions, velocities = orbit.state_at_time(t)
r = np.linalg.norm(positions[:, 1] - positions[:, 0], axis=-1)
v = np.linalg.norm(velocities[:, 1] - velocities[:, 0], axis=-1)
energy = 0.5 * v**2 - ic.G * ic.total_mass / r
print(f"largest energy error along the orbit: {np.max(np.abs(energy - 0.5 * ic.v_inf**2)):.2e}")

fig, ax1 = plt.subplots(layout="constrained")
ax1.plot(t, r, "C0")
ax1.set_xlabel("time from periastron")
ax1.set_ylabel("separation", color="C0")
ax2 = ax1.twinx()
ax2.plot(t, v, "C3")
ax2.set_ylabel("relative speed", color="C3")
