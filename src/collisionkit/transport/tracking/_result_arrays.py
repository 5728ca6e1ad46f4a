"""Storage forms of :class:`~collisionkit.transport.tracking.TrackingResult`: joined batches and checkpoint arrays.

The result's :meth:`combine`, :meth:`to_arrays` and :meth:`from_arrays`
delegate here. The functions take the result's field names and values, so
this module does not import the result's; how each field joins across
batches and how it is read back from an array are listed below.
"""

from __future__ import annotations

import numpy as np

from ..._kernels.transport.tracking import codes as _c

# end records: concatenated, the primary index of each shifted by the primaries of the batches before it
SHIFTED_RECORDS = ("records", "ion_records")
# one row per primary (and the track points): concatenated
CONCATENATED = ("electrons", "collected", "collisions", "induced_charge", "weighting_charge", "ion_induced_charge",
                "points")
# counts, times and histograms over the primaries: added
SUMMED = ("primaries", "null_collisions", "steps", "rejected_steps", "particle_time", "seconds", "signal",
          "ion_signal", "profiles", "moments")
# the fields stored as 0-d arrays, and the type each is read back as
SCALARS = {"primaries": int, "null_collisions": int, "steps": int, "rejected_steps": int, "particle_time": float,
           "signal_step": float, "seconds": float, "method": str, "mass": float, "profile_coordinate": str,
           "collector": str}
NAME_TUPLES = ("surfaces", "process_labels", "process_kinds")


def combined_values(names, parts: list) -> dict:
    """The field values of one result made of consecutive batches of primaries of the same run.

    Parameters
    ----------
    names : sequence of str
        The result's field names, in order.
    parts : list
        The batches' results (at least one), in the order of their primaries.

    Returns
    -------
    dict
        Field name to joined value; a field that is the run's setting
        (surfaces, labels, bins, sample times ...) is the first part's.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> part = SimpleNamespace(primaries=2, electrons=np.ones(2), method="null-collision")
    >>> values = combined_values(["primaries", "electrons", "method"], [part, part])
    >>> values["primaries"], values["electrons"].tolist(), values["method"]
    (4, [1.0, 1.0, 1.0, 1.0], 'null-collision')
    """
    offsets = np.cumsum([0] + [p.primaries for p in parts[:-1]])
    values = {}
    for name in names:
        data = [getattr(p, name) for p in parts]
        if name in SHIFTED_RECORDS:
            values[name] = _shifted_records(data, offsets)
        elif name in CONCATENATED:
            values[name] = np.concatenate(data)
        elif name in SUMMED:
            values[name] = sum(data[1:], data[0])
        else:
            values[name] = data[0]
    return values


def _shifted_records(data, offsets) -> np.ndarray:
    """End records of consecutive batches joined, each batch's primary indices shifted by its ``offsets`` entry."""
    arrays = []
    for offset, records in zip(offsets, data):
        rows = records.copy()
        rows[:, _c.RECORD_PRIMARY] += offset
        arrays.append(rows)
    return np.concatenate(arrays)


def field_arrays(result, names) -> dict[str, np.ndarray]:
    """Every field of ``result`` as an array, as a checkpoint stores them.

    Parameters
    ----------
    result : TrackingResult
        The result to store.
    names : sequence of str
        Its field names, in order.

    Returns
    -------
    dict of str to ndarray
        Tuples become string arrays and a missing collector the empty string.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> arrays = field_arrays(SimpleNamespace(collector=None, surfaces=("anode",)), ["collector", "surfaces"])
    >>> arrays["collector"].item(), arrays["surfaces"].tolist()
    ('', ['anode'])
    """
    out = {}
    for name in names:
        value = getattr(result, name)
        if name == "collector":
            value = "" if value is None else value
        out[name] = np.asarray(value) if not isinstance(value, tuple) else np.array(value, dtype=str)
    return out


def values_from_arrays(names, arrays) -> dict:
    """The field values stored by :func:`field_arrays`, each with its type.

    Parameters
    ----------
    names : sequence of str
        The result's field names, in order (a missing one raises KeyError, the first in this order).
    arrays : mapping of str to array_like
        The stored arrays.

    Returns
    -------
    dict
        Field name to value: the scalars as int, float or str, the name
        tuples as tuples of str, the rest as float arrays; an empty collector is None.

    Examples
    --------
    >>> values = values_from_arrays(["primaries", "collector"], {"primaries": np.array(3), "collector": np.array("")})
    >>> values
    {'primaries': 3, 'collector': None}
    """
    values = {}
    for name in names:
        value = arrays[name]
        if name in SCALARS:
            value = SCALARS[name](np.asarray(value).item())
        elif name in NAME_TUPLES:
            value = tuple(str(v) for v in np.asarray(value).reshape(-1))
        else:
            value = np.asarray(value, dtype=float)
        values[name] = value
    values["collector"] = values["collector"] or None
    return values
