"""``--E-N`` of ``swarm`` and ``boltzmann``: numbers, comma lists and START:STOP:COUNT[:log] ranges.

Each item becomes E/N values in Td; a bad one is a one-line error naming
--E-N (exit 2) before any work.
"""

from __future__ import annotations

from ._common import fail

MAX_REDUCED_FIELD = 1e6  # Td
MAX_E_N_COUNT = 100_000  # values of one START:STOP:COUNT range
E_N_FORMS = "numbers, comma lists, START:STOP:COUNT or START:STOP:COUNT:log"


def _e_n_values(raw: list[str] | None, option: str = "--E-N", unit: str = "Td",
                high: float = MAX_REDUCED_FIELD) -> list[float] | None:
    # (--E of swarm reads the same forms: option "--E", unit "V/cm", no upper end of its own)
    """The E/N values of ``--E-N`` items: numbers, comma lists and ranges; a bad item is exit 2 naming --E-N.

    ``START:STOP:COUNT`` gives COUNT values from START to STOP evenly spaced,
    ``START:STOP:COUNT:log`` logarithmically spaced (START and STOP above 0);
    each value is rounded to 12 significant digits (10, not 10.000000000000002).

    Examples
    --------
    >>> _e_n_values(["10,20", "0:100:3", "1:1000:4:log", "-0"])
    [10.0, 20.0, 0.0, 50.0, 100.0, 1.0, 10.0, 100.0, 1000.0, 0.0]
    """
    if raw is None:
        return None
    items = [part.strip() for item in raw for part in str(item).split(",")]
    if all(not item for item in items):
        raise fail(f"{option}: give at least one {_quantity(option)} value ({unit}, 0 to {_short(high)})")
    values = []
    for item, given in ((item, given) for given in raw for item in str(given).split(",")):
        item = item.strip()
        if not item:
            raise fail(f"{option}: an empty item in {given!r}; give {E_N_FORMS}, separated by commas")
        values.extend(_range_values(item, option, unit, high) if ":" in item else [_number(item, item, option, unit)])
    return [value + 0.0 for value in values]  # -0 is 0


def _quantity(option: str) -> str:
    """What an option's values are: E/N for --E-N, else the option without its dashes (E)."""
    return "E/N" if option == "--E-N" else option.lstrip("-")


def _short(value: float) -> str:
    """1e6, not 1e+06."""
    return f"{value:g}".replace("e+0", "e").replace("e+", "e")


def _number(text: str, item: str, option: str = "--E-N", unit: str = "Td") -> float:
    try:
        return float(text)
    except ValueError:
        raise fail(f"{option}: {text!r} is not a number ({unit})" + (f" in {item!r}" if text != item else "")) from None


def _range_values(item: str, option: str = "--E-N", unit: str = "Td", high: float = MAX_REDUCED_FIELD) -> list[float]:
    """The values of ``START:STOP:COUNT`` (evenly spaced) or ``START:STOP:COUNT:log`` (logarithmically)."""
    import numpy as np

    parts = item.split(":")
    if len(parts) not in (3, 4) or (len(parts) == 4 and parts[3].strip().lower() != "log"):
        raise fail(f"{option}: {item!r} is not a range; give START:STOP:COUNT (evenly spaced) or START:STOP:COUNT:log "
                   "(logarithmically spaced)")
    start, stop = (_number(part.strip(), item, option, unit) for part in parts[:2])
    try:
        count = int(parts[2].strip())
    except ValueError:
        count = 0
    if not 2 <= count <= MAX_E_N_COUNT:
        raise fail(f"{option}: the COUNT of {item!r} must be a whole number from 2 to {MAX_E_N_COUNT}")
    for value in (start, stop):
        if not 0.0 <= value <= high:  # NaN fails too
            raise fail(f"{option}: every {_quantity(option)} must be a finite number from 0 to {high:g} {unit}; "
                       f"got {value:g} in {item!r}")
    if len(parts) == 4:
        if start == 0.0 or stop == 0.0:
            raise fail(f"{option}: a logarithmic range needs START and STOP above 0; got {item!r}")
        spaced = np.geomspace(start, stop, count)
    else:
        spaced = np.linspace(start, stop, count)
    return [float(f"{value:.12g}") for value in spaced]
