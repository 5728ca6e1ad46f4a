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


