"""The ``demo`` subcommand: every capability at small size.

Each capability contributes a section: a function ``run(pairs, seed, out,
plotting)`` returning a :class:`SectionResult`. The demo prints one table
row per check and writes the plots and ``summary.json`` to the folder.
"""

from __future__ import annotations

from ._demo_section import SectionResult

__all__ = ["SectionResult", "sections"]


def sections():
    """The demo sections in display order (imported lazily: each may be slow to import)."""
    from . import _demo_core, _demo_edmd, _demo_encounter, _demo_transport

    return [
        ("collision core", _demo_core.run),
        ("two-body encounters", _demo_encounter.run),
        ("event-driven MD", _demo_edmd.run),
        ("Monte Carlo transport", _demo_transport.run),
    ]
