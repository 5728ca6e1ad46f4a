"""Figures of Monte Carlo transport (:mod:`collisionkit.transport`): energy distributions, coefficients, paths."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from ._common import _axes


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


# above this many curves the E/N is a colour on a colour bar, not a legend entry
LEGEND_CURVES = 8


def plot_two_term_eedf(results, ax=None):
    """The two-term EEDFs F0(eps) (eV^-3/2, int eps^1/2 F0 = 1) of :func:`~collisionkit.transport.two_term_boltzmann`
    results, on a log scale as BOLSIG+ users read them (a Maxwellian is a straight line).

    Up to ``LEGEND_CURVES`` curves are named in a legend; more are coloured
    by E/N (logarithmic) on a colour bar. The energy axis is logarithmic
    when the mean energies span more than a decade (else the low-E/N curves
    hide against the axis), and F0 is shown down to 1e-12 of its highest peak.

    Examples
    --------
    >>> import numpy as np
    >>> from types import SimpleNamespace
    >>> from collisionkit import plotting
    >>> r = SimpleNamespace(energy=np.linspace(0.05, 10, 50), eedf=np.exp(-np.linspace(0.05, 10, 50)),
    ...                     reduced_field=12.0)
    >>> ax = plotting.plot_two_term_eedf([r])
    >>> ax.get_yscale(), ax.get_ylabel()
    ('log', 'F0 (eV^-3/2)')
    """
    from matplotlib import cm, colors

    ax = _axes(ax)
    fields = [r.reduced_field for r in results]
    many = len(results) > LEGEND_CURVES
    positive = min(fields, default=0.0) > 0.0
    norm = (colors.LogNorm if positive else colors.Normalize)(vmin=min(fields, default=0.0),
                                                                vmax=max(fields, default=1.0))
    means = [getattr(r, "mean_energy", None) for r in results]
    logarithmic = all(m is not None and m > 0 for m in means) and max(means, default=1.0) > 10.0 * min(means,
                                                                                                      default=1.0)
    for r in results:
        shown = (r.eedf > 0) & ((r.energy > 0) if logarithmic else True)
        style = {"color": cm.viridis(norm(r.reduced_field))} if many else {"label": f"E/N = {r.reduced_field:g} Td"}
        ax.plot(r.energy[shown], r.eedf[shown], **style)
    ax.set_yscale("log")
    if logarithmic:
        ax.set_xscale("log")
    peak = max((float(np.max(r.eedf)) for r in results), default=0.0)
    if peak > 0:
        ax.set_ylim(bottom=1e-12 * peak)
    ax.set_xlabel("energy (eV)")
    ax.set_ylabel("F0 (eV^-3/2)")
    if many:
        ax.figure.colorbar(cm.ScalarMappable(norm=norm, cmap="viridis"), ax=ax, label="E/N (Td)")
    elif results:
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


def plot_phase_resolved(results, axes=None):
    """Flux drift velocity W(phase) (its three components) and mean energy <e>(phase) over one period of an
    oscillating field, with error bars, for each result that has them (``phases`` not empty).

    Returns the two Axes (W, <e>).

    Examples
    --------
    >>> import numpy as np
    >>> from types import SimpleNamespace
    >>> from collisionkit import plotting
    >>> phases = np.linspace(0, 2 * np.pi, 8, endpoint=False)
    >>> r = SimpleNamespace(reduced_field=10.0, phases=phases, mean_energy_by_phase=1 + 0.1 * np.cos(2 * phases),
    ...     mean_energy_by_phase_error=np.full(8, 0.01),
    ...     drift_velocity_flux_by_phase=np.outer(np.cos(phases), [0, 0, 1]),
    ...     drift_velocity_flux_by_phase_error=np.full((8, 3), 0.01))
    >>> axes = plotting.plot_phase_resolved([r])
    >>> axes[1].get_ylabel()
    'mean energy (eV)'
    """
    if axes is None:
        _, axes = plt.subplots(1, 2, figsize=(10, 4), layout="constrained")
    for r in results:
        if len(r.phases) == 0:
            continue
        for k, axis in enumerate("xyz"):
            velocity = r.drift_velocity_flux_by_phase[:, k]
            if np.any(velocity != 0.0):
                axes[0].errorbar(r.phases, velocity, r.drift_velocity_flux_by_phase_error[:, k], marker="o",
                                 ms=3, label=f"W_{axis}, E0/N = {r.reduced_field:g} Td")
        axes[1].errorbar(r.phases, r.mean_energy_by_phase, r.mean_energy_by_phase_error, marker="o", ms=3,
                         label=f"E0/N = {r.reduced_field:g} Td")
    axes[0].set_xlabel("phase omega t (rad)")
    axes[0].set_ylabel("flux drift velocity (m/s)")
    axes[1].set_xlabel("phase omega t (rad)")
    axes[1].set_ylabel("mean energy (eV)")
    for ax in axes:
        ax.legend(fontsize="small")
    return axes
