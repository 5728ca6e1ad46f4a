"""
Comparisons with published and analytic results
================================================

Five checks, each run at build time with small sizes (the test suite runs
larger ones): the hard-sphere and hard-disc equations of state, irfpy's
stationary-target formulas in the centre-of-mass frame, Rutherford's law
against the classical deflection integral, the exact conic propagation
against a high-order numerical integrator, and the two-term Boltzmann
solver against the equation's exact solutions.
"""

# %%
# Hard-sphere and hard-disc equations of state
# --------------------------------------------
#
# Compressibility factor :math:`Z = PV/(NkT)` measured by event-driven dynamics
# (collisional virial, block standard errors) against Hansen-Goos (J. Chem.
# Phys. 144, 164506 (2016)) for spheres and Henderson (Mol. Phys. 30, 971
# (1975)) for discs.

import math

import matplotlib.pyplot as plt
import numpy as np
from scipy import integrate, optimize

from collisionkit import edmd, encounters, plotting, scattering
from collisionkit.compat.irfpy import binary_collision_stationary

fig, axes = plt.subplots(1, 2, figsize=(10, 4), layout="constrained")
print(" d  eta    N    Z (EDMD)          theory    deviation/error")
for ax, dim, etas, theory in ((axes[0], 3, (0.2, 0.4), edmd.hansen_goos), (axes[1], 2, (0.3, 0.5), edmd.henderson)):
    points = []
    for eta in etas:
        system = edmd.random_fluid(dim, 500, eta, seed=11)
        system.run(collisions=10 * system.count)
        m = edmd.measure(system, collisions=100 * system.count, blocks=8)
        points.append(m)
        expected = float(theory(eta))
        deviation = (m.compressibility_factor - expected) / m.compressibility_factor_error
        print(f" {dim}  {eta:.2f} {m.particles:4d}  {m.compressibility_factor:.4f} +- {m.compressibility_factor_error:.4f}"
              f"   {expected:.4f}   {deviation:+.1f}")
    plotting.plot_equation_of_state(points, dim=dim, ax=ax)

# %%
# irfpy's stationary target in the centre-of-mass frame
# -----------------------------------------------------
#
# irfpy's documentation leaves a TODO: check the stationary-target formulation
# in the centre-of-mass system. In that frame an elastic collision keeps both
# speeds, keeps the momenta opposite, and turns them by
# :math:`\chi = 2\arccos(d/(r_1+r_2))` (hard spheres, :math:`b = \sigma\cos(\chi/2)`).

m1, m2, v1, sigma = 1.0, 2.5, 1.0, 1.0
d = np.linspace(0.0, 0.98, 50) * sigma
V1, W1, V2, W2 = binary_collision_stationary(m1, v1, m2, d, sigma)
v_cm = m1 * v1 / (m1 + m2)
w1 = np.stack([V1 - v_cm, W1], axis=-1)
w2 = np.stack([V2 - v_cm, W2], axis=-1)
turn = np.arctan2(w1[:, 1], w1[:, 0])
speed_error = np.max(np.abs(np.linalg.norm(w1, axis=-1) / (v1 - v_cm) - 1))
momentum_error = np.max(np.abs(m1 * w1 + m2 * w2))
angle_error = np.max(np.abs(np.abs(turn) - 2 * np.arccos(d / sigma)))
print(f"largest relative change of the CM speed:  {speed_error:.1e}")
print(f"largest CM momentum after the collision:  {momentum_error:.1e}")
print(f"largest error of the turn 2 arccos(d/s):  {angle_error:.1e} rad")

fig, ax = plt.subplots(layout="constrained")
ax.plot(d / sigma, np.degrees(np.abs(turn)), "o", ms=4, label="irfpy formulas, CM frame")
ax.plot(d / sigma, np.degrees(2 * np.arccos(d / sigma)), "k-", label=r"$2\arccos(d/\sigma)$")
ax.set_xlabel(r"impact parameter $d/\sigma$")
ax.set_ylabel("CM deflection (degrees)")
ax.legend()

# %%
# Rutherford's law against the deflection integral
# ------------------------------------------------
#
# The closed form :math:`\tan(\chi/2) = k/(\mu v^2 b)` against Landau &
# Lifshitz eq. 18.1, :math:`\chi = \pi - 2\int_{r_{min}}^\infty b\,dr /
# (r^2\sqrt{1 - b^2/r^2 - V/E})`, integrated with scipy (substituting
# :math:`u = 1/r` and :math:`u = u_{max}(1 - s^2)` to remove the endpoint singularity).


def deflection_integral(b, k, mu, v):
    energy = 0.5 * mu * v * v

    def radicand(u):
        return 1.0 - (b * u) ** 2 - k * u / energy

    upper = 1.0
    while radicand(upper) > 0:
        upper *= 2.0
    u_max = optimize.brentq(radicand, 0.0, upper, xtol=1e-15, rtol=1e-15)

    def integrand(s):
        u = u_max * (1.0 - s * s)
        return b * 2.0 * u_max * s / math.sqrt(max(radicand(u), 1e-300))

    value, _ = integrate.quad(integrand, 0.0, 1.0, epsabs=1e-13, epsrel=1e-12, limit=200)
    return math.pi - 2.0 * value


mu, v = 1.0, 1.0
b = np.geomspace(0.05, 20.0, 40)
fig, ax = plt.subplots(layout="constrained")
for k, colour in ((1.0, "C0"), (-1.0, "C3")):
    closed = scattering.rutherford_deflection(b, k, mu, v)
    numeric = np.array([deflection_integral(bi, k, mu, v) for bi in b])
    print(f"k = {k:+.0f} ({'repulsive' if k > 0 else 'attractive'}): largest |closed form - integral| = "
          f"{np.max(np.abs(closed - numeric)):.1e} rad")
    ax.semilogx(b, np.degrees(numeric), "o", ms=4, color=colour, label=f"integral, k = {k:+.0f}")
    ax.semilogx(b, np.degrees(closed), "-", color=colour, lw=1, label=f"Rutherford, k = {k:+.0f}")
ax.set_xlabel(r"impact parameter $b\,\mu v^2/|k|$")
ax.set_ylabel(r"CM deflection $\chi$ (degrees)")
ax.legend(fontsize="small")

# %%
# Exact conic propagation against DOP853
# --------------------------------------
#
# The universal-variable propagation of :class:`collisionkit.encounters.TwoBodyOrbit`
# against scipy's 8th-order Dormand-Prince integrator (rtol 1e-13) of
# :math:`\ddot r = -\mu_K r/r^3`, from periastron outwards: a hyperbola
# (e = 1.5) out to 1000 periastron distances, and an ellipse (e = 0.7) over
# ten periods.


def relative_ode(_, y, mu_k):
    r = y[:3]
    return np.concatenate([y[3:], -mu_k * r / np.sqrt(r @ r) ** 3])


fig, ax = plt.subplots(layout="constrained")
for orbit, span, label in (
    (encounters.TwoBodyOrbit(1.0, 1.0, periastron=1.0, eccentricity=1.5), None, "hyperbola, e = 1.5"),
    (encounters.TwoBodyOrbit(1.0, 1.0, periastron=1.0, eccentricity=0.7), 10, "ellipse, e = 0.7"),
):
    end = orbit.time_at_separation(1000.0, branch="outbound") if span is None else span * orbit.period
    times = np.linspace(0.0, end, 400)[1:]
    mu_k = orbit.kepler_parameter
    r0 = np.array([orbit.periastron, 0.0, 0.0])
    v0 = np.array([0.0, orbit.periastron_speed, 0.0])
    solution = integrate.solve_ivp(relative_ode, (0.0, end), np.concatenate([r0, v0]), method="DOP853",
                                   rtol=1e-13, atol=1e-22, t_eval=times, args=(mu_k,))
    exact, _ = orbit.relative_state_at_time(times)
    error = np.linalg.norm(solution.y[:3].T - exact, axis=-1) / np.linalg.norm(exact, axis=-1)
    print(f"{label}: largest relative position difference {error.max():.1e} over t = {end:.4g}")
    ax.semilogy(times / end, error + 1e-18, label=label)
ax.set_xlabel("time / time span")
ax.set_ylabel("|DOP853 - exact| / r")
ax.legend()


# %%
# The two-term Boltzmann equation against its exact solutions
# -----------------------------------------------------------
#
# :func:`collisionkit.transport.two_term_boltzmann` for two gases whose
# two-term equation is solved by hand (zero flux in energy:
# :math:`F_0'/F_0 = \tilde W/\tilde D`), electrons in helium-mass targets at
# 10 Td and 0 K. A constant collision frequency :math:`\nu = Nk` (the Maxwell
# model) gives a Maxwellian of :math:`kT_e = (M/6m)(2e/m)(E/N)^2/k^2`; a
# constant cross section :math:`\sigma` gives Druyvesteyn's
# :math:`F_0 \propto \exp(-3(m/M)\sigma^2\epsilon^2/(E/N)^2)`. The scheme is
# second order in the cell: the mean energy's error falls 4x as the cells double.

from scipy import constants  # noqa: E402

from collisionkit import transport  # noqa: E402

helium, field = 4 * constants.atomic_mass, 10e-21  # kg, V m^2
kTe = helium / (6 * constants.m_e) * (2 * constants.e / constants.m_e) * field**2 / 1e-26  # k = 1e-13 m^3/s
a = 3 * constants.m_e / helium * (6e-20) ** 2 / field**2
cases = {  # gas, exact F0 shape, exact mean energy
    "Maxwell model, k = 1e-13 m^3/s": (transport.maxwell_model(1e-13), lambda e: np.exp(-e / kTe), 1.5 * kTe),
    "constant cross section, 6e-20 m^2": (transport.hard_sphere_gas(6e-20), lambda e: np.exp(-a * e**2),
                                          math.gamma(1.25) / (math.gamma(0.75) * math.sqrt(a))),
}
fig, axes = plt.subplots(1, 2, figsize=(9, 3.6), layout="constrained")
for label, (gas, shape, exact_mean) in cases.items():
    result = transport.two_term_boltzmann(gas, 10.0, 0.0)
    edges = np.linspace(0.0, result.max_energy, result.cells + 1)
    exact = shape(result.energy) / (shape(result.energy) @ np.diff(edges**1.5 / 1.5))  # int eps^1/2 F0 = 1
    axes[0].semilogy(result.energy, result.eedf, label=label)
    axes[0].semilogy(result.energy, exact, "k:", lw=1)
    cells = np.array([125, 250, 500, 1000, 2000])
    errors = [abs(transport.two_term_boltzmann(gas, 10.0, 0.0, cells=int(n)).mean_energy / exact_mean - 1.0)
              for n in cells]
    print(f"{label}: mean energy {result.mean_energy:.6f} eV, exact {exact_mean:.6f} eV; relative errors "
          f"from {cells[0]} to {cells[-1]} cells: " + ", ".join(f"{error:.1e}" for error in errors))
    axes[1].loglog(cells, errors, "o-", label=label)
axes[1].loglog(cells, errors[0] * (cells[0] / cells) ** 2, "k:", lw=1, label="second order")
axes[0].set_xlabel("energy (eV)")
axes[0].set_ylabel("F0 (eV^-3/2); dotted: exact")
axes[0].set_ylim(1e-16, 1)
axes[0].legend(fontsize=8)
axes[1].set_xlabel("cells")
axes[1].set_ylabel("|<e> / <e>exact - 1|")
axes[1].legend(fontsize=8)
