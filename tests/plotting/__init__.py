"""Tests of collisionkit.plotting, one module per plotting module."""


def colour_bars(figure):
    """Labels of the figure's colour bars (matplotlib gives their axes a ``_colorbar``)."""
    return [ax._colorbar.ax.get_ylabel() for ax in figure.axes if hasattr(ax, "_colorbar")]
