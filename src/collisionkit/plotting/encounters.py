"""Figures of two-body encounters (:mod:`collisionkit.encounters`) and their length and speed units."""

from __future__ import annotations

import numpy as np

from ._common import _axes


def _encounter_units(orbit, units):
    """Length and speed scales of an encounter and their unit labels: r_p and v_p, or ``units``."""
    if units is None:
        return orbit.periastron, orbit.periastron_speed, "/ $r_p$", "/ $v_p$"
    from ..encounters import unit_system

    system = unit_system(units) if isinstance(units, str) else units
    return 1.0, 1.0, f"({system.length})", f"({system.velocity})"




def plot_encounter(orbit, max_separation=None, points=400, units=None, ax=None):
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
    units : collisionkit.encounters.UnitSystem or str, optional
        The unit system the orbit is in: lengths are drawn in its length
        unit. Default: in units of the periastron distance r_p.
    ax : matplotlib Axes, optional

    Returns
    -------
    matplotlib.axes.Axes

    Examples
    --------
    >>> from collisionkit import plotting
    >>> from collisionkit.encounters import Hyperbolic
    >>> ax = plotting.plot_encounter(Hyperbolic(1.0, 2.0, periastron=1.0, v_inf=1.0))
    >>> len(ax.lines)  # 2 trajectories, 2 periastra, 4 asymptotes, centre of mass
    9
    >>> ax.get_xlabel()
    'x towards periastron / $r_p$'
    >>> plotting.plot_encounter(Hyperbolic(1.0, 2.0, periastron=1.0, v_inf=1.0), units="solar").get_xlabel()
    'x towards periastron (AU)'
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
    scale, _, unit, _ = _encounter_units(orbit, units)
    positions = orbit.state_at_time(times)[0] / scale
    plane = orbit.basis[:2].T  # columns P, Q
    shares = (-orbit.m2 / orbit.total_mass, orbit.m1 / orbit.total_mass)
    ax = _axes(ax)
    for body, (share, colour) in enumerate(zip(shares, ("C0", "C1"))):
        xy = positions[:, body] @ plane
        ax.plot(xy[:, 0], xy[:, 1], color=colour, label=f"body {body + 1}")
        ax.plot(share * orbit.periastron / scale, 0.0, "o", color=colour, ms=5)
    if orbit.kind == "hyperbolic":
        incoming, outgoing, centre = (vector @ plane for vector in orbit.asymptotes())
        centre = centre / scale
        reach = float(np.max(np.linalg.norm(positions[:, 1] - positions[:, 0], axis=-1)))
        length = np.array([0.0, reach + float(np.linalg.norm(centre))])
        for share, colour in zip(shares, ("C0", "C1")):
            for direction, sign in ((outgoing, 1.0), (incoming, -1.0)):
                line = share * (centre + sign * length[:, None] * direction)
                ax.plot(line[:, 0], line[:, 1], "--", color=colour, lw=0.8)
    ax.plot(0.0, 0.0, "k+", ms=8)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel(f"x towards periastron {unit}")
    ax.set_ylabel(f"y along the periastron velocity {unit}")
    ax.set_title(f"{orbit.kind} encounter, e = {orbit.eccentricity:.4g}")
    ax.legend()
    return ax


def plot_star_encounter(initial_conditions, stars, units=None, max_points=4000, ax=None):
    """Two particle stars at their start on the encounter's orbit, with the asymptotes.

    The centres of mass' trajectories and asymptotes as :func:`plot_encounter`
    draws them, and each star's particles at the start (body 1 in blue, body 2
    in orange), projected on the orbital plane.

    Parameters
    ----------
    initial_conditions : collisionkit.encounters.InitialConditions
        The two-body set-up the stars were placed on.
    stars : collisionkit.encounters.StarModel
        The placed pair (``star_ids`` 1 and 2), in the units of the set-up.
    units : collisionkit.encounters.UnitSystem or str, optional
        As in :func:`plot_encounter`: draw in its length unit (default: in r_p).
    max_points : int
        At most this many particles of each star are drawn (every k-th).
    ax : matplotlib Axes, optional

    Returns
    -------
    matplotlib.axes.Axes

    Examples
    --------
    >>> from collisionkit import plotting
    >>> from collisionkit.encounters import StarEncounterParameters, polytrope_star, star_encounter_summary
    >>> star = polytrope_star(1.5, 300, neighbours=10, seed=1)
    >>> _, ic, pair = star_encounter_summary(star, star, StarEncounterParameters(sep0=20.0))
    >>> ax = plotting.plot_star_encounter(ic, pair)
    >>> len(ax.collections), ax.get_legend_handles_labels()[1][2:]
    (2, ['star 1 (300 particles)', 'star 2 (300 particles)'])
    """
    if stars.star_ids is None:
        raise ValueError("stars must be a placed pair (star_ids 1 and 2), as place_stars gives")
    ax = plot_encounter(initial_conditions, units=units, ax=ax)
    orbit = initial_conditions.orbit
    scale = _encounter_units(orbit, units)[0]
    plane = orbit.basis[:2].T
    for number, colour in ((1, "C0"), (2, "C1")):
        mine = stars.positions[stars.star_ids == number]
        step = max(1, -(-len(mine) // max_points))
        xy = mine[::step] @ plane / scale
        ax.scatter(xy[:, 0], xy[:, 1], s=1.5, color=colour, alpha=0.5, linewidths=0,
                   label=f"star {number} ({len(mine)} particles)")
    ax.set_title(f"two stars at sep0 = {initial_conditions.sep0:.4g}, e = {orbit.eccentricity:.4g}")
    ax.legend(markerscale=4)
    return ax

