"""The figure of a parameter study: a result against a varied option, from points aggregated across replicas."""

from __future__ import annotations

import math

import numpy as np

from ._common import _axes


def _sweep_label(names, values):
    return ", ".join(f"{name} = {value}" for name, value in zip(names, values))


def _is_finite(value):
    """Whether ``value`` is a finite number (None, text and NaN are not)."""
    return isinstance(value, (int, float, np.integer, np.floating)) and math.isfinite(value)


def _with_finite(groups, key):
    """Each group's points with a finite ``key``; groups with none are left out."""
    kept = {values: [point for point in group if _is_finite(point.get(key))] for values, group in groups.items()}
    return {values: group for values, group in kept.items() if group}


def _axis_value(value, categorical=False):
    """A varied option's value as matplotlib draws it: a list option's (``diameters = [1, 0.6]``) as its text, a
    category on the axis; a number among such lists (``restitution = 0.9`` beside a matrix) as text too, since an
    axis takes numbers or categories, not both."""
    if isinstance(value, (list, tuple)):
        return str(list(value))
    return f"{value:g}" if categorical and isinstance(value, (int, float, np.integer, np.floating)) else value


def plot_sweep(points, x, y, series=(), title=None, ax=None):
    """A study's result ``y`` against the varied option ``x``: mean across replicas, standard error bars.

    Parameters
    ----------
    points : sequence of dict
        One per point of the study, already aggregated across its replicas:
        the value of the varied option ``x`` and of each option in
        ``series``, ``"mean"`` (the mean of ``y``; points whose mean is not
        finite are left out), ``"error"`` (its standard error; NaN draws no
        bar) and, optionally, ``"theory"`` (a theoretical value of ``y`` at
        that point, drawn as a dashed line labelled "theory" beside the
        measured points).
    x, y : str
        Name of the varied option and of the result.
    series : sequence of str, optional
        Other varied options: one line per combination of their values.
    title : str, optional
    ax : matplotlib Axes, optional

    Returns
    -------
    matplotlib.axes.Axes

    Raises
    ------
    ValueError
        If no point has a finite mean.

    Examples
    --------
    >>> from collisionkit import plotting
    >>> points = [{"eta": 0.1, "mean": 1.55, "error": 0.05}, {"eta": 0.2, "mean": 2.45, "error": 0.05}]
    >>> ax = plotting.plot_sweep(points, "eta", "Z")
    >>> ax.get_xlabel(), ax.get_ylabel(), len(ax.containers)
    ('eta', 'Z (mean of replicas)', 1)
    >>> points = [point | {"theory": {0.1: 1.52, 0.2: 2.43}[point["eta"]]} for point in points]
    >>> ax = plotting.plot_sweep(points, "eta", "Z")
    >>> [text.get_text() for text in ax.get_legend().get_texts()]
    ['theory', 'measured']
    >>> points = [{"diameters": [1.0, d], "mean": z, "error": 0.01} for d, z in ((0.5, 3.5), (0.8, 3.9))]
    >>> [label.get_text() for label in plotting.plot_sweep(points, "diameters", "Z").get_xticklabels()]
    ['[1.0, 0.5]', '[1.0, 0.8]']
    >>> points = [{"e": e, "mean": 1.0, "error": 0.1} for e in (0.9, [[0.9, 0.8], [0.8, 0.7]])]
    >>> [label.get_text() for label in plotting.plot_sweep(points, "e", "Z").get_xticklabels()]
    ['0.9', '[[0.9, 0.8], [0.8, 0.7]]']
    """
    series = list(series)
    categorical = any(isinstance(point[x], (list, tuple)) for point in points)  # no line between categories
    groups = {}
    for point in points:
        groups.setdefault(tuple(_axis_value(point[name]) for name in series), []).append(point)
    measured = _with_finite(groups, "mean")
    if not measured:
        raise ValueError(f"points hold no finite mean of {y!r}")
    expected = _with_finite(groups, "theory")
    ax = _axes(ax)
    for values, group in measured.items():
        errors = np.nan_to_num(np.array([point.get("error", np.nan) for point in group], dtype=float))
        label = _sweep_label(series, values) or ("measured" if expected else None)
        bars = ax.errorbar([_axis_value(point[x], categorical) for point in group], [point["mean"] for point in group],
                           yerr=errors, fmt="o" if categorical else "o-", capsize=3, label=label)
        if values in expected:
            line = [(_axis_value(point[x], categorical), point["theory"]) for point in expected[values]]
            colour = bars.lines[0].get_color() if series else "k"
            ax.plot(*zip(*line), "--", color=colour, lw=1, label=f"{label}, theory" if series else "theory")
    ax.set_xlabel(x)
    ax.set_ylabel(f"{y} (mean of replicas)")
    if title is not None:
        ax.set_title(title)
    if series or expected:
        ax.legend(fontsize="small")
    return ax
