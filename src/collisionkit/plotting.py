"""Matplotlib helpers; each returns the Axes it drew on.

Not imported by ``collisionkit`` itself (the core needs no matplotlib):
``from collisionkit import plotting``.
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from . import scattering
from .compat.irfpy import binary_collision_stationary


SIGMA_X, SIGMA_Y = r"$x\,/\,\sigma$", r"$y\,/\,\sigma$"  # EDMD lengths: the largest diameter sigma
THERMAL_SPEED = r"$\sqrt{kT/m}$"  # EDMD speeds


def _axes(ax):
    if ax is None:
        _, ax = plt.subplots(figsize=(6, 4), layout="constrained")
    return ax


def _encounter_units(orbit, units):
    """Length and speed scales of an encounter and their unit labels: r_p and v_p, or ``units``."""
    if units is None:
        return orbit.periastron, orbit.periastron_speed, "/ $r_p$", "/ $v_p$"
    from .encounters import unit_system

    system = unit_system(units) if isinstance(units, str) else units
    return 1.0, 1.0, f"({system.length})", f"({system.velocity})"


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


def save(ax, path):
    """Save the figure holding ``ax`` to ``path`` and close it.

    Parameters
    ----------
    ax : matplotlib Axes
        Any axes of the figure to save.
    path : str or Path
        The image file; its suffix (``.png``, ``.pdf``, ``.svg``, ...) sets the format.

    Returns
    -------
    str or Path
        ``path``.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from collisionkit import plotting
    >>> folder = tempfile.TemporaryDirectory()
    >>> path = plotting.save(plotting.plot_deflection_laws(), pathlib.Path(folder.name) / "laws.png")
    >>> path.read_bytes()[1:4]
    b'PNG'
    """
    figure = ax.figure
    figure.savefig(path, dpi=120)
    plt.close(figure)
    return path


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


# ------------------------------------------------------------------ event-driven MD (collisionkit.edmd)


def _eos_points(measurements_or_points):
    """(eta, Z, Z error) rows from Measurement objects or (eta, Z[, error]) tuples."""
    rows = []
    for item in measurements_or_points:
        if hasattr(item, "compressibility_factor"):
            rows.append((item.packing_fraction, item.compressibility_factor, item.compressibility_factor_error))
        else:
            values = tuple(float(value) for value in item)
            if len(values) not in (2, 3):
                raise ValueError(f"each point must be (eta, Z) or (eta, Z, error); got {item!r}")
            rows.append(values if len(values) == 3 else (*values, 0.0))
    if not rows:
        raise ValueError("measurements_or_points must hold at least one measurement or point")
    return np.array(rows, dtype=float)


def plot_equation_of_state(measurements_or_points, dim, ax=None):
    """Measured compressibility factors Z = PV/(NkT) with error bars on the theory curve.

    Parameters
    ----------
    measurements_or_points : sequence
        :class:`collisionkit.edmd.Measurement` objects, or tuples
        ``(eta, Z)`` or ``(eta, Z, error)``.
    dim : {2, 3}
        3: hard spheres against Hansen-Goos (2016) and Carnahan-Starling;
        2: hard discs against Henderson (1975).
    ax : matplotlib Axes, optional

    Returns
    -------
    matplotlib.axes.Axes

    Examples
    --------
    >>> from collisionkit import plotting
    >>> ax = plotting.plot_equation_of_state([(0.2, 2.41, 0.01), (0.4, 6.95, 0.03)], dim=3)
    >>> [text.get_text() for text in ax.get_legend().get_texts()]
    ['Hansen-Goos (2016)', 'Carnahan-Starling', 'EDMD']
    """
    from . import edmd

    if dim not in (2, 3):
        raise ValueError(f"dim must be 2 or 3; got {dim!r}")
    points = _eos_points(measurements_or_points)
    top = max(0.5 if dim == 3 else 0.7, 1.05 * float(points[:, 0].max()))
    eta = np.linspace(1e-3, min(top, 0.74), 300)
    curves = [("Hansen-Goos (2016)", edmd.hansen_goos), ("Carnahan-Starling", edmd.carnahan_starling)]
    ax = _axes(ax)
    for (label, equation), style in zip(curves if dim == 3 else [("Henderson (1975)", edmd.henderson)], ("-", "--")):
        ax.plot(eta, equation(eta), style, color="k" if style == "-" else "0.5", lw=1, label=label)
    ax.errorbar(points[:, 0], points[:, 1], yerr=points[:, 2], fmt="o", color="C3", capsize=3, label="EDMD")
    ax.set_xlabel(r"packing fraction $\eta$")
    ax.set_ylabel(r"$Z = PV/(NkT)$")
    ax.set_title("hard spheres" if dim == 3 else "hard discs")
    ax.legend()
    return ax


def maxwell_boltzmann_speed_density(speed, kT, dim, mass=1.0):
    r"""Maxwell-Boltzmann density of speeds: Maxwell in 3D, Rayleigh in 2D.

    3D: :math:`4\pi v^2 (m/2\pi kT)^{3/2} e^{-mv^2/2kT}`;
    2D: :math:`(mv/kT)\, e^{-mv^2/2kT}`.

    Examples
    --------
    >>> from scipy.integrate import quad
    >>> from collisionkit.plotting import maxwell_boltzmann_speed_density
    >>> round(quad(maxwell_boltzmann_speed_density, 0, 50, args=(2.0, 3))[0], 10)
    1.0
    """
    if dim not in (2, 3):
        raise ValueError(f"dim must be 2 or 3; got {dim!r}")
    if not (kT > 0 and mass > 0):
        raise ValueError(f"kT and mass must be > 0; got kT={kT}, mass={mass}")
    speed = np.asarray(speed, dtype=float)
    boltzmann = np.exp(-mass * speed**2 / (2.0 * kT))
    if dim == 2:
        return mass * speed / kT * boltzmann
    return 4.0 * np.pi * speed**2 * (mass / (2.0 * np.pi * kT)) ** 1.5 * boltzmann


def plot_speed_distribution(speeds, kT, dim, mass=1.0, ax=None):
    """Histogram of speeds against the Maxwell-Boltzmann speed density at ``kT``.

    Parameters
    ----------
    speeds : array_like
        Sampled speeds (e.g. ``Measurement.speeds``).
    kT : float
        Temperature of the reference curve (> 0).
    dim : {2, 3}
        Maxwell distribution in 3D, Rayleigh in 2D.
    mass : float
    ax : matplotlib Axes, optional

    Returns
    -------
    matplotlib.axes.Axes

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit import plotting
    >>> speeds = np.linalg.norm(np.random.default_rng(1).normal(size=(5000, 2)), axis=1)
    >>> ax = plotting.plot_speed_distribution(speeds, kT=1.0, dim=2)
    >>> len(ax.patches) > 10, len(ax.lines)
    (True, 1)
    """
    speeds = np.asarray(speeds, dtype=float).ravel()
    if speeds.size == 0:
        raise ValueError("speeds must hold at least one speed")
    maxwell_boltzmann_speed_density(0.0, kT, dim, mass)  # checks kT, dim and mass
    ax = _axes(ax)
    ax.hist(speeds, bins=min(60, max(10, int(np.sqrt(speeds.size)))), density=True, color="C0", alpha=0.6, label="EDMD")
    v = np.linspace(0.0, max(float(speeds.max()), 4.0 * np.sqrt(kT / mass)), 300)
    law = "Maxwell" if dim == 3 else "Rayleigh (2D Maxwell)"
    ax.plot(v, maxwell_boltzmann_speed_density(v, kT, dim, mass), "k", lw=1.2, label=f"{law}, kT = {kT:.4g}")
    ax.set_xlabel(f"speed $v$ / {THERMAL_SPEED}")
    ax.set_ylabel(f"probability density (1 / {THERMAL_SPEED})")
    ax.legend()
    return ax


def plot_snapshot(positions, radii, box, ax=None):
    """A picture of a hard-sphere configuration drawn to scale.

    2D: every disc. 3D: the cut through the mid-plane z = L_z/2, each sphere
    it crosses drawn as its circular cross-section, coloured by the distance
    of its centre from the plane (with a colour bar). Lengths are labelled in
    units of sigma, the largest diameter (the units of ``collisionkit edmd``).

    Parameters
    ----------
    positions : array_like, shape (N, 2) or (N, 3)
        Centres in the box [0, L), in units of sigma.
    radii : float or array_like, shape (N,)
    box : array_like, shape (d,)
        Box lengths.
    ax : matplotlib Axes, optional

    Returns
    -------
    matplotlib.axes.Axes

    Examples
    --------
    >>> from collisionkit import plotting
    >>> from collisionkit.edmd import lattice
    >>> positions, box = lattice("hexagonal", 6, 0.5)
    >>> ax = plotting.plot_snapshot(positions, 0.5, box)
    >>> len(ax.collections[0].get_offsets())
    72
    >>> cut = plotting.plot_snapshot([[1.0, 1.0, 2.1], [3.0, 3.0, 0.5]], 0.5, [4.0, 4.0, 4.0])
    >>> len(cut.collections[0].get_offsets())  # only the first sphere crosses z = 2
    1
    >>> print(cut.figure.axes[-1].get_ylabel())  # the colour bar
    $|z - L_z/2|\\,/\\,\\sigma$ (depth of the centre)
    """
    from matplotlib.collections import EllipseCollection
    from matplotlib.patches import Rectangle

    positions = np.asarray(positions, dtype=float)
    if positions.ndim != 2 or positions.shape[1] not in (2, 3):
        raise ValueError(f"positions must have shape (N, 2) or (N, 3); got {positions.shape}")
    box = np.asarray(box, dtype=float)
    if box.shape != (positions.shape[1],):
        raise ValueError(f"box must have shape ({positions.shape[1]},); got {box.shape}")
    radii = np.broadcast_to(np.asarray(radii, dtype=float), (positions.shape[0],))
    if positions.shape[1] == 3:
        depth = positions[:, 2] - box[2] / 2.0
        cut = np.abs(depth) < radii
        top, shade = radii.max(), np.abs(depth[cut])
        radii, positions = np.sqrt(radii[cut] ** 2 - depth[cut] ** 2), positions[cut]
    ax = _axes(ax)
    discs = EllipseCollection(
        2 * radii, 2 * radii, np.zeros_like(radii), units="xy", offsets=positions[:, :2],
        offset_transform=ax.transData, cmap="viridis", facecolors="C0", edgecolors="k", linewidths=0.3,
    )  # fmt: skip
    ax.add_collection(discs)
    if box.size == 3:
        discs.set_array(shade)
        discs.set_clim(0.0, top)
        ax.figure.colorbar(discs, ax=ax, label=r"$|z - L_z/2|\,/\,\sigma$ (depth of the centre)", shrink=0.8)
    ax.add_patch(Rectangle((0.0, 0.0), box[0], box[1], fill=False, color="0.3", lw=1))
    ax.set_xlim(-0.05 * box[0], 1.05 * box[0])
    ax.set_ylim(-0.05 * box[1], 1.05 * box[1])
    ax.set_aspect("equal")
    ax.set_xlabel(SIGMA_X)
    ax.set_ylabel(SIGMA_Y)
    kind = f"{len(radii)} discs" if box.size == 2 else f"cut at z = L/2: {len(radii)} spheres"
    ax.set_title(f"snapshot, {kind}")
    return ax


def plot_radial_distribution(r, g, ax=None):
    """The radial distribution function g(r), with the ideal-gas value 1 for reference.

    Parameters
    ----------
    r, g : array_like
        Bin centres and g(r) (e.g. ``Measurement.rdf_r`` and ``Measurement.rdf``).
    ax : matplotlib Axes, optional

    Returns
    -------
    matplotlib.axes.Axes

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit import plotting
    >>> r = np.linspace(0.0, 3.0, 31)
    >>> ax = plotting.plot_radial_distribution(r, np.where(r < 1, 0.0, 1.0))
    >>> len(ax.lines)
    2
    """
    r, g = np.asarray(r, dtype=float), np.asarray(g, dtype=float)
    if r.shape != g.shape:
        raise ValueError(f"r and g must have the same shape; got {r.shape} and {g.shape}")
    ax = _axes(ax)
    ax.plot(r, g, color="C0")
    ax.axhline(1.0, color="0.6", lw=0.8, ls="--")
    ax.set_xlabel(r"distance $r/\sigma$")
    ax.set_ylabel("$g(r)$")
    return ax


# ------------------------------------------------------------------ parameter sweeps (collisionkit.sweep)


def _sweep_label(names, values):
    return ", ".join(f"{name} = {value}" for name, value in zip(names, values))


def plot_sweep(table, x, y, series=(), title=None, theory=None, ax=None):
    """A study's result ``y`` against the varied option ``x``: mean across replicas, standard error bars.

    Parameters
    ----------
    table : sequence of dict
        Rows of a study's ``results.csv`` (e.g. ``StudyResults.table``);
        rows whose ``status`` is not ``"ok"`` are left out.
    x, y : str
        Column of the varied option and of the result.
    series : sequence of str, optional
        Other varied options: one line per combination of their values.
    title : str, optional
    theory : str, optional
        Column of a theoretical value of ``y`` (e.g.
        ``compressibility_factor_theory``), drawn as a dashed line labelled
        "theory" beside the measured points.
    ax : matplotlib Axes, optional

    Returns
    -------
    matplotlib.axes.Axes

    Examples
    --------
    >>> from collisionkit import plotting
    >>> rows = [{"eta": eta, "Z": z, "status": "ok"} for eta, z in [(0.1, 1.5), (0.1, 1.6), (0.2, 2.4), (0.2, 2.5)]]
    >>> ax = plotting.plot_sweep(rows, "eta", "Z")
    >>> ax.get_xlabel(), ax.get_ylabel(), len(ax.containers)
    ('eta', 'Z (mean of replicas)', 1)
    >>> rows = [row | {"Z_theory": {0.1: 1.52, 0.2: 2.43}[row["eta"]]} for row in rows]
    >>> ax = plotting.plot_sweep(rows, "eta", "Z", theory="Z_theory")
    >>> [text.get_text() for text in ax.get_legend().get_texts()]
    ['theory', 'measured']
    """
    from .sweep import aggregate

    series = list(series)
    points = aggregate(table, y, [*series, x])
    if not points:
        raise ValueError(f"table has no successful row with a finite {y!r}")
    groups = {}
    for point in points:
        groups.setdefault(tuple(point[name] for name in series), []).append(point)
    expected = {}
    for point in aggregate(table, theory, [*series, x]) if theory else []:
        expected.setdefault(tuple(point[name] for name in series), []).append(point)
    ax = _axes(ax)
    for values, group in groups.items():
        errors = np.nan_to_num(np.array([point["error"] for point in group], dtype=float))
        label = _sweep_label(series, values) or ("measured" if expected else None)
        bars = ax.errorbar([point[x] for point in group], [point["mean"] for point in group], yerr=errors,
                           fmt="o-", capsize=3, label=label)  # fmt: skip
        if values in expected:
            line = [(point[x], point["mean"]) for point in expected[values]]
            colour = bars.lines[0].get_color() if series else "k"
            ax.plot(*zip(*line), "--", color=colour, lw=1, label=f"{label}, theory" if series else "theory")
    ax.set_xlabel(x)
    ax.set_ylabel(f"{y} (mean of replicas)")
    if title is not None:
        ax.set_title(title)
    if series or expected:
        ax.legend(fontsize="small")
    return ax


# ------------------------------------------------------------------ animations (collisionkit animate)

COLOUR_MODES = ("none", "speed", "species")
ANIMATION_FORMATS = (".gif", ".mp4")


def _check_colour(colour_by):
    if colour_by is None:
        return "none"
    if colour_by not in COLOUR_MODES:
        raise ValueError(f"colour_by must be one of {COLOUR_MODES}; got {colour_by!r}")
    return colour_by


def _figure_axes(ax):
    if ax is None:
        _, ax = plt.subplots(figsize=(5, 5), layout="constrained")
    return ax


def _freeze_layout(ax, created):
    """Lay out a figure we created once, then keep it: frames draw about twice as fast."""
    if created:
        ax.figure.canvas.draw()
        ax.figure.set_layout_engine("none")


def _frame_discs(frame):
    """Centres (n, 2), diameters (n,), speeds (n,) and type ids (n,) drawn for one frame.

    2D: every disc. 3D: the cut through the mid-plane z = L_z/2, as in :func:`plot_snapshot`.
    """
    positions = np.asarray(frame["positions"], dtype=float)
    if positions.ndim != 2 or positions.shape[1] not in (2, 3):
        raise ValueError(f"frame positions must have shape (N, 2) or (N, 3); got {positions.shape}")
    count = positions.shape[0]
    diameters = np.broadcast_to(np.asarray(frame.get("diameters", 1.0), dtype=float), (count,))
    velocities = frame.get("velocities")
    speeds = np.zeros(count) if velocities is None else np.linalg.norm(np.asarray(velocities, dtype=float), axis=-1)
    typeids = np.broadcast_to(np.asarray(frame.get("typeids", 0), dtype=int), (count,))
    if positions.shape[1] == 3:
        depth = positions[:, 2] - float(np.asarray(frame["box"], dtype=float)[2]) / 2.0
        cut = np.abs(depth) < diameters / 2.0
        diameters = 2.0 * np.sqrt(diameters[cut] ** 2 / 4.0 - depth[cut] ** 2)
        positions, speeds, typeids = positions[cut], speeds[cut], typeids[cut]
    return positions[:, :2], diameters, speeds, typeids


def animate_frames(frames, colour_by="speed", interval=50, ax=None):
    """Animate hard-sphere frames (as :func:`collisionkit.trajectory.read_gsd` returns them).

    Each frame is drawn to scale like :func:`plot_snapshot`: every disc in
    2D, the cut through the mid-plane z = L_z/2 in 3D.

    Parameters
    ----------
    frames : sequence of dict
        Each with ``positions`` (N, d) in [0, L) and ``box`` (d,); optional
        ``diameters`` (N,) (default 1), ``velocities`` (N, d) (needed for
        colouring by speed), ``typeids`` (N,) and ``step``.
    colour_by : {"speed", "species", "none"}
        Colour each particle by its speed (viridis, one scale for the whole
        animation, with a colour bar) or by its species (type id, with a
        legend). Lengths are labelled in sigma, speeds in sqrt(kT/m).
    interval : float
        Milliseconds between frames when shown on screen.
    ax : matplotlib Axes, optional

    Returns
    -------
    matplotlib.animation.FuncAnimation
        Save it with :func:`save_animation`; in Jupyter show it with
        ``IPython.display.HTML(animation.to_jshtml())``.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit import plotting
    >>> frames = [{"positions": np.array([[1.0 + t, 2.0], [3.0, 2.0]]), "box": np.array([5.0, 4.0]),
    ...            "velocities": np.array([[1.0, 0.0], [0.0, 0.0]]), "step": t} for t in range(3)]
    >>> animation = plotting.animate_frames(frames, colour_by="speed")
    >>> animation._fig.axes[0].get_title()
    'step 0'
    >>> import tempfile, pathlib
    >>> folder = tempfile.TemporaryDirectory()
    >>> plotting.save_animation(animation, pathlib.Path(folder.name) / "two.gif", fps=2, dpi=30).stat().st_size > 0
    True
    """
    from matplotlib.animation import FuncAnimation
    from matplotlib.collections import EllipseCollection
    from matplotlib.patches import Rectangle

    colour_by = _check_colour(colour_by)
    frames = list(frames)
    if not frames:
        raise ValueError("frames must hold at least one frame")
    if colour_by == "speed" and any(frame.get("velocities") is None for frame in frames):
        raise ValueError("colour_by='speed' needs 'velocities' in every frame")
    box = np.asarray(frames[0]["box"], dtype=float)
    drawn = [_frame_discs(frame) for frame in frames]
    created = ax is None
    ax = _figure_axes(ax)
    palette = plt.get_cmap("tab10").colors

    def discs(index):
        centres, diameters, speeds, typeids = drawn[index]
        return centres, diameters, speeds, typeids

    centres, diameters, speeds, typeids = discs(0)
    collection = EllipseCollection(
        diameters, diameters, np.zeros_like(diameters), units="xy", offsets=centres,
        offset_transform=ax.transData, edgecolors="k", linewidths=0.3, cmap="viridis",
    )  # fmt: skip
    if colour_by == "speed":
        top = max((float(item[2].max()) for item in drawn if item[2].size), default=1.0)
        collection.set_clim(0.0, top if top > 0 else 1.0)
        collection.set_array(speeds)
        ax.figure.colorbar(collection, ax=ax, label=f"speed / {THERMAL_SPEED}", shrink=0.8)
    elif colour_by == "species":
        from matplotlib.patches import Patch

        species = np.unique(np.concatenate([item[3] for item in drawn]))
        handles = [Patch(facecolor=palette[typeid % len(palette)], edgecolor="k", label=f"species {typeid}")
                   for typeid in species]  # fmt: skip
        ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize="small")
    ax.add_collection(collection)
    ax.add_patch(Rectangle((0.0, 0.0), box[0], box[1], fill=False, color="0.3", lw=1))
    ax.set_xlim(-0.05 * box[0], 1.05 * box[0])
    ax.set_ylim(-0.05 * box[1], 1.05 * box[1])
    ax.set_aspect("equal")
    ax.set_xlabel(SIGMA_X)
    ax.set_ylabel(SIGMA_Y)

    def update(index):
        centres, diameters, speeds, typeids = discs(index)
        collection.set_offsets(centres if len(centres) else np.empty((0, 2)))
        collection.set_widths(diameters)
        collection.set_heights(diameters)
        collection.set_angles(np.zeros_like(diameters))
        if colour_by == "speed":
            collection.set_array(speeds)
        elif colour_by == "species":
            collection.set_facecolors([palette[typeid % len(palette)] for typeid in typeids])
        else:
            collection.set_facecolors("C0")
        step = frames[index].get("step", index)
        ax.set_title(f"step {step}" + (" (cut at z = L/2)" if box.size == 3 else ""))
        return (collection,)

    update(0)
    _freeze_layout(ax, created)
    return FuncAnimation(ax.figure, update, frames=len(frames), interval=interval, blit=False)


def animate_gsd(path, colour_by="speed", every=1, max_frames=None, interval=50, ax=None):
    """Animate an EDMD trajectory stored as a GSD file (``collisionkit edmd --trajectory``).

    Parameters
    ----------
    path : str or Path
        The ``.gsd`` file (needs the ``gsd`` package).
    colour_by : {"speed", "species", "none"}
    every : int
        Use every ``every``-th frame (>= 1).
    max_frames : int, optional
        Use at most this many frames (the first ones).
    interval : float
        Milliseconds between frames on screen.
    ax : matplotlib Axes, optional

    Returns
    -------
    matplotlib.animation.FuncAnimation

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from collisionkit import plotting
    >>> from collisionkit.edmd import random_fluid
    >>> from collisionkit.trajectory import GSDWriter
    >>> folder = tempfile.TemporaryDirectory()
    >>> path = pathlib.Path(folder.name) / "run.gsd"
    >>> system = random_fluid(2, 30, 0.3, seed=1)
    >>> with GSDWriter(path) as writer:
    ...     for step in range(3):
    ...         _ = system.run(collisions=20)
    ...         writer.write(system, step=20 * step)
    >>> animation = plotting.animate_gsd(path, colour_by="species", every=2)
    >>> animation._fig.axes[0].get_title()
    'step 0'
    >>> plotting.save_animation(animation, pathlib.Path(folder.name) / "run.gif", fps=2, dpi=30).suffix
    '.gif'
    """
    from .trajectory import read_gsd

    if not (isinstance(every, (int, np.integer)) and every >= 1):
        raise ValueError(f"every must be an integer >= 1; got {every!r}")
    if max_frames is not None and not (isinstance(max_frames, (int, np.integer)) and max_frames >= 1):
        raise ValueError(f"max_frames must be an integer >= 1 or None; got {max_frames!r}")
    first = read_gsd(path, frame=0)
    indices = list(range(0, first["frames"], every))[:max_frames]
    frames = [first] + [read_gsd(path, frame=index) for index in indices[1:]]
    return animate_frames(frames, colour_by=colour_by, interval=interval, ax=ax)


def animate_encounter(orbit, frames=120, max_separation=None, colour_by="speed", interval=50, units=None, ax=None):
    """Animate a two-body encounter in the centre-of-mass frame, with trails.

    Drawn in the orbital plane as in :func:`plot_encounter`; the frames are
    evenly spaced in time, so the bodies visibly speed up near periastron.

    Parameters
    ----------
    orbit : collisionkit.encounters.TwoBodyOrbit or InitialConditions
        Initial conditions run from the start (separation sep0) to the same
        separation after periastron.
    frames : int
        Number of frames (>= 2).
    max_separation : float, optional
        For an orbit: start and end at this separation (default 10 r_p); a
        bound orbit is shown over one period.
    colour_by : {"speed", "species", "none"}
        Speed of each body in the centre-of-mass frame (viridis, with a
        colour bar), or body 1 / body 2 in two colours.
    interval : float
        Milliseconds between frames on screen.
    units : collisionkit.encounters.UnitSystem or str, optional
        The unit system the orbit is in. Default: lengths in units of the
        periastron distance r_p, speeds in units of the periastron speed v_p.
    ax : matplotlib Axes, optional

    Returns
    -------
    matplotlib.animation.FuncAnimation

    Examples
    --------
    >>> from collisionkit import plotting
    >>> from collisionkit.encounters import starcrash_initial_conditions
    >>> ic = starcrash_initial_conditions(1.0, 0.5, rp=1.0, vinf=0.5, sep0=10.0)
    >>> animation = plotting.animate_encounter(ic, frames=3, colour_by="species")
    >>> animation._fig.axes[0].get_title()
    't = -11.16'
    >>> import tempfile, pathlib
    >>> folder = tempfile.TemporaryDirectory()
    >>> plotting.save_animation(animation, pathlib.Path(folder.name) / "flyby.gif", fps=2, dpi=30).suffix
    '.gif'
    """
    from matplotlib.animation import FuncAnimation

    colour_by = _check_colour(colour_by)
    if not (isinstance(frames, (int, np.integer)) and frames >= 2):
        raise ValueError(f"frames must be an integer >= 2; got {frames!r}")
    if hasattr(orbit, "orbit"):  # InitialConditions
        start, end = -orbit.time_to_periastron, orbit.time_to_periastron
        orbit = orbit.orbit
    elif orbit.kind == "elliptic":
        start, end = -0.5 * orbit.period, 0.5 * orbit.period
    else:
        reach = 10.0 * orbit.periastron if max_separation is None else max_separation
        end = orbit.time_at_separation(max(reach, orbit.periastron), branch="outbound")
        start = -end
    times = np.linspace(start, end, frames)
    positions, velocities = orbit.state_at_time(times)
    length, speed, length_unit, speed_unit = _encounter_units(orbit, units)
    plane = orbit.basis[:2].T
    xy = positions @ plane / length  # (frames, 2 bodies, 2)
    speeds = np.linalg.norm(velocities, axis=-1) / speed
    created = ax is None
    ax = _figure_axes(ax)
    trail_colours = ("C0", "C1") if colour_by == "species" else ("0.6", "0.6")
    trails = [ax.plot([], [], "-", color=colour, lw=1)[0] for colour in trail_colours]
    kwargs = {"s": 80, "edgecolors": "k", "zorder": 3}
    if colour_by == "speed":
        bodies = ax.scatter(xy[0, :, 0], xy[0, :, 1], c=speeds[0], cmap="viridis", vmin=0.0,
                            vmax=float(speeds.max()), **kwargs)  # fmt: skip
        ax.figure.colorbar(bodies, ax=ax, label=f"speed, centre-of-mass frame {speed_unit}", shrink=0.8)
    else:
        colours = ["C0", "C1"] if colour_by == "species" else ["0.3", "0.3"]
        bodies = ax.scatter(xy[0, :, 0], xy[0, :, 1], c=colours, **kwargs)
    ax.plot(0.0, 0.0, "k+", ms=8)
    span = float(np.abs(xy).max()) * 1.08
    ax.set_xlim(-span, span)
    ax.set_ylim(-span, span)
    ax.set_aspect("equal")
    ax.set_xlabel(f"x towards periastron {length_unit}")
    ax.set_ylabel(f"y along the periastron velocity {length_unit}")

    def update(index):
        for body, trail in enumerate(trails):
            trail.set_data(xy[: index + 1, body, 0], xy[: index + 1, body, 1])
        bodies.set_offsets(xy[index])
        if colour_by == "speed":
            bodies.set_array(speeds[index])
        ax.set_title(f"t = {times[index]:.4g}")
        return (bodies, *trails)

    update(0)
    _freeze_layout(ax, created)
    return FuncAnimation(ax.figure, update, frames=frames, interval=interval, blit=False)


def ffmpeg_available():
    """Whether matplotlib can write MP4 files (an ``ffmpeg`` program it can run).

    A system ``ffmpeg`` is used where installed; otherwise the binary that the
    ``imageio-ffmpeg`` package ships (part of the ``plot`` extra) is handed to
    matplotlib.

    Examples
    --------
    >>> from collisionkit.plotting import ffmpeg_available
    >>> ffmpeg_available() in (True, False)
    True
    """
    from matplotlib import animation

    if animation.writers.is_available("ffmpeg"):
        return True
    try:
        import imageio_ffmpeg
    except ImportError:
        return False
    plt.rcParams["animation.ffmpeg_path"] = imageio_ffmpeg.get_ffmpeg_exe()
    return bool(animation.writers.is_available("ffmpeg"))


def save_animation(animation, path, fps=20, dpi=80, progress=None):
    """Write an animation to a GIF (Pillow) or MP4 (ffmpeg) file and close its figure.

    Parameters
    ----------
    animation : matplotlib.animation.Animation
        E.g. from :func:`animate_gsd`, :func:`animate_frames` or :func:`animate_encounter`.
    path : str or Path
        Ends in ``.gif`` (needs only Pillow, which matplotlib installs) or
        ``.mp4`` (needs the ``ffmpeg`` program).
    fps : int
        Frames per second, 1 to 60.
    dpi : int
        Resolution of the frames.
    progress : callable, optional
        Called as ``progress(frame_index, total_frames)`` after each frame.

    Returns
    -------
    Path
        The file written.

    Raises
    ------
    ValueError
        For another suffix or fps out of range.
    RuntimeError
        For ``.mp4`` when ffmpeg is not installed.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from collisionkit import plotting
    >>> from collisionkit.encounters import Hyperbolic
    >>> folder = tempfile.TemporaryDirectory()
    >>> animation = plotting.animate_encounter(Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1.0), frames=4)
    >>> path = plotting.save_animation(animation, pathlib.Path(folder.name) / "flyby.gif", fps=5, dpi=40)
    >>> path.read_bytes()[:6]
    b'GIF89a'
    """
    from pathlib import Path

    from matplotlib import animation as mpl_animation

    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in ANIMATION_FORMATS:
        raise ValueError(f"path must end in .gif or .mp4; got {str(path)!r}")
    if not (isinstance(fps, (int, np.integer)) and 1 <= fps <= 60):
        raise ValueError(f"fps must be an integer from 1 to 60; got {fps!r}")
    if suffix == ".mp4":
        if not ffmpeg_available():
            raise RuntimeError("writing MP4 needs the ffmpeg program, which is not installed; write a .gif instead")
        writer = mpl_animation.FFMpegWriter(fps=fps)
    else:
        writer = mpl_animation.PillowWriter(fps=fps)
    path.parent.mkdir(parents=True, exist_ok=True)
    callback = None if progress is None else (lambda index, total: progress(index, total))
    try:
        animation.save(str(path), writer=writer, dpi=dpi, progress_callback=callback)
    finally:
        plt.close(animation._fig)
    return path


# ------------------------------------------------------------------ Monte Carlo transport

# Reid's ramp, LoKI-MC (Dias et al., Comput. Phys. Commun. 282, 108554 (2023), Table 1):
# E/N (Td), mean energy (eV), bulk W (m/s), N D_T, N D_L (1/m/s)
REID_PUBLISHED = (
    (1.0, 0.1014, 1.264e4, 0.9637e24, 0.7542e24),
    (12.0, 0.2691, 6.838e4, 1.137e24, 0.5679e24),
    (24.0, 0.4081, 8.881e4, 1.138e24, 0.4595e24),
)


def plot_energy_distribution(results, ax=None):
    """Energy distribution functions f(eps) (per eV, area 1) of swarm results.

    Examples
    --------
    >>> import numpy as np
    >>> from types import SimpleNamespace
    >>> from collisionkit import plotting
    >>> r = SimpleNamespace(eedf_energy=np.linspace(0.05, 1, 20), eedf=np.ones(20), reduced_field=12.0)
    >>> ax = plotting.plot_energy_distribution([r])
    >>> ax.get_xlabel()
    'energy (eV)'
    """
    ax = _axes(ax)
    for r in results:
        ax.plot(r.eedf_energy, r.eedf, label=f"E/N = {r.reduced_field:g} Td")
    ax.set_xlabel("energy (eV)")
    ax.set_ylabel("f(energy) (1/eV)")
    ax.legend()
    return ax


def plot_transport_coefficients(results, reference=REID_PUBLISHED, axes=None):
    """Mean energy, |bulk W|, N D_L and N D_T against E/N with error bars (and published Reid points).

    Pass ``reference=()`` for gases other than Reid's ramp. Returns the 2 x 2 array of Axes.

    Examples
    --------
    >>> import numpy as np
    >>> from types import SimpleNamespace
    >>> from collisionkit import plotting
    >>> r = SimpleNamespace(reduced_field=12.0, mean_energy=0.27, mean_energy_error=1e-4,
    ...     drift_velocity_bulk=np.array([0, 0, -6.8e4]), drift_velocity_bulk_error=np.array([0, 0, 10.0]),
    ...     diffusion_L_N=5.7e23, diffusion_L_N_error=1e22, diffusion_T_N=1.1e24, diffusion_T_N_error=1e22)
    >>> axes = plotting.plot_transport_coefficients([r])
    >>> axes.shape
    (2, 2)
    """
    if axes is None:
        _, axes = plt.subplots(2, 2, figsize=(9, 6), layout="constrained")
    e_n = [r.reduced_field for r in results]
    series = (
        ("mean energy (eV)", [r.mean_energy for r in results], [r.mean_energy_error for r in results], 1),
        ("|bulk W| (m/s)", [abs(r.drift_velocity_bulk[2]) for r in results],
         [r.drift_velocity_bulk_error[2] for r in results], 2),
        ("N D_L (1/m/s)", [r.diffusion_L_N for r in results], [r.diffusion_L_N_error for r in results], 4),
        ("N D_T (1/m/s)", [r.diffusion_T_N for r in results], [r.diffusion_T_N_error for r in results], 3),
    )
    for ax, (label, values, errors, column) in zip(axes.flat, series):
        ax.errorbar(e_n, values, yerr=errors, fmt="o-", label="collisionkit")
        if reference:
            ax.plot([row[0] for row in reference], [row[column] for row in reference], "s", mfc="none",
                    label="LoKI-MC (Reid)")
        ax.set_xlabel("E/N (Td)")
        ax.set_ylabel(label)
        ax.legend()
    return axes


def plot_trajectories(positions, ax=None):
    """Sample trajectories (x, z) of swarm particles, ``positions`` of shape (points, particles, 3) in m.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit import plotting
    >>> ax = plotting.plot_trajectories(np.cumsum(np.ones((10, 2, 3)), axis=0))
    >>> len(ax.lines)
    2
    """
    ax = _axes(ax)
    positions = np.asarray(positions)
    for k in range(positions.shape[1]):
        ax.plot(positions[:, k, 0] * 1e6, positions[:, k, 2] * 1e6, lw=0.8)
    ax.set_xlabel("x (µm)")
    ax.set_ylabel("z (µm)")
    ax.set_aspect("equal", adjustable="datalim")
    return ax
