"""Reader of LXCat cross-section files (classic blocks and the SPECIES:/PROCESS:/PARAM.: style).

A block starts with a keyword line (ELASTIC, EFFECTIVE, EXCITATION,
IONIZATION, ATTACHMENT), then the target species (``Ar`` or
``Ar -> Ar*``), then - except for ATTACHMENT - a number: the mass ratio m/M
(ELASTIC, EFFECTIVE) or the threshold energy in eV (EXCITATION,
IONIZATION). Comment lines follow until a line of five or more dashes; the
table (energy in eV, cross section in m^2) runs to the next dashes line.
Newer files add ``SPECIES: e / Ar``, ``PROCESS: E + Ar -> E + Ar*, Excitation``
and ``PARAM.: E = 11.5 eV`` (or ``m/M = 1.36e-5``) lines in the comment
part; a block may also start directly at its ``SPECIES:`` line, the kind then
being read from the ``PROCESS:`` line. Everything outside blocks is ignored.

EFFECTIVE (momentum transfer of all processes) becomes an elastic momentum
transfer cross section ``sigma_eff - sum(inelastic)`` (clipped at 0), as
BOLSIG+ does.

Malformed input raises :class:`LXCatError` (a ValueError) naming the file and line.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy import constants

from .gases import Gas, Process, Species

__all__ = ["LXCatError", "LXCatBlock", "parse_lxcat", "read_lxcat"]

KEYWORDS = ("ELASTIC", "EFFECTIVE", "MOMENTUM", "EXCITATION", "IONIZATION", "ATTACHMENT", "ROTATION", "ROTATIONAL")
KIND_OF = {"ELASTIC": "elastic", "EFFECTIVE": "effective", "MOMENTUM": "elastic", "EXCITATION": "excitation",
           "ROTATION": "excitation", "ROTATIONAL": "excitation", "IONIZATION": "ionization",
           "ATTACHMENT": "attachment"}
DASHES = re.compile(r"^-{5,}\s*$")
NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eEdD][-+]?\d+)?"


class LXCatError(ValueError):
    """A malformed or unphysical LXCat file; the message names the line.

    Examples
    --------
    >>> from collisionkit.transport import LXCatError, parse_lxcat
    >>> try:
    ...     parse_lxcat(chr(10).join(["ELASTIC", "Ar", " not a number", "-----", "1 2", "-----"]))
    ... except LXCatError as error:
    ...     print("refused")
    refused
    """


@dataclass
class LXCatBlock:
    """One process block as read from the file.

    Examples
    --------
    >>> from collisionkit.transport.lxcat import LXCatBlock
    >>> LXCatBlock(kind="EXCITATION", species="Ar", line=12, parameter=11.5).parameter
    11.5
    """

    kind: str
    species: str
    line: int
    parameter: float | None = None
    process: str = ""
    energy: np.ndarray = field(default_factory=lambda: np.zeros(0))
    cross_section: np.ndarray = field(default_factory=lambda: np.zeros(0))

    @property
    def target(self) -> str:
        """The target name: ``Ar`` from ``Ar -> Ar*`` or ``e / Ar``."""
        name = self.species.split("->")[0].split("<->")[0]
        if "/" in name:
            name = name.split("/")[-1]
        return name.strip()


def _number(text, where):
    try:
        return float(text.replace("d", "e").replace("D", "e"))
    except ValueError:
        raise LXCatError(f"{where}: expected a number, got {text!r}") from None


def _kind_from_process(text, where):
    kind = text.rsplit(",", 1)[-1].strip().upper()
    for keyword in KEYWORDS:
        if kind.startswith(keyword):
            return KIND_OF[keyword]
    raise LXCatError(f"{where}: cannot tell the process type from PROCESS: {text!r}")


def _param(block, text, where):
    match = re.search(r"(m/M|E)\s*=\s*(" + NUMBER + ")", text)
    if match:
        value = _number(match.group(2), where)
        if match.group(1) == "E" and block.kind in ("excitation", "ionization"):
            block.parameter = value
        elif match.group(1) == "m/M" and block.kind in ("elastic", "effective"):
            block.parameter = value


def _read_table(lines, start, source):
    """Rows from ``start`` to the closing dashes; return (energy, sigma, next index)."""
    rows = []
    i = start
    while i < len(lines):
        text = lines[i].strip()
        if DASHES.match(text):
            return np.array([r[0] for r in rows]), np.array([r[1] for r in rows]), i + 1
        where = f"{source}, line {i + 1}"
        parts = text.split()
        if len(parts) < 2:
            raise LXCatError(f"{where}: expected two numbers (energy, cross section) in the table, got {text!r}")
        energy, sigma = _number(parts[0], where), _number(parts[1], where)
        if energy < 0:
            raise LXCatError(f"{where}: negative energy {energy}")
        if sigma < 0:
            raise LXCatError(f"{where}: negative cross section {sigma}")
        if rows and energy <= rows[-1][0]:
            raise LXCatError(f"{where}: energies must increase ({energy} after {rows[-1][0]})")
        rows.append((energy, sigma))
        i += 1
    raise LXCatError(f"{source}, line {start}: table not closed by a line of dashes")


def _read_block(lines, i, source):
    """Parse the block starting at line index ``i``; return (block, next index)."""
    first = lines[i].strip()
    where = f"{source}, line {i + 1}"
    keyword = first.split()[0].upper() if first else ""
    if keyword in KIND_OF:
        if i + 1 >= len(lines):
            raise LXCatError(f"{where}: {keyword} block ends before its species line")
        block = LXCatBlock(KIND_OF[keyword], lines[i + 1].strip(), i + 1)
        j = i + 2
        if block.kind != "attachment" and j < len(lines) and re.match(r"^\s*" + NUMBER + r"(\s|$)", lines[j]):
            block.parameter = _number(lines[j].split()[0], f"{source}, line {j + 1}")
            j += 1
    else:  # a block that starts at SPECIES:
        block = LXCatBlock("", first.split(":", 1)[1].strip(), i + 1)
        j = i + 1
    while j < len(lines) and not DASHES.match(lines[j].strip()):
        text = lines[j].strip()
        upper = text.upper()
        here = f"{source}, line {j + 1}"
        if upper.startswith("SPECIES:") and block.kind:
            block.species = text.split(":", 1)[1].strip()
        elif upper.startswith("PROCESS:"):
            block.process = text.split(":", 1)[1].strip()
            if not block.kind:
                block.kind = _kind_from_process(block.process, here)
        elif upper.startswith("PARAM.:") and block.kind:
            _param(block, text, here)
        j += 1
    if j >= len(lines):
        raise LXCatError(f"{where}: block has no table (no line of dashes follows)")
    if not block.kind:
        raise LXCatError(f"{where}: block without a process type (no keyword line and no PROCESS: line)")
    block.energy, block.cross_section, j = _read_table(lines, j + 1, source)
    _check_block(block, where)
    return block, j


def _check_block(block, where):
    if block.energy.size == 0:
        raise LXCatError(f"{where}: empty cross-section table")
    if block.kind in ("excitation", "ionization"):
        if block.parameter is None:
            raise LXCatError(f"{where}: {block.kind} block needs a threshold energy (eV)")
        if block.parameter < 0:
            raise LXCatError(f"{where}: threshold below zero ({block.parameter} eV)")
    if block.kind in ("elastic", "effective"):
        if block.parameter is None or not block.parameter > 0:
            raise LXCatError(f"{where}: {block.kind} block needs a mass ratio m/M > 0; got {block.parameter}")


def parse_lxcat(text: str, source: str = "<string>") -> list[LXCatBlock]:
    """All process blocks of an LXCat file's text.

    Examples
    --------
    >>> from collisionkit.transport.lxcat import parse_lxcat
    >>> text = '''EXCITATION
    ... Ar -> Ar*(11.5eV)
    ... 11.5
    ... -----
    ... 11.5 0
    ... 20 1e-21
    ... -----
    ... '''
    >>> [(b.kind, b.target, b.parameter, b.energy.size) for b in parse_lxcat(text)]
    [('excitation', 'Ar', 11.5, 2)]
    """
    lines = text.splitlines()
    blocks, i = [], 0
    while i < len(lines):
        stripped = lines[i].strip()
        keyword = stripped.split()[0].upper() if stripped else ""
        starts_at_species = stripped.upper().startswith("SPECIES:") and i + 1 < len(lines) and (
            lines[i + 1].strip().upper().startswith("PROCESS:"))
        if stripped == keyword and keyword in KIND_OF or starts_at_species:
            block, i = _read_block(lines, i, source)
            blocks.append(block)
        else:
            i += 1
    if not blocks:
        raise LXCatError(f"{source}: no cross-section blocks found (expected ELASTIC, EXCITATION, ... keywords)")
    return blocks


def _species_from_blocks(name, blocks, scattering, screening_energy):
    masses = [b.parameter for b in blocks if b.kind in ("elastic", "effective")]
    if not masses:
        raise LXCatError(f"species {name}: no ELASTIC or EFFECTIVE block (needed for the mass ratio)")
    mass = constants.m_e / masses[0]
    inelastic = [b for b in blocks if b.kind in ("excitation", "ionization", "attachment")]
    processes = []
    for b in blocks:
        label = b.process or f"{b.kind} {b.species}"
        if b.kind in ("elastic", "effective"):
            sigma = b.cross_section.copy()
            if b.kind == "effective":
                for other in inelastic:
                    sigma -= np.interp(b.energy, other.energy, other.cross_section, left=0.0,
                                       right=other.cross_section[-1])
                sigma = np.maximum(sigma, 0.0)
            processes.append(Process("elastic", b.energy, sigma, label=label, scattering="isotropic"))
        else:
            threshold = b.parameter if b.kind != "attachment" else 0.0
            processes.append(Process(b.kind, b.energy, b.cross_section, threshold=threshold, label=label))
    species = Species(name, mass, tuple(processes))
    if scattering != "isotropic":
        from .gases import screened_coulomb_momentum_ratio

        converted = []
        for p in species.processes:
            if p.kind == "elastic":
                ratio = screened_coulomb_momentum_ratio(p.energy, screening_energy)
                p = Process("elastic", p.energy, p.cross_section / ratio, label=p.label, scattering=scattering,
                            screening_energy=screening_energy)
            converted.append(p)
        species = Species(name, mass, tuple(converted))
    return species


def read_lxcat(path, species=None, fractions=None, scattering="isotropic", screening_energy=1.0) -> Gas:
    """Read an LXCat file into a :class:`~collisionkit.transport.Gas`.

    Parameters
    ----------
    path : str or Path
    species : sequence of str, optional
        Targets to keep (default: every target in the file).
    fractions : sequence of float, optional
        Number fractions of those targets (default: equal).
    scattering : {"isotropic", "screened_coulomb"}
        Angular model of elastic collisions; for screened Coulomb the file's
        momentum-transfer cross section is divided by <1 - cos chi>.
    screening_energy : float
        eV, see :func:`~collisionkit.transport.screened_coulomb_momentum_ratio`.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from collisionkit.transport import read_lxcat
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (folder / "he.txt").write_text("ELASTIC\\nHe\\n1.37e-4\\n-----\\n0 6e-20\\n100 6e-20\\n-----\\n")
    >>> gas = read_lxcat(folder / "he.txt")
    >>> gas.species[0].name, round(gas.species[0].mass / 9.1093837e-31 * 1.37e-4, 6)
    ('He', 1.0)
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8", errors="replace")
    except FileNotFoundError:
        raise LXCatError(f"cross-section file not found: {path}") from None
    blocks = parse_lxcat(text, str(path))
    names = list(dict.fromkeys(b.target for b in blocks))
    chosen = list(species) if species is not None else names
    missing = [name for name in chosen if name not in names]
    if missing:
        raise LXCatError(f"{path}: species {missing} not in the file (found {names})")
    members = tuple(_species_from_blocks(name, [b for b in blocks if b.target == name], scattering, screening_energy)
                    for name in chosen)
    return Gas(members, tuple(fractions) if fractions is not None else ())
