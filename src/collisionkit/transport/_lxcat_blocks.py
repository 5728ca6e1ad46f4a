"""The blocks of an LXCat file: found first, checked only when used.

:func:`scan` walks a file's lines and cuts them into blocks without reading
their numbers, so a malformed block of a species nobody asked for cannot stop
the reading of another (its fault is kept in :attr:`LXCatBlock.problem`).
:meth:`LXCatBlock.check` reads the numbers of a block that is used and
raises :class:`LXCatError` naming the file, the line and the block.

A block starts at a keyword line (ELASTIC, MOMENTUM, EFFECTIVE, EXCITATION,
VIBRATIONAL, ROTATIONAL, ROTATION, IONIZATION, ATTACHMENT) or, in the newer
style, at a ``SPECIES:`` line followed by a ``PROCESS:`` line. After the
keyword come the target line (``Ar``, ``Ar <-> Ar*``; absent when a
``SPECIES:`` line follows at once) and, except for ATTACHMENT, the parameter
line: m/M (ELASTIC, EFFECTIVE) or the energy loss in eV, possibly followed by
the statistical-weight ratio g_final/g_initial of a reversible excitation
(``19.82 3.0`` or ``19.82 / 3.0``; text after the numbers, ``/ threshold
energy``, is a comment). Comment lines (``SPECIES:``, ``PROCESS:``,
``PARAM.: E = 11.5 eV, g1/g0 = 5``, ...) run to a line of five or more
dashes; the table (energy in eV, cross section in m^2) runs to the next one.
``DATABASE:`` and ``PERMLINK:`` lines between blocks name the database of the
blocks that follow (``www.lxcat.net/Biagi`` is ``Biagi``).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

import numpy as np

from ._lxcat_names import target_name

__all__ = ["LXCatError", "LXCatBlock", "KEYWORDS", "scan"]

KIND_OF = {"ELASTIC": "elastic", "MOMENTUM": "elastic", "EFFECTIVE": "effective", "EXCITATION": "excitation",
           "VIBRATIONAL": "excitation", "ROTATIONAL": "excitation", "ROTATION": "excitation",
           "IONIZATION": "ionization", "ATTACHMENT": "attachment"}
KEYWORDS = tuple(KIND_OF)
DASHES = re.compile(r"^-{5,}\s*$")
NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eEdD][-+]?\d+)?"
PARAMETER_LINE = re.compile(rf"^\s*({NUMBER})(?:\s*/?\s*({NUMBER})(?![\w.]))?")
LEVELS = re.compile(r"\b([vJ])\s*=\s*(\d+)\s*-\s*\1\s*=\s*(\d+)")


class LXCatError(ValueError):
    """A malformed or unphysical LXCat file; the message names the file, the line and the block.

    Examples
    --------
    >>> from collisionkit.transport import LXCatError, parse_lxcat
    >>> try:
    ...     parse_lxcat(chr(10).join(["ELASTIC", "Ar", " not a number", "-----", "1 2", "-----"]))
    ... except LXCatError as error:
    ...     print("refused")
    refused
    """


def _number(text: str, where: str, suffix: str = "") -> float:
    try:
        return float(text.replace("d", "e").replace("D", "e"))
    except ValueError:
        raise LXCatError(f"{where}: expected a number, got {text!r}{suffix}") from None


@dataclass
class LXCatBlock:
    """One process block of an LXCat file.

    Attributes
    ----------
    kind : str
        ``elastic`` (ELASTIC, MOMENTUM), ``effective``, ``excitation``
        (EXCITATION, VIBRATIONAL, ROTATIONAL), ``ionization`` or ``attachment``.
    species : str
        The target as written (the target line, else the ``SPECIES:`` value).
    line : int
        The block's first line (1-based).
    parameter : float or None
        m/M (elastic, effective) or the energy loss in eV.
    weight_ratio : float or None
        g_final/g_initial of a reversible excitation, if the file gives it.
    reversible : bool
        The reaction is written with ``<->``.
    keyword, process, database, source : str
        The block's keyword, its ``PROCESS:`` text, its database (the
        ``PERMLINK:`` name, else the file name) and its file.
    problem : str or None
        What is wrong with the block's layout, raised by :meth:`check`.
    name : str
        The species the block is read for: :attr:`target`, or the formula
        its file's target-preserving processes give a name that is not one
        (``Nitrogen`` -> ``N2``; set by the reader).

    Examples
    --------
    >>> from collisionkit.transport.lxcat import LXCatBlock
    >>> LXCatBlock(kind="excitation", species="Ar -> Ar*", line=12, parameter=11.5).target
    'Ar'
    """

    kind: str
    species: str
    line: int
    parameter: float | None = None
    weight_ratio: float | None = None
    reversible: bool = False
    keyword: str = ""
    process: str = ""
    database: str = ""
    source: str = "<string>"
    problem: str | None = None
    name: str = ""
    rows: list = field(default_factory=list, repr=False)
    energy: np.ndarray = field(default_factory=lambda: np.zeros(0))
    cross_section: np.ndarray = field(default_factory=lambda: np.zeros(0))

    @property
    def target(self) -> str:
        """The target species' name: ``Ar`` from ``Ar -> Ar*``, ``e / Ar`` or ``Ar(1S0)`` (see ``_lxcat_names``)."""
        return target_name(self.species or self.process)

    @property
    def where(self) -> str:
        """``file, line N`` of the block's first line."""
        return f"{self.source}, line {self.line}"

    @property
    def title(self) -> str:
        """The block for a message: ``the EXCITATION block of Ar (Ar -> Ar*) at line 12``."""
        shown = self.species and self.species != self.target and not self.species.lower().startswith("e /")
        written = f" ({self.species})" if shown else ""
        return f"the {self.keyword or self.kind.upper()} block of {self.target}{written} at line {self.line}"

    def initial_level(self) -> str | None:
        """The rotational or vibrational level a level-resolved process starts from (``J=3``, ``v=1``); else None.

        A J-resolved process (``N2 (J=0-J=2)``) always has one; a vibrational
        one only above v = 0 (``N2 (v=0 - v=1)`` starts from the ground level).

        Examples
        --------
        >>> from collisionkit.transport.lxcat import LXCatBlock
        >>> LXCatBlock("excitation", "", 1, process="E + N2 <-> E + N2 (J=3-J=5), Rotational").initial_level()
        'J=3'
        >>> LXCatBlock("excitation", "N2 -> N2 (v=0 - v=1)", 1).initial_level() is None
        True
        """
        match = LEVELS.search(self.process) or LEVELS.search(self.species)
        if match is None or (match.group(1) == "v" and match.group(2) == "0"):
            return None
        return f"{match.group(1)}={match.group(2)}"

    def check(self) -> "LXCatBlock":
        """Read the table and check the block (LXCatError naming file, line and block); return the block.

        Examples
        --------
        >>> from collisionkit.transport.lxcat import LXCatBlock
        >>> block = LXCatBlock("elastic", "Ar", 1, parameter=1.36e-5, rows=[(5, "0 1e-20"), (6, "1 2e-20")])
        >>> block.check().cross_section.tolist()
        [1e-20, 2e-20]
        """
        suffix = f" ({self.title})"
        if self.problem is not None:
            raise LXCatError(self.problem + suffix)
        energy, sigma = [], []
        for number, text in self.rows:
            where = f"{self.source}, line {number}"
            parts = text.split()
            if len(parts) < 2:
                raise LXCatError(f"{where}: expected two numbers (energy, cross section) in the table, got "
                                 f"{text!r}{suffix}")
            e, s = _number(parts[0], where, suffix), _number(parts[1], where, suffix)
            if e < 0:
                raise LXCatError(f"{where}: negative energy {e}{suffix}")
            if s < 0:
                raise LXCatError(f"{where}: negative cross section {s}{suffix}")
            if not (np.isfinite(e) and np.isfinite(s)):
                raise LXCatError(f"{where}: energy and cross section must be finite, got {text!r}{suffix}")
            if energy and e <= energy[-1]:
                raise LXCatError(f"{where}: energies must increase ({e} after {energy[-1]}){suffix}")
            energy.append(e)
            sigma.append(s)
        if not energy:
            raise LXCatError(f"{self.where}: empty cross-section table{suffix}")
        if self.kind in ("excitation", "ionization"):
            if self.parameter is None:
                raise LXCatError(f"{self.where}: {self.kind} block needs a threshold (its energy loss in eV: the line "
                                 f"after the target, or PARAM.: E = ...){suffix}")
            if self.parameter < 0:
                raise LXCatError(f"{self.where}: threshold below zero ({self.parameter} eV): an explicit "
                                 f"superelastic process is not read; write the excitation with <-> and its "
                                 f"statistical-weight ratio{suffix}")
        if self.kind in ("elastic", "effective") and (self.parameter is None or not self.parameter > 0):
            raise LXCatError(f"{self.where}: {self.kind} block needs a mass ratio m/M > 0; got {self.parameter}{suffix}")
        if self.weight_ratio is not None and not self.weight_ratio > 0:
            raise LXCatError(f"{self.where}: statistical-weight ratio must be > 0; got {self.weight_ratio}{suffix}")
        self.energy, self.cross_section = np.array(energy), np.array(sigma)
        return self


def _keyword(text: str) -> str | None:
    return text if text in KIND_OF else None


def _kind_from_process(text: str) -> str | None:
    kind = text.rsplit(",", 1)[-1].strip().upper()
    for keyword in KEYWORDS:
        if kind.startswith(keyword):
            return keyword
    return None


def _read_param(block: LXCatBlock, text: str) -> None:
    """``PARAM.: m/M = 1.4e-5`` / ``E = 11.5 eV, g1/g0 = 5``: used where the parameter line gave nothing."""
    mass = re.search(rf"m\s*/\s*M\s*=\s*({NUMBER})", text)
    loss = re.search(rf"(?<![\w/])E\s*=\s*({NUMBER})", text)
    ratio = re.search(rf"g\w*\s*/\s*g\w*\s*=\s*({NUMBER})", text)
    where = f"{block.source}, line {block.line}"
    if block.parameter is None:
        if mass and block.kind in ("elastic", "effective"):
            block.parameter = _number(mass.group(1), where)
        elif loss and block.kind in ("excitation", "ionization"):
            block.parameter = _number(loss.group(1), where)
    if ratio and block.weight_ratio is None and block.kind == "excitation":
        block.weight_ratio = _number(ratio.group(1), where)


def _header(block: LXCatBlock, lines: list[str], j: int) -> int:
    """Read the comment lines from ``j`` to the first dashes; return the index of the dashes (or where it broke)."""
    seen_species = False
    while j < len(lines) and not DASHES.match(lines[j]):
        text = lines[j].strip()
        upper = text.upper()
        if _keyword(text) or (upper.startswith("SPECIES:") and seen_species):  # the next block, before any table
            block.problem = f"{block.where}: block has no table (a new block starts at line {j + 1})"
            return j
        if upper.startswith("SPECIES:"):
            seen_species = True
            block.species = block.species or text.split(":", 1)[1].strip()
        elif upper.startswith("PROCESS:"):
            block.process = text.split(":", 1)[1].strip()
            block.reversible = block.reversible or "<->" in block.process
            if not block.keyword:
                block.keyword = _kind_from_process(block.process) or ""
                block.kind = KIND_OF.get(block.keyword, "")
        elif upper.startswith("PARAM.:"):
            _read_param(block, text)
        j += 1
    if j >= len(lines):
        block.problem = f"{block.where}: block has no table (no line of dashes follows)"
    return j


def _start(lines: list[str], i: int, source: str, database: str) -> tuple[LXCatBlock, int]:
    """The block's keyword, target and parameter lines; return the block and the index of its comment lines."""
    first = lines[i].strip()
    keyword = _keyword(first)
    block = LXCatBlock(KIND_OF.get(keyword, ""), "", i + 1, keyword=keyword or "", database=database, source=source)
    if keyword is None:  # a block that starts at its SPECIES: line
        return block, i
    j = i + 1
    if j < len(lines) and not lines[j].strip().upper().startswith("SPECIES:"):
        block.species = lines[j].strip()
        block.reversible = "<->" in block.species
        j += 1
        match = PARAMETER_LINE.match(lines[j]) if j < len(lines) else None
        if match:
            where = f"{source}, line {j + 1}"
            block.parameter = _number(match.group(1), where)
            if match.group(2) is not None and block.kind == "excitation":
                block.weight_ratio = _number(match.group(2), where)
            if block.kind == "attachment":
                block.parameter = None  # LXCat writes no parameter for attachment: a number here is its threshold 0
            j += 1
    return block, j


def _table(block: LXCatBlock, lines: list[str], j: int) -> int:
    """The table rows after the dashes at ``j``; return the index after the closing dashes."""
    k = j + 1
    while k < len(lines) and not DASHES.match(lines[k]):
        text = lines[k].strip()
        if _keyword(text):
            block.problem = f"{block.where}: table not closed by a line of dashes (a new block starts at line {k + 1})"
            return k
        if text:
            block.rows.append((k + 1, text))
        k += 1
    if k >= len(lines):
        block.problem = f"{block.source}, line {j + 1}: table not closed by a line of dashes"
        return k
    return k + 1


def _database_name(text: str) -> str:
    name = text.split(":", 1)[1].strip()
    return re.split(r"\s+\(|\s+database\b", name, maxsplit=1, flags=re.IGNORECASE)[0].strip() or name


def scan(text: str, source: str = "<string>") -> list[LXCatBlock]:
    """The blocks of an LXCat file's text, laid out but not checked (see :meth:`LXCatBlock.check`).

    Examples
    --------
    >>> from collisionkit.transport._lxcat_blocks import scan
    >>> text = "DATABASE: Test\\nEXCITATION\\nAr <-> Ar*\\n 11.5 / 3.0\\n-----\\n11.5 0\\n20 1e-21\\n-----\\n"
    >>> [(b.kind, b.target, b.parameter, b.weight_ratio, b.database) for b in scan(text)]
    [('excitation', 'Ar', 11.5, 3.0, 'Test')]
    """
    lines = [line.rstrip("\r\n") for line in text.splitlines()]
    blocks, i, database = [], 0, source.replace("\\", "/").rsplit("/", 1)[-1]
    while i < len(lines):
        stripped = lines[i].strip()
        upper = stripped.upper()
        if upper.startswith("DATABASE:"):
            database = _database_name(stripped)
        elif upper.startswith("PERMLINK:"):
            database = stripped.rstrip("/").rsplit("/", 1)[-1].strip() or database
        species_start = upper.startswith("SPECIES:") and i + 1 < len(lines) and \
            lines[i + 1].strip().upper().startswith("PROCESS:")
        if not (_keyword(stripped) or species_start):
            i += 1
            continue
        block, j = _start(lines, i, source, database)
        j = _header(block, lines, j)
        if block.problem is None:
            j = _table(block, lines, j)
        if not block.kind and block.problem is None:
            block.problem = f"{block.where}: cannot tell the process type (no keyword line, PROCESS: {block.process!r})"
        blocks.append(block)
        i = max(j, i + 1)
    return blocks
