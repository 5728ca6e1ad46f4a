"""Matplotlib helpers; each returns the Axes it drew on.

Not imported by ``collisionkit`` itself (the core needs no matplotlib):
``from collisionkit import plotting``.
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from . import scattering
from .compat.irfpy import binary_collision_stationary


def _axes(ax):
    if ax is None:
        _, ax = plt.subplots(figsize=(6, 4), layout="constrained")
    return ax


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
    ax.set_xlabel("expected loss")
    ax.set_ylabel("measured loss")
    ax.legend()
    return ax


def save(ax, path):
    """Save the figure holding ``ax`` to ``path`` and close it."""
    figure = ax.figure
    figure.savefig(path, dpi=120)
    plt.close(figure)
    return path


def plot_encounter(orbit, max_separation=None, points=400, ax=None):
    """Trajectories of both bodies of a two-body encounter in the centre-of-mass frame.

    Drawn in the orbital plane (x towards periastron, y along the velocity
    there), with the periastron positions marked, the centre of mass (+) and,
    for an unbound orbit, the asymptotes of each body (dashed).

    Parameters
    ----------
    orbit : collisionkit.encounters.TwoBodyOrbit or InitialConditions
        The encounter (initial conditions also set ``max_separation`` to sep0).
    max_separation : float, optional
        Draw while the separation is below this; default 10 r_p, or sep0.
        A bound orbit is drawn over one period.
    points : int
        Samples along the trajectories.

    Examples
    --------
    >>> from collisionkit import plotting
    >>> from collisionkit.encounters import Hyperbolic
    >>> ax = plotting.plot_encounter(Hyperbolic(1.0, 2.0, periastron=1.0, v_inf=1.0))
    >>> len(ax.lines)  # 2 trajectories, 2 periastra, 4 asymptotes, centre of mass
    9
    """
    if hasattr(orbit, "orbit"):  # InitialConditions
        max_separation = orbit.sep0 if max_separation is None else max_separation
        orbit = orbit.orbit
    if orbit.kind == "elliptic":
        half = 0.5 * orbit.period
    else:
        reach = 10.0 * orbit.periastron if max_separation is None else max_separation
        half = orbit.time_at_separation(max(reach, orbit.periastron), branch="outbound")
    times = np.linspace(-half, half, points)
    positions, _ = orbit.state_at_time(times)
    plane = orbit.basis[:2].T  # columns P, Q
    shares = (-orbit.m2 / orbit.total_mass, orbit.m1 / orbit.total_mass)
    ax = _axes(ax)
    for body, (share, colour) in enumerate(zip(shares, ("C0", "C1"))):
        xy = positions[:, body] @ plane
        ax.plot(xy[:, 0], xy[:, 1], color=colour, label=f"body {body + 1}")
        ax.plot(share * orbit.periastron, 0.0, "o", color=colour, ms=5)
    if orbit.kind == "hyperbolic":
        incoming, outgoing, centre = (vector @ plane for vector in orbit.asymptotes())
        reach = float(np.max(np.linalg.norm(positions[:, 1] - positions[:, 0], axis=-1)))
        length = np.array([0.0, reach + float(np.linalg.norm(centre))])
        for share, colour in zip(shares, ("C0", "C1")):
            for direction, sign in ((outgoing, 1.0), (incoming, -1.0)):
                line = share * (centre + sign * length[:, None] * direction)
                ax.plot(line[:, 0], line[:, 1], "--", color=colour, lw=0.8)
    ax.plot(0.0, 0.0, "k+", ms=8)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("towards periastron")
    ax.set_ylabel("along the periastron velocity")
    ax.set_title(f"{orbit.kind} encounter, e = {orbit.eccentricity:.4g}")
    ax.legend()
    return ax
