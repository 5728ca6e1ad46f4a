"""The catalogue of real gases: LXCat cross-section sets by name, shipped or placed in the data folder.

Sets whose terms allow it ship with collisionkit (``transport/data/``, the
files as their authors distribute them, headers kept; their terms are in
``transport/data/README.md``). Sets that may not ship are listed with the
LXCat page to download them from: saved as ``<name>.txt`` in the data folder
(:func:`data_folder`: ``$COLLISIONKIT_DATA``, else the platform's user data
folder) they are used by name like the shipped ones. Any other LXCat file
saved there as ``<name>.txt`` (one species) is usable by its name too.

A gas is named by a set (``"Ar"``) or a mixture of sets by mole fraction
(``"Ar:0.9,N2:0.1"``, fractions summing to 1 within 1e-6)::

    gas = catalogue_gas("Ar")                 # a Gas, ready for simulate_swarm
    gas = catalogue_gas("Ar:0.9,N2:0.1")
    [entry.name for entry in catalogue()]     # what there is; entry.status(): shipped, placed, missing
"""

from __future__ import annotations

import math
import os
import sys
import warnings
from dataclasses import dataclass
from pathlib import Path

from .gases import Gas
from .lxcat import LXCatError, LXCatWarning, lxcat_contents, read_lxcat

__all__ = ["GasSet", "CATALOGUE", "catalogue", "catalogue_entry", "catalogue_gas", "catalogue_files", "data_folder",
           "parse_gas_spec", "catalogue_rows", "FRACTION_TOLERANCE"]

DATA = Path(__file__).parent / "data"
FRACTION_TOLERANCE = 1e-6
IST_LISBON = "L.L. Alves, J. Phys.: Conf. Ser. 565, 012007 (2014), IST-Lisbon database, www.lxcat.net"
GPL = "GPL-3.0 (distributed by the database's authors in LoKI-B, github.com/IST-Lisbon/LoKI)"
LXCAT_TERMS = "LXCat terms: download it yourself from LXCat (no redistribution by third parties)"


@dataclass(frozen=True)
class GasSet:
    """One set of the catalogue: a species' complete cross-section set from one database.

    Attributes
    ----------
    name : str
        The name that picks it (``--gas Ar``).
    species : str
        The species it holds, as the reader names it.
    database : str
        The LXCat database (its PERMLINK name).
    reference : str
        What to cite.
    file : str
        The file: in the package's data folder if ``shipped``, else the name
        to save the download under in :func:`data_folder`.
    shipped : bool
        Whether the file ships with collisionkit.
    url : str
        Where to get it (the LXCat database page).
    terms : str
        The terms the file is under.
    cite : str
        The reference, short (``Yanguas-Gil et al. 2005``).

    Examples
    --------
    >>> from collisionkit.transport import CATALOGUE
    >>> CATALOGUE["Ar"].species, CATALOGUE["Ar"].shipped
    ('Ar', True)
    """

    name: str
    species: str
    database: str
    reference: str
    file: str
    shipped: bool
    url: str
    terms: str
    cite: str = ""

    def path(self) -> Path | None:
        """The file if it is here (shipped, or placed in the data folder), else None.

        Examples
        --------
        >>> from collisionkit.transport import CATALOGUE
        >>> CATALOGUE["Ar"].path().name
        'IST-Lisbon_Ar.txt'
        """
        path = (DATA if self.shipped else data_folder()) / self.file
        return path if path.is_file() else None

    def status(self) -> str:
        """``shipped``, ``placed`` (saved in the data folder) or ``missing``.

        Examples
        --------
        >>> from collisionkit.transport import CATALOGUE
        >>> CATALOGUE["N2"].status()
        'shipped'
        """
        if self.shipped:
            return "shipped"
        return "placed" if self.path() is not None else "missing"

    def where(self) -> str:
        """How to get the set: the shipped file, or where to download it and where to save it.

        Examples
        --------
        >>> from collisionkit.transport import CATALOGUE
        >>> CATALOGUE["Ar"].where().startswith("shipped")
        True
        """
        if self.shipped:
            return f"shipped with collisionkit ({self.file})"
        return (f"download {self.species} from {self.url} (LXCat: choose the {self.database} database, species "
                f"{self.species}, download as text) and save it as {data_folder() / self.file}")

    def gas(self) -> Gas:
        """The set as a :class:`~collisionkit.transport.Gas` (LXCatError if it is missing or unreadable).

        Examples
        --------
        >>> from collisionkit.transport import CATALOGUE
        >>> [p.kind for p in CATALOGUE["O2"].gas().species[0].processes][:2]
        ['attachment', 'elastic']
        """
        path = self.path()
        if path is None:
            raise LXCatError(f"gas {self.name!r} is not here: {self.where()}")
        species = None if not self.species else [self.species]
        database = self.database or None
        blocks = lxcat_contents(path)
        if len({entry["database"] for entry in blocks if entry["species"] == self.species}) <= 1:
            database = None  # one database in the file: no need to name it
        return read_lxcat(path, species=species, database=database)


def _ist_lisbon(name: str, set_reference: str, cite: str) -> GasSet:
    return GasSet(name, name, "IST-Lisbon", f"{set_reference}; {IST_LISBON}", f"IST-Lisbon_{name}.txt", True,
                  "https://www.lxcat.net/IST-Lisbon", GPL, cite)


def _download(name: str, species: str, database: str, reference: str, cite: str) -> GasSet:
    return GasSet(name, species, database, reference, f"{name}.txt", False, f"https://www.lxcat.net/{database}",
                  LXCAT_TERMS, cite)


CATALOGUE: dict[str, GasSet] = {entry.name: entry for entry in (
    _ist_lisbon("Ar", "A. Yanguas-Gil, J. Cotrino and L.L. Alves, J. Phys. D 38, 1588 (2005)",
                "Yanguas-Gil et al. 2005"),
    _ist_lisbon("N2", "J. Loureiro and C.M. Ferreira, J. Phys. D 19, 17 (1986)", "Loureiro & Ferreira 1986"),
    _ist_lisbon("O2", "L.L. Alves, P. Coche, M.A. Ridenti and V. Guerra, Eur. Phys. J. D 70, 124 (2016)",
                "Alves et al. 2016"),
    _ist_lisbon("He", "M. Santos, C. Noel, T. Belmonte and L.L. Alves, J. Phys. D 47, 265201 (2014)",
                "Santos et al. 2014"),
    _download("Ar-Biagi", "Ar", "Biagi", "S.F. Biagi, Magboltz (Fortran code), Biagi database, www.lxcat.net",
              "Biagi, Magboltz"),
    _download("Ar-Phelps", "Ar", "Phelps", "A.V. Phelps, Phelps database, www.lxcat.net", "Phelps"),
    _download("N2-Biagi", "N2", "Biagi", "S.F. Biagi, Magboltz (Fortran code), Biagi database, www.lxcat.net",
              "Biagi, Magboltz"),
    _download("N2-Phelps", "N2", "Phelps", "A.V. Phelps and L.C. Pitchford, Phys. Rev. A 31, 2932 (1985); "
                                         "Phelps database, www.lxcat.net", "Phelps & Pitchford 1985"),
    _download("O2-Phelps", "O2", "Phelps", "A.V. Phelps, JILA Information Center Report 28 (1985); Phelps database, "
                                         "www.lxcat.net", "Phelps 1985"),
)}


def data_folder() -> Path:
    """The folder of placed cross-section files: ``$COLLISIONKIT_DATA``, else the platform's user data folder.

    The default is ``%LOCALAPPDATA%\\collisionkit`` on Windows,
    ``~/Library/Application Support/collisionkit`` on macOS and
    ``$XDG_DATA_HOME/collisionkit`` (``~/.local/share/collisionkit``)
    elsewhere. It is not created here.

    Examples
    --------
    >>> import os
    >>> from unittest import mock
    >>> from collisionkit.transport import data_folder
    >>> with mock.patch.dict(os.environ, {"COLLISIONKIT_DATA": "/tmp/my-gases"}):
    ...     str(data_folder())
    '/tmp/my-gases'
    """
    chosen = os.environ.get("COLLISIONKIT_DATA")
    if chosen:
        return Path(chosen).expanduser()
    home = Path.home()
    if sys.platform == "win32":
        base = Path(os.environ.get("LOCALAPPDATA") or home / "AppData" / "Local")
    elif sys.platform == "darwin":
        base = home / "Library" / "Application Support"
    else:
        base = Path(os.environ.get("XDG_DATA_HOME") or home / ".local" / "share")
    return base / "collisionkit"


def _placed_files() -> list[GasSet]:
    """Sets saved in the data folder under names the catalogue does not have (``<name>.txt``)."""
    folder = data_folder()
    if not folder.is_dir():
        return []
    taken = {entry.file for entry in CATALOGUE.values() if not entry.shipped} | set(CATALOGUE)
    found = []
    for path in sorted(folder.glob("*.txt")):
        name = path.stem
        if path.name in taken or name in CATALOGUE or any(mark in name for mark in ":,") or not path.is_file():
            continue
        found.append(GasSet(name, "", "", f"placed by you ({path.name})", path.name, False, str(path),
                            "your own download", "your file"))
    return found


def catalogue() -> list[GasSet]:
    """Every set: the catalogue's, then the other files placed in the data folder.

    Examples
    --------
    >>> from collisionkit.transport import catalogue
    >>> [entry.name for entry in catalogue()][:4]
    ['Ar', 'N2', 'O2', 'He']
    """
    return list(CATALOGUE.values()) + _placed_files()


def catalogue_entry(name: str) -> GasSet:
    """The set called ``name`` (ValueError listing the names if there is none).

    Examples
    --------
    >>> from collisionkit.transport import catalogue_entry
    >>> catalogue_entry("N2").database
    'IST-Lisbon'
    """
    entries = {entry.name: entry for entry in catalogue()}
    if name not in entries:
        raise ValueError(f"gas {name!r} is not in the catalogue; choose one of {', '.join(entries)} "
                         "(collisionkit gases lists them), or read a file with --cross-sections")
    return entries[name]


def parse_gas_spec(spec: str) -> list[tuple[str, float]]:
    """``"Ar"`` or ``"Ar:0.9,N2:0.1"`` as ``[(name, fraction)]``, fractions checked to sum to 1 (within 1e-6).

    Examples
    --------
    >>> from collisionkit.transport import parse_gas_spec
    >>> parse_gas_spec("Ar:0.9, N2:0.1")
    [('Ar', 0.9), ('N2', 0.1)]
    >>> parse_gas_spec("Ar:0.9,N2:0.2")
    Traceback (most recent call last):
    ...
    ValueError: gas 'Ar:0.9,N2:0.2': mole fractions must sum to 1 (within 1e-06); they sum to 1.1
    """
    if not isinstance(spec, str) or not spec.strip():
        raise ValueError(f"gas must be a catalogue name or a mixture such as 'Ar:0.9,N2:0.1'; got {spec!r}")
    parts = [part.strip() for part in spec.split(",")]
    if len(parts) == 1 and ":" not in parts[0]:
        return [(parts[0], 1.0)]
    mixture = []
    for part in parts:
        name, colon, text = part.partition(":")
        if not colon or not name.strip():
            raise ValueError(f"gas {spec!r}: write each part as NAME:FRACTION (e.g. 'Ar:0.9,N2:0.1'); got {part!r}")
        try:
            fraction = float(text)
        except ValueError:
            raise ValueError(f"gas {spec!r}: the fraction of {name.strip()} must be a number; got {text!r}") from None
        if not (math.isfinite(fraction) and 0.0 <= fraction <= 1.0):
            raise ValueError(f"gas {spec!r}: the fraction of {name.strip()} must lie in [0, 1]; got {text.strip()}")
        mixture.append((name.strip(), fraction))
    names = [name for name, _ in mixture]
    twice = sorted({name for name in names if names.count(name) > 1})
    if twice:
        raise ValueError(f"gas {spec!r}: {twice[0]} is named twice")
    total = math.fsum(fraction for _, fraction in mixture)
    if abs(total - 1.0) > FRACTION_TOLERANCE:
        raise ValueError(f"gas {spec!r}: mole fractions must sum to 1 (within {FRACTION_TOLERANCE:g}); they sum to "
                         f"{total:.10g}")
    return mixture


def catalogue_files(spec: str) -> list[Path]:
    """The files a gas name or mixture reads (ValueError or LXCatError if a set is unknown or missing).

    Examples
    --------
    >>> from collisionkit.transport import catalogue_files
    >>> [path.name for path in catalogue_files("Ar:0.5,N2:0.5")]
    ['IST-Lisbon_Ar.txt', 'IST-Lisbon_N2.txt']
    """
    files = []
    for name, _ in parse_gas_spec(spec):
        entry = catalogue_entry(name)
        path = entry.path()
        if path is None:
            raise LXCatError(f"gas {name!r} is not here: {entry.where()}")
        files.append(path)
    return files


def catalogue_gas(spec: str) -> Gas:
    """The :class:`~collisionkit.transport.Gas` a catalogue name or mixture names.

    Parameters
    ----------
    spec : str
        A set's name (``"Ar"``) or a mixture by mole fraction
        (``"Ar:0.9,N2:0.1"``).

    Raises
    ------
    ValueError
        An unknown name (the message lists the names), bad fractions, or a
        set that is not here (:class:`~collisionkit.transport.LXCatError`,
        saying where to download it).

    Examples
    --------
    >>> from collisionkit.transport import catalogue_gas
    >>> gas = catalogue_gas("Ar:0.9,N2:0.1")
    >>> [s.name for s in gas.species], [round(f, 6) for f in gas.fractions]
    (['Ar', 'N2'], [0.9, 0.1])
    """
    mixture = parse_gas_spec(spec)
    parts, names = {}, {}
    for name, fraction in mixture:
        gas = catalogue_entry(name).gas()
        if len(gas.species) != 1:
            raise LXCatError(f"gas {name!r} holds {len(gas.species)} species "
                             f"({', '.join(s.name for s in gas.species)}): read it with --cross-sections and --species")
        species = gas.species[0].name
        if species in names:
            raise ValueError(f"gas {spec!r}: {names[species]} and {name} are both the species {species}; take one")
        names[species] = name
        parts[gas] = fraction
    if len(parts) == 1:
        return next(iter(parts))
    return Gas.mixture(parts)


def catalogue_rows() -> list[dict]:
    """One row per set for ``collisionkit gases``: name, species, database, reference, processes, status, where.

    The processes are counted by kind from the file (``elastic``,
    ``excitation``, ``ionization``, ``attachment``); a missing set has none.

    Examples
    --------
    >>> from collisionkit.transport.catalogue import catalogue_rows
    >>> row = catalogue_rows()[0]
    >>> row["name"], row["status"], row["processes"]["ionization"]
    ('Ar', 'shipped', 1)
    """
    rows = []
    for entry in catalogue():
        path = entry.path()
        counts, species, database = {}, entry.species, entry.database
        if path is not None:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", LXCatWarning)
                try:
                    contents = lxcat_contents(path)
                except LXCatError:
                    contents = []
            chosen = [c for c in contents if not entry.species or c["species"] == entry.species]
            if entry.database and len(chosen) > 1:
                chosen = [c for c in chosen if c["database"].lower() == entry.database.lower()] or chosen
            for content in chosen:
                for kind, count in content["processes"].items():
                    counts[kind] = counts.get(kind, 0) + count
            species = species or ", ".join(dict.fromkeys(c["species"] for c in chosen))
            database = database or ", ".join(dict.fromkeys(c["database"] for c in chosen))
        rows.append({"name": entry.name, "species": species, "database": database, "reference": entry.reference,
                     "cite": entry.cite,
                     "processes": counts, "status": entry.status(), "where": entry.where(), "terms": entry.terms,
                     "file": str(path) if path is not None else str(data_folder() / entry.file)})
    return rows
