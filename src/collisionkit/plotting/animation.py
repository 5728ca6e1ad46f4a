"""Animations: hard-sphere frames and two-body encounters, saved as GIF or MP4."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from ._common import SIGMA_X, SIGMA_Y, THERMAL_SPEED
from .encounters import _encounter_units

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

    2D: every disc. 3D: the cut through the mid-plane z = L_z/2, as in
    :func:`~collisionkit.plotting.edmd.plot_snapshot`.
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
    """Animate hard-sphere frames (as :func:`collisionkit.trajectory.read_gsd_frames` returns them).

    Each frame is drawn to scale like
    :func:`~collisionkit.plotting.edmd.plot_snapshot`: every disc in 2D, the
    cut through the mid-plane z = L_z/2 in 3D.

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

    An EDMD trajectory stored as a GSD file (``collisionkit edmd --trajectory``),
    every other frame:

    >>> from collisionkit.edmd import random_fluid
    >>> from collisionkit.trajectory import GSDWriter, read_gsd_frames
    >>> path = pathlib.Path(folder.name) / "run.gsd"
    >>> system = random_fluid(2, 30, 0.3, seed=1)
    >>> with GSDWriter(path) as writer:
    ...     for step in range(3):
    ...         _ = system.run(collisions=20)
    ...         writer.write(system, step=20 * step)
    >>> animation = plotting.animate_frames(read_gsd_frames(path, every=2), colour_by="species")
    >>> animation._fig.axes[0].get_title()
    'step 0'
    >>> plotting.save_animation(animation, pathlib.Path(folder.name) / "run.gif", fps=2, dpi=30).suffix
    '.gif'
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


def animate_encounter(orbit, frames=120, max_separation=None, colour_by="speed", interval=50, units=None, ax=None):
    """Animate a two-body encounter in the centre-of-mass frame, with trails.

    Drawn in the orbital plane as in
    :func:`~collisionkit.plotting.encounters.plot_encounter`; the frames are
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
    >>> ic = starcrash_initial_conditions(1.0, 0.5, rp=1.0, v_inf=0.5, sep0=10.0)
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
        E.g. from :func:`animate_frames` or :func:`animate_encounter`.
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


