"""Species names of LXCat blocks: the target of a reaction, in one spelling.

LXCat files name a target freely: ``Ar``, ``Ar <-> Ar*`` (the target before
the arrow), ``e + N2 -> e + N2(v=1)`` (the electron dropped), ``e / Ar`` (a
``SPECIES:`` line), ``N2(X,v=0)`` (a state designation). :func:`target_name`
reduces them to one name:

* the text before a reaction arrow (``<->``, ``->``, ``<=>``, ``=>``), after
  a ``SPECIES:`` line's ``e /``, without a leading ``e +`` and without spaces;
* a state in parentheses or brackets is dropped when it is the ground state
  (``X...``, ``gnd``, ``ground``, ``v=0``, ``J=0``, ``v=0,J=0`` or the ground
  term ``1S0`` of a rare gas): ``N2(X,v=0)`` and ``Ar(1S0)`` are ``N2`` and
  ``Ar``; any other state stays part of the name (``Ar(4p[3/2]2)``,
  ``NO(v=38)``, ``O2(a1Dg)``): an excited target is another species, with
  its own density;
* a charge is written ``^+`` / ``^-`` (``N2+`` and ``N2^+`` are ``N2^+``;
  ``O-`` is ``O^-``), an excitation mark ``*`` is kept (``Ar*``).

A name that is not a chemical formula (``Nitrogen``, ``N2-rot``, ``CO_anis``:
names the IST-Lisbon database gives its groups of processes) is resolved by
:func:`product_formula` from the processes that leave the target unchanged
(elastic, rotational, vibrational: ``E + Nitrogen <-> E + N2 (J=0-J=2)``
names N2); see :func:`resolve_names`.
"""

from __future__ import annotations

import re

ARROWS = ("<->", "<=>", "->", "=>", "→", "↔")
FORMULA = re.compile(r"(?:[A-Z][a-z]?\d*)+(?:\^\d*[+-])?\**")
GROUND = re.compile(r"^(?:X(?![a-z]).*|gnd|ground|1S0|(?:v=0)?,?(?:J=0)?)$", re.IGNORECASE)
STATE = re.compile(r"[(\[][^()\[\]]*(?:[(\[][^()\[\]]*[)\]][^()\[\]]*)*[)\]]")
CHARGE = re.compile(r"(?:\^(\d*)([+-])|([+-]+))$")  # N2^+, N^2+, N2+ (the digit is the formula's), O--


def _before_arrow(text: str) -> str:
    cut = len(text)
    for arrow in ARROWS:
        where = text.find(arrow)
        if where >= 0:
            cut = min(cut, where)
    return text[:cut]


def _without_electron(text: str) -> str:
    text = text.strip()
    if "/" in text and text.split("/", 1)[0].strip().lower() == "e":  # "e / Ar" of a SPECIES: line
        text = text.split("/", 1)[1]
    return re.sub(r"^\s*e\s*\+\s*", "", text, flags=re.IGNORECASE).strip()


def _split_state(name: str) -> tuple[str, str]:
    """(the name without its state designations, the designations joined by commas)."""
    states = [match.group(0)[1:-1] for match in STATE.finditer(name)]
    return STATE.sub("", name), ",".join(state for state in states if state)


def _charge(base: str) -> str:
    if not FORMULA.fullmatch(CHARGE.sub("", base) or "-"):
        return base
    def spelled(match):
        if match.group(3):
            signs = match.group(3)
            return f"^{len(signs) if len(signs) > 1 else ''}{signs[0]}"
        return f"^{match.group(1)}{match.group(2)}"

    return CHARGE.sub(spelled, base)


def target_name(text: str) -> str:
    """The species a target line, a ``SPECIES:`` value or a reaction names (see the module docstring).

    Examples
    --------
    >>> from collisionkit.transport._lxcat_names import target_name
    >>> [target_name(t) for t in ["Ar", "Ar <-> Ar*", "e + N2 -> e + N2(v=1)", "N2 -> N2^+", "O2 -> O2^-"]]
    ['Ar', 'Ar', 'N2', 'N2', 'O2']
    >>> [target_name(t) for t in ["e / Ar", "N2(X,v=0)", "Ar(1S0)", "Ar*", "N2+", "O-", "Ar(4p[3/2]2) -> Ar(+)"]]
    ['Ar', 'N2', 'Ar', 'Ar*', 'N2^+', 'O^-', 'Ar(4p[3/2]2)']
    """
    name = "".join(_before_arrow(_without_electron(text)).split())
    base, state = _split_state(name)
    if not base:
        return name
    base = _charge(base)
    if not state or GROUND.match(state):
        return base
    return f"{base}({state})"


def is_formula(name: str) -> bool:
    """True if ``name`` reads as a chemical formula (with a charge, a mark or a state): ``N2``, ``Ar*``, ``O^-``.

    Examples
    --------
    >>> from collisionkit.transport._lxcat_names import is_formula
    >>> [is_formula(n) for n in ["N2", "Ar*", "O^-", "NO(v=38)", "Nitrogen", "N2-rot", "CO_anis"]]
    [True, True, True, True, False, False, False]
    """
    base, _ = _split_state(name)
    return bool(FORMULA.fullmatch(base))


def product_target(process: str) -> str | None:
    """The first heavy product of a ``PROCESS:`` reaction, named as a target (state kept unless ground); else None.

    For an elastic process this is its target: ``E + Oxygen -> E + O(1D), Elastic`` is elastic scattering on
    O(1D).

    Examples
    --------
    >>> from collisionkit.transport._lxcat_names import product_target
    >>> product_target("E + Oxygen -> E + O(1D), Elastic"), product_target("E + Oxygen -> E + O, Elastic")
    ('O(1D)', 'O')
    """
    reaction = process.rsplit(",", 1)[0] if "," in process.split(")")[-1] else process
    for arrow in ARROWS:
        if arrow in reaction:
            right = reaction.split(arrow, 1)[1]
            break
    else:
        return None
    for term in right.split(" + "):
        term = "".join(term.split())
        if term.lower() in ("e", "") or term.startswith("E+"):
            continue
        name = target_name(term)
        return name if is_formula(name) else None
    return None


def product_formula(process: str) -> str | None:
    """The formula of the first heavy product of a ``PROCESS:`` reaction, without its state; None if none.

    ``E + Nitrogen <-> E + N2 (J=0-J=2), Rotational`` gives ``N2``: for a
    process that leaves the target unchanged this names the target.

    Examples
    --------
    >>> from collisionkit.transport._lxcat_names import product_formula
    >>> product_formula("E + Nitrogen <-> E + N2 (J=0-J=2), Rotational"), product_formula("E + CO-elec -> E + CO-elec")
    ('N2', None)
    """
    name = product_target(process)
    return None if name is None else _split_state(name)[0]


def resolve_names(raw_names, preserving_products) -> dict[str, str]:
    """Map names that are not formulas to the one formula their target-preserving processes give.

    Parameters
    ----------
    raw_names : iterable of str
        The normalised names of a file's blocks.
    preserving_products : mapping of str to set of str
        For each name, the product formulas of its elastic, effective,
        momentum, rotational and vibrational processes.

    Returns
    -------
    dict
        ``{name: formula}`` for names that resolve to exactly one formula.

    Examples
    --------
    >>> from collisionkit.transport._lxcat_names import resolve_names
    >>> resolve_names(["Nitrogen", "N2", "Oxygen"], {"Nitrogen": {"N2"}, "Oxygen": set()})
    {'Nitrogen': 'N2'}
    """
    resolved = {}
    for name in dict.fromkeys(raw_names):
        if is_formula(name):
            continue
        formulas = set(preserving_products.get(name, ()))
        if len(formulas) == 1:
            resolved[name] = formulas.pop()
    return resolved
