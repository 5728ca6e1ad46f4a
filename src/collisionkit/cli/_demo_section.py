"""What one capability's demo section returns (its own module, so the sections and the demo import no circle)."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any


@dataclass
class SectionResult:
    """What one capability's demo shows: table rows, summary values and files."""

    name: str
    rows: list[tuple[str, str, str]]
    summary: dict[str, Any]
    files: list[Path] = field(default_factory=list)
