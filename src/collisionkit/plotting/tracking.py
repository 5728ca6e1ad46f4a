"""Figures of particle tracking (:mod:`collisionkit.transport.tracking`): sample tracks in the device, spectra."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from ._common import _axes


def _outline(ax, device, plane: str) -> None:
    """The device's electrodes in the plotted plane (plates: lines z = 0 and z = gap; coaxial: circles)."""
    from ..transport.tracking import CoaxialField, ParallelPlateField

    field = device.electric
    if isinstance(field, ParallelPlateField):
        for z, name in ((0.0, "cathode"), (field.gap, "anode")):
            ax.axhline(z * 1e3, color="0.3", linewidth=1.5)
            ax.annotate(name, (0.01, z * 1e3), xycoords=("axes fraction", "data"), fontsize=8, va="bottom")
    elif isinstance(field, CoaxialField) and plane == "xy":
        angle = np.linspace(0, 2 * np.pi, 200)
        for radius in (field.wire_radius, field.cathode_radius):
            ax.plot((field.axis[0] + radius * np.cos(angle)) * 1e3, (field.axis[1] + radius * np.sin(angle)) * 1e3,
                    color="0.3", linewidth=1.5)
        ax.set_aspect("equal")


def plot_tracks(result, device=None, ax=None, particles: int = 30):
    """Sample tracks (the points a run kept with ``record_points``) in mm: x-z for plates, x-y for a counter.

    Examples
    --------
    >>> import numpy as np
    >>> from types import SimpleNamespace
    >>> from collisionkit import plotting
    >>> points = np.array([[0, 0, 0, 0, 0], [0, 1e-9, 1e-4, 0, 2e-4], [1, 0, 0, 0, 1e-4], [1, 1e-9, 0, 1e-4, 3e-4]])
    >>> ax = plotting.plot_tracks(SimpleNamespace(points=points))
    >>> len(ax.lines), ax.get_xlabel()
    (2, 'x (mm)')
    >>> import matplotlib.pyplot as plt
    >>> plt.close(ax.figure)
    """
    from ..transport.tracking import CoaxialField

    ax = _axes(ax)
    plane = "xy" if device is not None and isinstance(device.electric, CoaxialField) else "xz"
    second = 2 if plane == "xy" else 3
    points = np.asarray(result.points)
    for number in np.unique(points[:, 0])[:particles] if points.size else []:
        mine = points[points[:, 0] == number]
        ax.plot(mine[:, 2] * 1e3, mine[:, 1 + second] * 1e3, linewidth=0.7)
    if device is not None:
        _outline(ax, device, plane)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel(("y" if plane == "xy" else "z") + " (mm)")
    ax.set_title("sample tracks")
    return ax


def plot_tracking_spectra(result, axes=None, bins: int = 50):
    """Arrival times and energies at the collecting electrode, the gain distribution, the ionization and excitation
    profiles and the induced current of a :class:`~collisionkit.transport.tracking.TrackingResult`.

    Returns the 2 x 3 array of Axes (the last one empty).

    Examples
    --------
    >>> from collisionkit import plotting
    >>> from collisionkit.transport import maxwell_model
    >>> from collisionkit.transport.tracking import Device, track
    >>> device = Device.parallel_plate(maxwell_model(1e-13, mass=1e-29), 1e-4, 10.0, density=1e23)
    >>> axes = plotting.plot_tracking_spectra(track(device, primaries=4, position=(0, 0, 5e-5), seed=1))
    >>> axes.shape
    (2, 3)
    >>> import matplotlib.pyplot as plt
    >>> plt.close(axes[0, 0].figure)
    """
    if axes is None:
        _, axes = plt.subplots(2, 3, figsize=(13, 7), layout="constrained")
    collected = result.collected_records()
    ax = axes[0, 0]
    if collected.shape[0]:
        edges, counts = result.arrival_time_spectrum(bins)
        ax.stairs(counts, edges * 1e9)
    ax.set_xlabel("arrival time (ns)")
    ax.set_ylabel("electrons per primary")
    ax = axes[0, 1]
    if collected.shape[0]:
        edges, density = result.energy_spectrum(bins)
        ax.stairs(density, edges)
    ax.set_xlabel("energy at the electrode (eV)")
    ax.set_ylabel("electrons per primary and eV")
    ax = axes[0, 2]
    gains, fractions = result.gain_distribution()
    ax.plot(gains, fractions, "o", markersize=3)
    ax.set_xlabel("gain")
    ax.set_ylabel("fraction of primaries")
    ax = axes[1, 0]
    for kind in ("ionization", "excitation"):
        edges, rate = result.profile(kind)
        if rate.size:
            ax.stairs(rate, edges * 1e3, label=kind)
    ax.set_xlabel(f"{result.profile_coordinate} (mm)")
    ax.set_ylabel("events per primary and m")
    if ax.get_legend_handles_labels()[0]:
        ax.legend()
    ax = axes[1, 1]
    edges, current = result.current()
    if current.size:
        ax.stairs(current, edges * 1e9, label="electrons and ions")
        if np.any(result.ion_signal):
            ax.stairs(result.signal / max(result.primaries, 1) / result.signal_step, edges * 1e9, label="electrons")
            ax.legend()
    ax.set_xlabel("time (ns)")
    ax.set_ylabel("induced current per primary (A)")
    axes[1, 2].axis("off")
    return axes
