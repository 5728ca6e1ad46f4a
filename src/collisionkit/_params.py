"""Run parameters shared by the library, the sweep and the command line.

Every run a command can do (``edmd``, ``swarm``, ``slab``, ``encounter``)
has a frozen dataclass of its physics parameters, derived from
:class:`Parameters`. It checks every value when it is made (a
``ValueError`` or ``TypeError`` naming the parameter and the allowed
range), reads values spelled as Python names (``packing_fraction``,
``reduced_field``) or as command-line flags (``packing-fraction``,
``E-N``), and writes itself back as plain data that makes it again.
"""

from __future__ import annotations

import dataclasses
import math
import numbers
from collections.abc import Mapping, Sequence
from typing import Any, ClassVar


def flag_of(name: str, flags: Mapping[str, str]) -> str:
    """The command-line spelling of a parameter: ``packing_fraction`` -> ``packing-fraction``.

    Examples
    --------
    >>> flag_of("packing_fraction", {}), flag_of("reduced_field", {"reduced_field": "E-N"})
    ('packing-fraction', 'E-N')
    """
    return flags.get(name, name.replace("_", "-"))


@dataclasses.dataclass(frozen=True)
class Parameters:
    """Base of the run parameters: spellings, plain data and checks.

    Subclasses are frozen dataclasses; ``FLAGS`` maps the Python names
    whose command-line flag is not the dashed name (``reduced_field`` ->
    ``E-N``).
    """

    FLAGS: ClassVar[Mapping[str, str]] = {}

    @classmethod
    def names(cls) -> tuple[str, ...]:
        """The parameters' Python names, in order."""
        return tuple(item.name for item in dataclasses.fields(cls))

    @classmethod
    def flag(cls, name: str) -> str:
        """The command-line spelling of the parameter ``name``."""
        return flag_of(name, cls.FLAGS)

    @classmethod
    def name_of(cls, key: str) -> str | None:
        """The Python name a key spells (a Python name, a flag, dashes or underscores), or None.

        Examples
        --------
        >>> from collisionkit.transport.scan import SwarmParameters
        >>> SwarmParameters.name_of("E-N"), SwarmParameters.name_of("gas-temperature"), SwarmParameters.name_of("x")
        ('reduced_field', 'gas_temperature', None)
        """
        key = str(key)
        for name in cls.names():
            if key in (name, cls.flag(name)) or key.replace("-", "_").lower() in (name.lower(),
                                                                                  cls.flag(name).replace("-", "_").lower()):
                return name
        return None

    @classmethod
    def from_mapping(cls, values: Mapping[str, Any], **overrides):
        """Make the parameters from a mapping keyed by Python names or flags; unknown keys are a ValueError."""
        data: dict[str, Any] = {}
        for key, value in {**values, **overrides}.items():
            name = cls.name_of(key)
            if name is None:
                allowed = ", ".join(cls.flag(name) for name in cls.names())
                raise ValueError(f"unknown parameter {key!r}; allowed: {allowed}")
            if name in data:
                raise ValueError(f"parameter {cls.flag(name)!r} is given twice")
            data[name] = value
        return cls(**data)

    def to_dict(self) -> dict[str, Any]:
        """The parameters as plain data (lists for tuples, strings for paths), by Python name."""
        return {name: _plain(getattr(self, name)) for name in self.names()}

    def replace(self, **changes):
        """A copy with some parameters changed (checked again)."""
        return dataclasses.replace(self, **changes)


def _plain(value: Any) -> Any:
    if isinstance(value, tuple):
        return [_plain(item) for item in value]
    if hasattr(value, "__fspath__"):
        return str(value)
    return value


# ------------------------------------------------------------------ checks


def check_unchanged(parameters: Parameters, given, path) -> None:
    """Raise ValueError if a parameter in ``given`` differs from the saved ``parameters`` of checkpoint ``path``."""
    if not given:
        return
    try:
        now = parameters.from_mapping(parameters.to_dict() | _by_name(parameters, given))
    except ValueError:
        # the given values do not combine with the saved ones: name the first that differs, not the saved one the
        # check tripped over (a changed restitution_law leaves the saved law_speed without a law)
        for name, value in sorted(_by_name(parameters, given).items()):
            before = getattr(parameters, name)
            if _plain(value) != _plain(before):
                raise ValueError(f"{name} = {_shown(value)} differs from the checkpoint {path} ({name} = "
                                 f"{_shown(before)}); a resumed run keeps the physics parameters it started with"
                                 ) from None
        raise
    for name in sorted(_by_name(parameters, given)):
        value, before = getattr(now, name), getattr(parameters, name)
        if value != before:
            raise ValueError(f"{name} = {_shown(value)} differs from the checkpoint {path} ({name} = {_shown(before)}); "
                             "a resumed run keeps the physics parameters it started with")


def _by_name(parameters: Parameters, given) -> dict[str, Any]:
    named = {}
    for key, value in given.items():
        name = parameters.name_of(key)
        if name is None:
            raise ValueError(f"unknown parameter {key!r}")
        named[name] = value
    return named


def _shown(value) -> str:
    if isinstance(value, tuple):
        return ",".join(_shown(item) for item in value)
    return f"{value:g}" if isinstance(value, float) else str(value)



def check_real(name: str, value: Any, low: float = -math.inf, high: float = math.inf, *,
               low_open: bool = False, high_open: bool = False, allow_inf: bool = False) -> float:
    """``value`` as a float, or a TypeError/ValueError naming ``name`` and the allowed range.

    Examples
    --------
    >>> check_real("restitution", 0.9, 0, 1)
    0.9
    >>> check_real("restitution", 1.5, 0, 1)
    Traceback (most recent call last):
    ...
    ValueError: restitution must be in [0, 1]; got 1.5
    """
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a number; got {value!r}")
    value = float(value)
    if math.isnan(value) or (math.isinf(value) and not allow_inf):
        raise ValueError(f"{name} must be finite; got {value}")
    below = value < low or (low_open and value == low)
    above = value > high or (high_open and value == high)
    if below or above:
        raise ValueError(f"{name} must be {_interval(low, high, low_open, high_open)}; got {value:g}")
    return value


def _interval(low: float, high: float, low_open: bool, high_open: bool) -> str:
    if math.isinf(high):
        return f"{'>' if low_open else '>='} {low:g}" if math.isfinite(low) else "a real number"
    if math.isinf(low):
        return f"{'<' if high_open else '<='} {high:g}"
    return f"in {'(' if low_open else '['}{low:g}, {high:g}{')' if high_open else ']'}"


def check_integer(name: str, value: Any, low: int, high: int | None = None) -> int:
    """``value`` as an int in [low, high], or a TypeError/ValueError naming ``name``.

    Examples
    --------
    >>> check_integer("particles", 500, 2)
    500
    >>> check_integer("particles", 1, 2)
    Traceback (most recent call last):
    ...
    ValueError: particles must be >= 2; got 1
    """
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        if isinstance(value, float) and value.is_integer() and abs(value) < 2**53:
            value = int(value)
        else:
            raise TypeError(f"{name} must be an integer; got {value!r}")
    value = int(value)
    if value < low or (high is not None and value > high):
        allowed = f">= {low}" if high is None else f"in [{low}, {high}]"
        raise ValueError(f"{name} must be {allowed}; got {value}")
    return value


def check_choice(name: str, value: Any, choices: Sequence[Any]) -> Any:
    """``value`` if it is one of ``choices``, else a ValueError listing them.

    Examples
    --------
    >>> check_choice("sharing", "equal", ("equal", "uniform"))
    'equal'
    """
    if value not in choices:
        raise ValueError(f"{name} must be one of {', '.join(map(str, choices))}; got {value!r}")
    return value


def check_seed(name: str, value: Any) -> int:
    """A seed for a saved, repeatable run: an integer >= 0."""
    return check_integer(name, value, 0)
