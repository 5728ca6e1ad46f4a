"""The moments of a two-term solution (:mod:`collisionkit.transport.two_term`): transport coefficients, rates and
where the field's power goes.

Every moment is a sum over the grid's cells or inner edges with F0 constant
in each cell (Hagelaar & Pitchford, Plasma Sources Sci. Technol. 14, 722
(2005), eqs. (47)-(62)); the field's, recoil's and electron-electron powers
are the fluxes the solved equation carries, so that the power balance checks
the solution.
"""

from __future__ import annotations

import math

import numpy as np

from ._two_term_operators import GAMMA, cell_integral


def moments(solution, field_si) -> dict:
    """The moments of F0 as TwoTermResult's fields: mean energy, mobility, diffusion, rates, the power balance."""
    eedf, edges, inner = solution["eedf"], solution["edges"], solution["inner"]
    effective, collisions = solution["effective"], solution["collisions"]
    low, high = edges[:-1], edges[1:]
    mean_energy = float(eedf @ ((high**2.5 - low**2.5) / 2.5))
    mobility = float(-GAMMA / 3.0 * np.sum(inner / effective * np.diff(eedf)))
    diffusion = float(GAMMA / 3.0 * np.sum(eedf * cell_integral(lambda e: e / _effective_at(solution, e), edges)))
    energy_mobility = float(-GAMMA / (3.0 * mean_energy) * np.sum(inner**2 / effective * np.diff(eedf)))
    energy_diffusion = float(GAMMA / (3.0 * mean_energy) * np.sum(
        eedf * cell_integral(lambda e: e**2 / _effective_at(solution, e), edges)))
    momentum_frequency = float(GAMMA * np.sum(eedf * cell_integral(
        lambda e: e * sum(x * sigma(e) for x, sigma in collisions.momentum), edges)))
    rates, losses = _rates_and_losses(solution)
    ionization = sum(rates[label] for label, kind, *_ in collisions.channels if kind == "ionization")
    attachment = sum(rates[label] for label, kind, *_ in collisions.channels if kind == "attachment")
    inelastic_power = sum(losses.values())
    drift_velocity = mobility * field_si
    # eV m^3/s per electron and N: -sum D_field dF0 over the inner edges (mobility E^2/N^2 in a DC field)
    field_power = float(-np.sum(solution["field_diffusion"] * np.diff(eedf)))
    growth = solution["growth"]
    if solution["growth_model"] == "temporal":
        growth_power = growth * mean_energy  # new electrons are born cold: they dilute the mean energy
        denominator = drift_velocity  # alpha = k_i / W
    else:  # the energy the alpha terms carry: alpha [E/N (N D + <e> mu_e N) - alpha <e> D_e N]
        growth_power = growth * (field_si * (diffusion + mean_energy * energy_mobility)
                                 - growth * mean_energy * energy_diffusion)
        net = ionization - attachment
        denominator = net / growth if net != 0.0 and growth != 0.0 else drift_velocity
    elastic_power = _elastic_power(solution)
    coulomb = solution["coulomb"]  # the electrons' energy exchange among themselves: zero but for the top cell
    among_electrons = coulomb.power(eedf) if coulomb is not None else 0.0
    balance = ((field_power - inelastic_power - elastic_power - growth_power - among_electrons) / field_power
               if field_power else 0.0)
    shares = {"elastic": elastic_power, **losses, "growth": growth_power, "electron-electron": among_electrons}
    power_fractions = {name: value / field_power for name, value in shares.items()} if field_power else {}
    return dict(
        energy=solution["energy"], eedf=eedf, mean_energy=mean_energy, mobility_N=mobility,
        drift_velocity=drift_velocity, diffusion_N=diffusion,
        characteristic_energy=diffusion / mobility if mobility > 0 else math.inf, energy_mobility_N=energy_mobility,
        energy_diffusion_N=energy_diffusion, momentum_frequency_N=momentum_frequency, rate_coefficients=rates,
        ionization_frequency_N=ionization, attachment_frequency_N=attachment,
        alpha_N=ionization / denominator if denominator > 0 else 0.0,
        eta_N=attachment / denominator if denominator > 0 else 0.0, growth=solution["growth_model"],
        power_balance=float(balance), power_fractions=power_fractions, omega_N=solution["omega_N"],
        **_electron_fields(coulomb, eedf))


def _electron_fields(coulomb, eedf):
    """The result's fields of the electron-electron collisions (zeros without them)."""
    if coulomb is None:
        return {}
    coulomb.coefficients(eedf)  # its Coulomb logarithm at this F0
    return {"ionization_degree": coulomb.ionization_degree, "electron_density": coulomb.electron_density,
            "coulomb_logarithm": coulomb.coulomb_logarithm}


def _rates_and_losses(solution):
    """Every process's rate coefficient (by label, m^3/s) and the power it takes from the electrons per electron
    and N (eV m^3/s; negative for a superelastic one, which gives; an attachment takes the electron's energy)."""
    eedf, edges = solution["eedf"], solution["edges"]
    low, high = edges[:-1], edges[1:]
    rates, losses = {}, {}
    for label, kind, share, integral, threshold, weight_ratio in solution["collisions"].channels:
        if kind == "superelastic":
            rates[label] = GAMMA * share / weight_ratio * float(eedf @ integral(low + threshold, high + threshold))
            losses[label] = -rates[label] * threshold
        else:
            rates[label] = GAMMA * share * float(eedf @ integral(low, high))
            losses[label] = rates[label] * threshold
        if kind == "attachment":
            losses[label] += GAMMA * share * float(eedf @ cell_integral(lambda e: e * integral.integrand(e), edges))
    return rates, losses


def field_diffusion(field_si, omega_N, inner, effective):
    r"""The field's diffusion in energy at the inner edges: :math:`\frac{\gamma}{3}(E/N)^2\epsilon/\tilde\sigma_m`, or
    for a high-frequency field of amplitude E (its mean square :math:`E^2/2`)
    :math:`\frac{\gamma}{3}\frac{(E/N)^2}{2}\frac{\epsilon\tilde\sigma_m}{\tilde\sigma_m^2 + q^2/\epsilon}`,
    :math:`q = \omega/(N\gamma)` (Hagelaar & Pitchford 2005, eq. (16))."""
    if omega_N == 0.0:
        return GAMMA / 3.0 * field_si**2 * inner / effective
    q = omega_N / GAMMA
    return GAMMA / 3.0 * 0.5 * field_si**2 * inner * effective / (effective**2 + q * q / inner)


def _effective_at(solution, energy):
    """The momentum-transfer cross section the moments divide by: with temporal growth plus (nu/N)/(gamma eps^1/2)."""
    collisions = solution["collisions"]
    sigma = sum(x * s(energy) for x, s in collisions.momentum)
    if solution["growth_model"] != "temporal":
        return sigma
    with np.errstate(divide="ignore"):
        return sigma + solution["growth"] / (GAMMA * np.sqrt(energy))


def _elastic_power(solution):
    """Net power lost in elastic recoil: the flux the drift term carries, :math:`\\int (-\\tilde W F_0 + \\gamma kT
    \\epsilon^2\\sigma_\\epsilon \\partial_\\epsilon F_0)d\\epsilon`, on the grid's inner edges."""
    eedf, edges, inner = solution["eedf"], solution["edges"], solution["inner"]
    width = edges[1] - edges[0]
    sigma_eps, kT = solution["sigma_eps"], solution["kT"]
    at_edges = 0.5 * (eedf[:-1] + eedf[1:])
    slope = np.diff(eedf) / width
    return float(np.sum(GAMMA * inner**2 * sigma_eps * (at_edges + kT * slope)) * width)
