"""The checks of :class:`~collisionkit.transport.SwarmParameters`' values, each turned into its stored form.

E/N values, omega/N, a waveform's samples, LXCat paths (resolved), the
angular laws, the level populations, and lists of names or numbers: each
function takes the value given and returns it checked, or raises a
TypeError or ValueError naming it.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from .._params import check_choice, check_real
from ._validation import MAX_REDUCED_FIELD, check_reduced_frequency
from .angular import SCATTERING_LAWS
from .gases import SCATTERING_KINDS
from .swarm import check_waveform_peak


def _reduced_frequency(value) -> float:
    """omega/N checked: 0 or in the range (a bool or a non-number is a TypeError, as for the other numbers)."""
    check_real("reduced_frequency (omega/N, rad m^3/s)", value, 0.0)
    return check_reduced_frequency(value)


def _waveform(value, reduced_frequency, reduced_field):
    """The samples of a waveform as a tuple of (u, E/E0) pairs, checked with the largest E/N (None stays None)."""
    if value is None:
        return None
    check_waveform_peak(value, reduced_field)
    if reduced_frequency <= 0.0:
        raise ValueError("waveform needs reduced_frequency > 0 (--omega-N: the period is 2 pi / omega)")
    return tuple((float(u), float(f)) for u, f in value)


def _reduced_fields(value) -> tuple[float, ...]:
    """One E/N (Td) or several (a sequence or a 1-D numpy array), each checked, as a tuple of floats."""
    if isinstance(value, np.ndarray):
        if value.ndim > 1:
            raise ValueError(f"reduced_field (E/N) must be one value or a 1-D array of them; got shape {value.shape}")
        value = value.tolist()
    values = value if isinstance(value, Sequence) and not isinstance(value, str) else [value]
    if not values:
        raise ValueError("reduced_field (E/N) needs at least one value in Td")
    return tuple(check_real("reduced_field (E/N, Td)", item, 0.0, MAX_REDUCED_FIELD) for item in values)


def _paths(values) -> tuple[Path, ...]:
    """One path or several, resolved (a resumed scan finds them from any folder)."""
    values = [values] if isinstance(values, (str, Path)) or hasattr(values, "__fspath__") else list(values)
    if not values:
        raise ValueError("cross_sections needs at least one LXCat file")
    return tuple(Path(value).resolve() for value in values)


def _scattering(value):
    """The angular laws: None, one law for every kind, or ``{kind: law}`` (checked, kinds in canonical order)."""
    if value is None:
        return None
    if isinstance(value, str):
        check_choice("scattering", value, SCATTERING_LAWS)
        return value
    if not isinstance(value, Mapping) or not value:
        raise TypeError(f"scattering must be a law ({', '.join(SCATTERING_LAWS)}) or a table of laws by process "
                        f"kind ({', '.join(SCATTERING_KINDS)}); got {value!r}")
    for kind, law in value.items():
        check_choice("scattering kind", kind, SCATTERING_KINDS)
        check_choice(f"scattering[{kind!r}]", law, SCATTERING_LAWS)
    return {kind: value[kind] for kind in SCATTERING_KINDS if kind in value}


def _populations(value):
    """``{"species:label": fraction}`` with fractions in [0, 1), or None."""
    if value is None:
        return None
    if not isinstance(value, Mapping) or not value:
        raise TypeError(f"populations must be a table of fractions by process (\"species:label\" = fraction); "
                        f"got {value!r}")
    return {str(key): check_real(f"populations[{key!r}]", fraction, 0.0, 1.0, high_open=True)
            for key, fraction in value.items()}


def _strings(name: str, values) -> tuple[str, ...]:
    values = [values] if isinstance(values, str) else list(values)
    if not values or not all(isinstance(item, str) and item for item in values):
        raise TypeError(f"{name} must be a list of names; got {values!r}")
    return tuple(values)


def _reals(name: str, values) -> tuple[float, ...]:
    values = [values] if not isinstance(values, Sequence) else list(values)
    return tuple(check_real(name, item, 0.0) for item in values)
