"""Matplotlib helpers; each returns the Axes it drew on.

Not imported by ``collisionkit`` itself (the core needs no matplotlib):
``from collisionkit import plotting``. Every figure takes results, never
files or studies, and every name is importable from here; the modules
follow the domains:

* :mod:`~collisionkit.plotting.collisions` - irfpy's stationary-target scan,
  deflection laws, inelastic energy loss;
* :mod:`~collisionkit.plotting.encounters` - two-body encounters;
* :mod:`~collisionkit.plotting.edmd` - equation of state, speed
  distribution, snapshots, radial distribution, Helfand moments and their fits,
  the cooling of a granular gas;
* :mod:`~collisionkit.plotting.transport` - energy distributions, transport
  coefficients, swarm trajectories;
* :mod:`~collisionkit.plotting.tracking` - sample tracks in a device, and
  the spectra, profiles and induced current of a tracking run;
* :mod:`~collisionkit.plotting.sweep` - a parameter study's result;
* :mod:`~collisionkit.plotting.animation` - animations saved as GIF or MP4;
* :func:`save` writes any of these figures to an image file.
"""

from __future__ import annotations

import matplotlib.pyplot as plt

from ._common import SIGMA_X, SIGMA_Y, THERMAL_SPEED
from .animation import (
    ANIMATION_FORMATS,
    COLOUR_MODES,
    animate_encounter,
    animate_frames,
    ffmpeg_available,
    save_animation,
)
from .collisions import plot_deflection_laws, plot_energy_loss, plot_stationary_scan
from .edmd import (
    maxwell_boltzmann_speed_density,
    plot_cooling,
    plot_equation_of_state,
    plot_helfand_moments,
    plot_radial_distribution,
    plot_snapshot,
    plot_speed_distribution,
)
from .encounters import plot_encounter, plot_star_encounter
from .sweep import plot_sweep
from .tracking import plot_tracking_spectra, plot_tracks
from .transport import (
    REID_PUBLISHED, plot_energy_distribution, plot_phase_resolved, plot_trajectories, plot_transport_coefficients,
    plot_two_term_eedf,
)

__all__ = [
    "ANIMATION_FORMATS",
    "COLOUR_MODES",
    "REID_PUBLISHED",
    "SIGMA_X",
    "SIGMA_Y",
    "THERMAL_SPEED",
    "animate_encounter",
    "animate_frames",
    "ffmpeg_available",
    "maxwell_boltzmann_speed_density",
    "plot_cooling",
    "plot_deflection_laws",
    "plot_encounter",
    "plot_star_encounter",
    "plot_energy_distribution",
    "plot_energy_loss",
    "plot_equation_of_state",
    "plot_helfand_moments",
    "plot_phase_resolved",
    "plot_radial_distribution",
    "plot_snapshot",
    "plot_speed_distribution",
    "plot_stationary_scan",
    "plot_sweep",
    "plot_tracking_spectra",
    "plot_tracks",
    "plot_trajectories",
    "plot_transport_coefficients",
    "plot_two_term_eedf",
    "save",
    "save_animation",
]


def save(ax, path):
    """Save the figure holding ``ax`` to ``path``, atomically, and close it.

    The image is drawn into a temporary file beside ``path`` that then
    replaces it (``os.replace``): a reader, or a crash at any instant, sees
    the old file or the new one, never half an image; if drawing fails, the
    temporary file is removed and an existing ``path`` is left as it was.
    Its folder must exist (FileNotFoundError otherwise, as ``savefig``).

    Parameters
    ----------
    ax : matplotlib Axes
        Any axes of the figure to save.
    path : str or Path
        The image file; its suffix (``.png``, ``.pdf``, ``.svg``, ...) sets the format (none: matplotlib's
        default format, ``savefig.format``).

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
    >>> path.read_bytes()[1:4], [p.name for p in path.parent.iterdir()]
    (b'PNG', ['laws.png'])
    """
    from pathlib import Path

    from .._io import atomic_replacement

    figure = ax.figure
    image_format = Path(path).suffix[1:].lower() or plt.rcParams["savefig.format"]
    if not Path(path).parent.is_dir():  # as matplotlib's savefig: no folder is made (a mistyped path fails)
        plt.close(figure)
        raise FileNotFoundError(f"No such file or directory: {path} (its folder does not exist)")
    try:
        # the temporary file's name ends in .tmp: the format is the target's, given explicitly
        with atomic_replacement(path) as temporary:
            figure.savefig(temporary, dpi=120, format=image_format)
    finally:
        plt.close(figure)
    return path
