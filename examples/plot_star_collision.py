"""
From two polytropes to an SPH-ready collision
=============================================

The StarCrash set-up of a hyperbolic stellar collision (J. Faber, StarCrash
user manual, 2003, eqs. 34-39) starts from particle models of single stars
and places them on the orbit. Here both steps run in Python; the same is
``collisionkit star`` twice, then ``collisionkit encounter --star1 --star2``.

First two polytropes (Chandrasekhar, *Stellar Structure*, ch. IV) as SPH
particles, in stellar units (Msun, Rsun, km/s): a Sun-like n = 3 star and a
fully convective n = 1.5 star of half the mass and radius. Their radii are
drawn from the inverse of the Lane-Emden enclosed mass, so the sampled
profile follows :math:`M(<r)/M = \\xi^2\\theta'(\\xi)/(\\xi_1^2\\theta'(\\xi_1))`
up to Poisson noise, and the potential energy of the particles is close to
:math:`W = -\\frac{3}{5-n}\\frac{GM^2}{R}`.
"""

import h5py
import matplotlib.pyplot as plt
import numpy as np
from scipy import stats

from collisionkit import encounters, plotting

sun = encounters.polytrope_star(3.0, 3000, mass=1.0, radius=1.0, units="stellar", seed=1)
dwarf = encounters.polytrope_star(1.5, 1500, mass=0.5, radius=0.5, units="stellar", seed=2)

fig, ax = plt.subplots(layout="constrained")
for star, n, radius, colour in ((sun, 3.0, 1.0, "C0"), (dwarf, 1.5, 0.5, "C1")):
    r = np.sort(np.linalg.norm(star.positions, axis=1))
    solution = encounters.lane_emden(n)
    profile = solution.mass_fraction(r / radius * solution.xi1)
    p_value = stats.kstest(r, lambda x: solution.mass_fraction(x / radius * solution.xi1)).pvalue
    W, expected = star.potential_energy(), -3 / (5 - n) * star.G * star.mass**2 / radius
    print(f"n = {n}: K-S p = {p_value:.3f}; W = {W:.5g} vs -3/(5-n) G M^2/R = {expected:.5g} (km/s)^2 Msun; "
          f"99 % of the mass inside {star.radius(0.99):.3f} Rsun")
    ax.step(r, np.arange(1, len(r) + 1) / len(r), where="post", color=colour, label=f"n = {n:g}: particles")
    ax.plot(r, profile, "k--", lw=0.8)
ax.set_xlabel("r (Rsun)")
ax.set_ylabel("M(<r) / M")
ax.set_title("sampled enclosed mass and Lane-Emden (dashed)")
ax.legend()

# %%
# These models are **unrelaxed**: random positions carry Poisson noise in the
# density. Written with ``encounters.write_star(sun, "sun.hdf5")`` (the
# GADGET/SWIFT snapshot layout), each is the input to the SPH code's own
# relaxation; the relaxed snapshot is read back with ``encounters.read_star``.
# Here the unrelaxed ones stand in for them.
#
# Then the placement: each star's mass and centre of mass come from its
# particles, the two-body orbit from eqs. 34-39 (periastron 1 Rsun, 50 km/s at
# infinity), and each star is moved rigidly so that its centre of mass and its
# velocity are the two-body ones in the centre-of-mass frame. The stars start
# at :math:`r_0 = 8(R_1 + R_2)`, beyond the :math:`5(R_1 + R_2)` below which
# tides at the start are not negligible (:class:`~collisionkit.encounters.TidalWarning`).

R1, R2 = sun.radius(0.99), dwarf.radius(0.99)
parameters = encounters.StarEncounterParameters(rp=1.0, v_inf=50.0, sep0=8 * (R1 + R2), units="stellar")
summary, ic, pair = encounters.star_encounter_summary(sun, dwarf, parameters)
print(f"sep0 = {ic.sep0:.3f} Rsun, v0 = {ic.v0:.2f} km/s, b = {ic.impact_parameter:.3f} Rsun, "
      f"e = {ic.orbit.eccentricity:.4f}, warnings: {summary['warnings']}")
print(f"total momentum {np.linalg.norm(pair.masses @ pair.velocities):.1e} Msun km/s, "
      f"centre of mass at {np.linalg.norm(pair.centre_of_mass):.1e} Rsun")

path = encounters.write_star(pair, "initial_conditions.hdf5")
with h5py.File(path, "r") as file:
    header, units = file["Header"].attrs, file["Units"].attrs
    print(f"{path}: NumPart_Total = {header['NumPart_Total'].tolist()}, BoxSize = {header['BoxSize']:.3f}, "
          f"U_L = {units['Unit length in cgs (U_L)']:.4g} cm, datasets {sorted(file['PartType0'])}")

ax = plotting.plot_star_encounter(ic, pair, units="stellar")

# %%
# ``initial_conditions.hdf5`` holds star 1's particles, then star 2's
# (``StarID`` 1 and 2, IDs kept unique), centred on the origin: a code that
# wants positions in ``[0, BoxSize)`` shifts them by ``BoxSize / 2`` (SWIFT's
# ``InitialConditions: shift``).
