"""Figures of event-driven hard-sphere dynamics (:mod:`collisionkit.edmd`).

Equation of state, speed distribution, snapshots, the radial distribution function, the Einstein-Helfand
curves of the transport coefficients with their fits, and the cooling of a granular gas.
"""

from __future__ import annotations

import numpy as np

import matplotlib.pyplot as plt

from ._common import SIGMA_X, SIGMA_Y, THERMAL_SPEED, _axes


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


def plot_equation_of_state(measurements_or_points, dim, ax=None, mixture=None):
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
    mixture : (fractions, diameters), optional
        A mixture's number fractions and diameters: the curve is then its
        equation of state (BMCSL for spheres, SYH for discs:
        :func:`~collisionkit.edmd.mixture_compressibility`).

    Returns
    -------
    matplotlib.axes.Axes

    Examples
    --------
    >>> from collisionkit import plotting
    >>> ax = plotting.plot_equation_of_state([(0.2, 2.41, 0.01), (0.4, 6.95, 0.03)], dim=3)
    >>> [text.get_text() for text in ax.get_legend().get_texts()]
    ['Hansen-Goos (2016)', 'Carnahan-Starling', 'EDMD']
    >>> ax = plotting.plot_equation_of_state([(0.3, 3.5, 0.02)], dim=3, mixture=([0.5, 0.5], [1.0, 0.5]))
    >>> [text.get_text() for text in ax.get_legend().get_texts()]
    ['BMCSL (Mansoori et al. 1971)', 'EDMD']
    """
    from ..edmd import MAX_PACKING_FRACTION, carnahan_starling, hansen_goos, henderson, mixture_compressibility

    if dim not in (2, 3):
        raise ValueError(f"dim must be 2 or 3; got {dim!r}")
    measurements_or_points = list(measurements_or_points)
    for index, item in enumerate(measurements_or_points):
        if getattr(item, "dim", dim) != dim:
            raise ValueError(f"measurement {index} is of a {item.dim}-D system; dim is {dim}: plot each "
                             "dimension against its own theory")
    points = _eos_points(measurements_or_points)
    top = max(MAX_PACKING_FRACTION[dim], 1.05 * float(points[:, 0].max()))
    eta = np.linspace(1e-3, min(top, 0.74), 300)
    curves = [("Hansen-Goos (2016)", hansen_goos), ("Carnahan-Starling", carnahan_starling)]
    if dim == 2:
        curves = [("Henderson (1975)", henderson)]
    if mixture is not None:
        from ..edmd import MIXTURE_EQUATION_OF_STATE

        fractions, diameters = mixture
        mixture_compressibility(0.0, fractions, diameters, dim)  # checks the species before drawing
        curves = [(MIXTURE_EQUATION_OF_STATE[dim], np.vectorize(
            lambda value: mixture_compressibility(value, fractions, diameters, dim)))]
    ax = _axes(ax)
    for (label, equation), style in zip(curves, ("-", "--")):
        ax.plot(eta, equation(eta), style, color="k" if style == "-" else "0.5", lw=1, label=label)
    ax.errorbar(points[:, 0], points[:, 1], yerr=points[:, 2], fmt="o", color="C3", capsize=3, label="EDMD")
    ax.set_xlabel(r"packing fraction $\eta$")
    ax.set_ylabel(r"$Z = PV/(NkT)$")
    ax.set_title(("hard spheres" if dim == 3 else "hard discs") + ("" if mixture is None else ", mixture"))
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


def plot_speed_distribution(speeds, kT, dim, mass=1.0, ax=None, fractions=None):
    """Histogram of speeds against the Maxwell-Boltzmann speed density at ``kT``.

    Parameters
    ----------
    speeds : array_like
        Sampled speeds (e.g. ``Measurement.speeds``).
    kT : float
        Temperature of the reference curve (> 0).
    dim : {2, 3}
        Maxwell distribution in 3D, Rayleigh in 2D.
    mass : float or sequence of float
        The particles' mass, or one per species of a mixture (with ``fractions``).
    ax : matplotlib Axes, optional
    fractions : sequence of float, optional
        A mixture's number fractions, one per ``mass``: the curve is then
        the sum over species of x_i f(v; m_i), each at ``kT``.

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
    >>> ax = plotting.plot_speed_distribution(speeds, kT=1.0, dim=2, mass=[1.0, 4.0], fractions=[0.5, 0.5])
    >>> ax.get_legend().get_texts()[1].get_text()
    'Rayleigh (2D Maxwell), mixture, kT = 1'
    """
    speeds = np.asarray(speeds, dtype=float).ravel()
    if speeds.size == 0:
        raise ValueError("speeds must hold at least one speed")
    masses = np.atleast_1d(np.asarray(mass, dtype=float))
    weights = np.ones(1) if fractions is None else np.asarray(fractions, dtype=float)
    if masses.ndim != 1 or weights.shape != masses.shape or not np.all(weights > 0):
        raise ValueError(f"mass must be a number, or one per species with fractions (> 0) of the same length; got "
                         f"mass {mass!r}, fractions {fractions!r}")
    for each in masses:
        maxwell_boltzmann_speed_density(0.0, kT, dim, float(each))  # checks kT, dim and the masses
    ax = _axes(ax)
    ax.hist(speeds, bins=min(60, max(10, int(np.sqrt(speeds.size)))), density=True, color="C0", alpha=0.6, label="EDMD")
    v = np.linspace(0.0, max(float(speeds.max()), 4.0 * np.sqrt(kT / masses.min())), 300)
    law = "Maxwell" if dim == 3 else "Rayleigh (2D Maxwell)"
    density = sum(w * maxwell_boltzmann_speed_density(v, kT, dim, float(m)) for w, m in zip(weights / weights.sum(),
                                                                                          masses))
    ax.plot(v, density, "k", lw=1.2, label=f"{law}{'' if fractions is None else ', mixture'}, kT = {kT:.4g}")
    ax.set_xlabel(f"speed $v$ / {THERMAL_SPEED}")
    ax.set_ylabel(f"probability density (1 / {THERMAL_SPEED})")
    ax.legend()
    return ax


def plot_snapshot(positions, radii, box, ax=None, species=None):
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
    species : array_like of int, shape (N,), optional
        2D: each disc coloured by its species (C0, C1, ...; 3D keeps the depth's colours).

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
    >>> mixed = plotting.plot_snapshot(positions, 0.5, box, species=[0, 1] * 36)
    >>> mixed.collections[0].get_facecolors()[:2].round(2).tolist()  # C0 and C1
    [[0.12, 0.47, 0.71, 1.0], [1.0, 0.5, 0.05, 1.0]]
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
    faces = "C0"
    if species is not None and positions.shape[1] == 2:
        species = np.asarray(species)
        if species.shape != (positions.shape[0],):
            raise ValueError(f"species must have shape ({positions.shape[0]},); got {species.shape}")
        faces = [f"C{int(kind) % 10}" for kind in species]
    if positions.shape[1] == 3:
        depth = positions[:, 2] - box[2] / 2.0
        cut = np.abs(depth) < radii
        top, shade = radii.max(), np.abs(depth[cut])
        radii, positions = np.sqrt(radii[cut] ** 2 - depth[cut] ** 2), positions[cut]
    ax = _axes(ax)
    discs = EllipseCollection(
        2 * radii, 2 * radii, np.zeros_like(radii), units="xy", offsets=positions[:, :2],
        offset_transform=ax.transData, cmap="viridis", facecolors=faces, edgecolors="k", linewidths=0.3,
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


def plot_radial_distribution(r, g, ax=None, partial=None):
    """The radial distribution function g(r), with the ideal-gas value 1 for reference.

    Parameters
    ----------
    r, g : array_like
        Bin centres and g(r) (e.g. ``Measurement.rdf_r`` and ``Measurement.rdf``).
    ax : matplotlib Axes, optional
    partial : array_like, shape (S, S, len(r)), optional
        A mixture's partial g_ab(r) (``Measurement.partial_rdf``): drawn
        instead of g, one line for each pair of species a <= b (A-A, A-B, ...).

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
    >>> ax = plotting.plot_radial_distribution(r, np.ones(31), partial=np.ones((2, 2, 31)))
    >>> [text.get_text() for text in ax.get_legend().get_texts()]
    ['A-A', 'A-B', 'B-B']
    """
    from ..trajectory import type_names

    r, g = np.asarray(r, dtype=float), np.asarray(g, dtype=float)
    if r.shape != g.shape:
        raise ValueError(f"r and g must have the same shape; got {r.shape} and {g.shape}")
    ax = _axes(ax)
    if partial is None:
        ax.plot(r, g, color="C0")
    else:
        partial = np.asarray(partial, dtype=float)
        if partial.ndim != 3 or partial.shape[0] != partial.shape[1] or partial.shape[2] != r.size:
            raise ValueError(f"partial must have shape (S, S, {r.size}); got {partial.shape}")
        names = type_names(np.arange(len(partial)))
        for a, b in zip(*np.triu_indices(len(partial))):
            ax.plot(r, partial[a, b], label=f"{names[a]}-{names[b]}")
        ax.legend()
    ax.axhline(1.0, color="0.6", lw=0.8, ls="--")
    ax.set_xlabel(r"distance $r/\sigma$")
    ax.set_ylabel("$g(r)$" if partial is None else "$g_{ab}(r)$")
    return ax


def plot_cooling(collisions, temperatures, rate=None, species=None, ax=None, species_theory=None,
                 theory_temperatures=None, rotation=None, theory_rotation=None, homogeneity_lost_after=None):
    """kT of a cooling gas against collisions per particle (log scale), with the theory's line and each species'.

    Parameters
    ----------
    collisions : array_like, shape (K,)
        Collisions per particle C (2 per pair collision / N) at the block ends.
    temperatures : array_like, shape (K,)
        kT there (e.g. ``Measurement.block_temperature``).
    rate : float, optional
        The theory's -d ln T / dC (``cooling_rate_theory``: Haff's (1 - e^2) / d
        for one species): drawn as the line through the first point.
    species : array_like, shape (K, S), optional
        A mixture's T_a / T at the block ends
        (``Measurement.block_species_temperatures``): each species' kT_a drawn too.
    ax : matplotlib Axes, optional
    species_theory : array_like, shape (S,), optional
        The theory's T_a / T (``temperature_species_theory``): each species'
        kT_a by it, dotted in the species' colour.
    theory_temperatures : array_like, shape (K,), optional
        The theory's kT at ``collisions`` when its rate changes as the gas
        cools (a restitution law: :func:`~collisionkit.edmd.maxwellian_cooling`
        from the first point), drawn as the theory's line instead of ``rate``'s.
    rotation : array_like, shape (K,), optional
        Rough spheres' rotational kT at ``collisions``, drawn as a second
        series; ``theory_rotation`` (same shape) its theory's
        (:func:`~collisionkit.edmd.rough_cooling`), dotted.
    homogeneity_lost_after : float, optional
        The collisions per particle at which the gas was first found
        inhomogeneous (the summary's ``homogeneity_lost_after``): a vertical
        line, beyond which the homogeneous theory does not hold.

    Returns
    -------
    matplotlib.axes.Axes

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit import plotting
    >>> C = np.arange(1.0, 6.0)
    >>> ax = plotting.plot_cooling(C, np.exp(-0.06 * C), rate=0.06, species=np.tile([1.1, 0.9], (5, 1)))
    >>> [text.get_text() for text in ax.get_legend().get_texts()]
    ['all', 'theory, -d ln T/dC = 0.06', 'A', 'B']
    """
    from ..trajectory import type_names

    collisions = np.asarray(collisions, dtype=float)
    temperatures = np.asarray(temperatures, dtype=float)
    if collisions.ndim != 1 or collisions.shape != temperatures.shape:
        raise ValueError(f"collisions and temperatures must be 1-D of one length; got {collisions.shape} and "
                         f"{temperatures.shape}")
    ax = _axes(ax)
    ax.semilogy(collisions, temperatures, "o", color="C0", label="all" if rotation is None else "translation")
    if theory_temperatures is not None:
        theory_temperatures = np.asarray(theory_temperatures, dtype=float)
        if theory_temperatures.shape != collisions.shape:
            raise ValueError(f"theory_temperatures must have shape {collisions.shape}; got {theory_temperatures.shape}")
        ax.semilogy(collisions, theory_temperatures, color="0.4", lw=1, label="theory (Maxwellian)")
    elif rate is not None:
        ax.semilogy(collisions, temperatures[0] * np.exp(-rate * (collisions - collisions[0])), color="0.4", lw=1,
                    label=f"theory, -d ln T/dC = {rate:.4g}")
    for name, values in (("rotation", rotation), ("theory_rotation", theory_rotation)):
        if values is not None and np.shape(values) != collisions.shape:
            raise ValueError(f"{name} must have shape {collisions.shape}; got {np.shape(values)}")
    if rotation is not None:
        ax.semilogy(collisions, np.asarray(rotation, dtype=float), "s", mfc="none", color="C3", label="rotation")
    if theory_rotation is not None:
        ax.semilogy(collisions, np.asarray(theory_rotation, dtype=float), ls=":", color="C3",
                    label="rotation, theory")
    if species is not None:
        species = np.asarray(species, dtype=float)
        if species.ndim != 2 or species.shape[0] != collisions.size:
            raise ValueError(f"species must have shape ({collisions.size}, S); got {species.shape}")
        theory = None if species_theory is None else np.asarray(species_theory, dtype=float)
        if theory is not None and theory.shape != (species.shape[1],):
            raise ValueError(f"species_theory must have shape ({species.shape[1]},); got {theory.shape}")
        for index, name in enumerate(type_names(np.arange(species.shape[1]))):
            ax.semilogy(collisions, species[:, index] * temperatures, ls="--", marker=".", color=f"C{index + 1}",
                        label=name)
            if theory is not None:
                ax.semilogy(collisions, theory[index] * temperatures, ls=":", color=f"C{index + 1}",
                            label=f"{name}, theory")
    if homogeneity_lost_after is not None:  # (grey: the species take C1, C2, ...)
        ax.axvline(homogeneity_lost_after, color="0.5", lw=1, ls="--", label="shear flows: not homogeneous")
    drawn = [temperatures] + ([np.asarray(rotation, dtype=float)] if rotation is not None else []) + (
        [(species * temperatures[:, None]).ravel()] if species is not None else [])
    measured = np.concatenate(drawn)
    measured = measured[np.isfinite(measured) & (measured > 0)]
    if measured.size:  # the data's range (every series drawn): a theory cooling faster would stretch it to 1e-45
        ax.set_ylim(bottom=0.5 * float(measured.min()))
    ax.set_xlabel("collisions per particle $C$ (measured)")
    ax.set_title("cooling")
    ax.set_ylabel("$kT$")
    ax.legend()
    return ax


_HELFAND_LABELS = {
    "shear_viscosity": r"shear viscosity $\eta$",
    "bulk_viscosity": r"bulk viscosity $\zeta$",
    "thermal_conductivity": r"thermal conductivity $\lambda$",
    "interdiffusion": r"interdiffusion $D_{12}$",
}


def plot_helfand_moments(transport, axes=None):
    """The Einstein-Helfand curves of a transport measurement, each with its fitted line over the fit window.

    One panel per coefficient: the block mean of the normalised mean
    squared change of its Helfand moment against the lag (its slope is the
    coefficient), with its standard error as a band, the straight line
    fitted over the window (shaded) and the value with its error.

    Parameters
    ----------
    transport : TransportMeasurement
        ``Measurement.transport`` of a run with ``transport=True``.
    axes : sequence of matplotlib Axes, optional
        One per coefficient (3, or 4 for a binary mixture).

    Returns
    -------
    ndarray of matplotlib Axes

    Examples
    --------
    >>> from collisionkit import plotting
    >>> from collisionkit.edmd import measure, random_fluid
    >>> m = measure(random_fluid(3, 108, 0.3, seed=1), collisions=40_000, blocks=4, transport=True)
    >>> axes = plotting.plot_helfand_moments(m.transport)
    >>> len(axes), axes[0].get_title().split(" $")[0]
    (3, 'shear viscosity')
    """
    fits = transport.fits
    if axes is None:
        _, axes = plt.subplots(1, len(fits), figsize=(4.2 * len(fits), 3.8), layout="constrained", squeeze=False)
    axes = np.asarray(axes).ravel()
    if axes.size != len(fits):
        raise ValueError(f"axes must hold one Axes per coefficient ({len(fits)}); got {axes.size}")
    for ax, (name, fit) in zip(axes, fits.items()):
        ax.plot(fit.time, fit.curve, color="C0", label="Helfand moment")
        ax.fill_between(fit.time, fit.curve - fit.curve_error, fit.curve + fit.curve_error, color="C0", alpha=0.25,
                        lw=0)
        if np.isfinite(fit.window[0]):
            ax.axvspan(*fit.window, color="0.85", zorder=0, label="fit window")
            line = np.array(fit.window)
            ax.plot(line, fit.intercept + fit.value * line, "--", color="C3", lw=1.5, label="fit")
        ax.set_title(f"{_HELFAND_LABELS.get(name, name)}: {fit.value:.4g} ± {fit.error:.2g}", fontsize=10)
        ax.set_xlabel("lag $t$")
        ax.set_ylabel("mean squared change / normalisation")
        ax.legend(fontsize=8)
    return axes
