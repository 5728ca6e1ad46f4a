"""The ``demo`` subcommand: every capability at small size.

Each capability contributes a section: a function ``run(pairs, seed, out,
plotting)`` returning a :class:`SectionResult`. The demo prints one table
row per check and writes the plots and ``summary.json`` to the folder.
"""

from __future__ import annotations

from pathlib import Path

from ._demo_section import SectionResult

__all__ = ["DeliveredPlots", "SectionResult", "sections"]


class DeliveredPlots:
    """:mod:`collisionkit.plotting` for the demo's sections, its ``save`` written through a :class:`Deliveries`.

    A plot that cannot be written is reported at the end instead of losing
    the sections' results; ``save`` returns the path either way (the demo
    lists only the files that were written).

    Examples
    --------
    >>> import tempfile
    >>> from collisionkit import plotting
    >>> from collisionkit.cli._files import Deliveries
    >>> deliveries = Deliveries("demo")
    >>> plots = DeliveredPlots(plotting, deliveries)
    >>> path = plots.save(plots.plot_deflection_laws(), Path(tempfile.mkdtemp()) / "laws.png")
    >>> deliveries.files == [path]
    True
    """

    def __init__(self, plotting, deliveries):
        self._plotting = plotting
        self._deliveries = deliveries

    def __getattr__(self, name):
        return getattr(self._plotting, name)

    def save(self, figure, path) -> Path:
        """Save ``figure`` to ``path`` through the deliveries; the path, written or not.

        Examples
        --------
        >>> from collisionkit import plotting
        >>> from collisionkit.cli._files import Deliveries
        >>> plots = DeliveredPlots(plotting, Deliveries("demo"))
        >>> plots.save(plots.plot_deflection_laws(), Path("/no/such/folder/laws.png")).name
        'laws.png'
        """
        self._deliveries.write(f"the plot {path}", lambda: self._plotting.save(figure, path))
        return Path(path)


def sections():
    """The demo sections in display order (imported lazily: each may be slow to import)."""
    from . import _demo_core, _demo_edmd, _demo_encounter, _demo_transport

    return [
        ("collision core", _demo_core.run),
        ("two-body encounters", _demo_encounter.run),
        ("event-driven MD", _demo_edmd.run),
        ("Monte Carlo transport", _demo_transport.run),
    ]
