"""Figures of the collision core: irfpy's stationary-target scan, deflection laws, inelastic energy loss."""

from __future__ import annotations

import numpy as np

from .. import scattering
from ..compat.irfpy import binary_collision_stationary
from ._common import _axes


def plot_stationary_scan(mass_ratio=1.0, collision_length=1.0, points=201, ax=None):
    """irfpy's stationary-target scan: V1, W1, V2, W2 against the impact parameter.

    Particle 1 (speed 1) hits particle 2 at rest; ``mass_ratio`` = m2 / m1.

    Examples
    --------
    >>> from collisionkit import plotting
    >>> ax = plotting.plot_stationary_scan(mass_ratio=2.0)
    >>> [text.get_text() for text in ax.get_legend().get_texts()]
    ['$V_1$', '$W_1$', '$V_2$', '$W_2$']
    """
    d = np.linspace(0.0, collision_length, points)
    V1, W1, V2, W2 = binary_collision_stationary(1.0, 1.0, mass_ratio, d, collision_length)
    ax = _axes(ax)
    for values, label in ((V1, "$V_1$"), (W1, "$W_1$"), (V2, "$V_2$"), (W2, "$W_2$")):
        ax.plot(d / collision_length, values, label=label)
    ax.set_xlabel("impact parameter $d/(r_1+r_2)$")
    ax.set_ylabel("velocity after / $v_1$")
    ax.set_title(f"stationary target, $m_2/m_1 = {mass_ratio:g}$")
    ax.axhline(0.0, color="0.7", lw=0.8)
    ax.legend()
    return ax


def plot_deflection_laws(sigma=1.0, coulomb_length=0.25, points=400, ax=None):
    """CM deflection against impact parameter: hard sphere and Coulomb (both signs).

    ``coulomb_length`` is ``|k| / (mu v^2)``.

    Examples
    --------
    >>> from collisionkit import plotting
    >>> len(plotting.plot_deflection_laws().get_legend().get_texts())
    3
    """
    b = np.linspace(0.0, 2.0 * sigma, points)
    ax = _axes(ax)
    ax.plot(b, np.degrees(scattering.hard_sphere_deflection(b, sigma)), label="hard sphere")
    for sign, label in ((1.0, "Coulomb, repulsive"), (-1.0, "Coulomb, attractive")):
        chi = scattering.rutherford_deflection(b, sign * coulomb_length, 1.0, 1.0)
        ax.plot(b, np.degrees(chi), label=label)
    ax.set_xlabel(r"impact parameter $b/\sigma$")
    ax.set_ylabel(r"CM deflection $\chi$ (degrees)")
    ax.axhline(0.0, color="0.7", lw=0.8)
    ax.legend()
    return ax


def plot_energy_loss(approach_speed, loss, reduced_mass, restitution, ax=None):
    """Measured kinetic-energy loss of inelastic contacts against mu (1 - e^2) u_n^2 / 2.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit import plotting
    >>> u = np.linspace(0, 1, 5)
    >>> ax = plotting.plot_energy_loss(u, 0.5 * 0.75 * u**2, 1.0, 0.5)
    >>> len(ax.lines)
    2
    """
    ax = _axes(ax)
    theory = 0.5 * reduced_mass * (1.0 - np.square(restitution)) * np.square(approach_speed)
    ax.plot(theory, loss, ".", ms=3, label="resolve_contact")
    top = float(np.max(theory)) if np.size(theory) else 1.0
    ax.plot([0, top], [0, top], "k--", lw=1, label=r"$\frac{1}{2}\mu(1-e^2)u_n^2$")
    ax.set_xlabel(r"expected loss (units of $m\,v^2$)")
    ax.set_ylabel(r"measured loss (units of $m\,v^2$)")
    ax.legend()
    return ax


