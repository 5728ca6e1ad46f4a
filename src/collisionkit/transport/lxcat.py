"""Reader of LXCat cross-section files: both layouts, every process kind, several files, multi-database exports.

Blocks (see :mod:`collisionkit.transport._lxcat_blocks` for the layout):
ELASTIC and MOMENTUM (elastic momentum transfer), EFFECTIVE (momentum
transfer of all processes), EXCITATION, VIBRATIONAL, ROTATIONAL / ROTATION
(excitations), IONIZATION, ATTACHMENT, in the classic layout (keyword,
target, parameter lines) or the newer one (``SPECIES:`` / ``PROCESS:`` /
``PARAM.:`` lines). Species names follow :mod:`._lxcat_names`: ``Ar``,
``Ar <-> Ar*``, ``e / Ar`` and ``Ar(1S0)`` are all ``Ar``.

How a gas is made from the blocks:

* only the blocks of the species asked for are checked: a malformed block of
  another species (or of another database) is skipped with a note, never
  read;
* a species found in several databases (a multi-database export, or files
  from two databases) needs ``database=`` (its ``PERMLINK`` name, e.g.
  ``Biagi``; the file name for a file without ``DATABASE:`` lines);
* the mass ratio m/M comes from the ELASTIC or EFFECTIVE block; a file that
  brings a species without one (a rotational set) is read with a note when
  another file gives the species its elastic block, else refused;
* EFFECTIVE becomes an elastic momentum-transfer cross section
  ``sigma_eff - sum(inelastic of the same file)``, as BOLSIG+ does; a
  negative difference is clipped to 0 with a warning;
* a reversible excitation (``<->``, or a second number after the energy loss,
  or ``PARAM.: g1/g0 = ...``) gets ``Process.weight_ratio``: the given ratio,
  1 for ``<->`` without one (the BOLSIG+ convention written in LXCat
  headers).

Notes are :class:`LXCatWarning` (Python warnings); errors are
:class:`LXCatError` naming the file, the line and the block.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from pathlib import Path

import numpy as np
from scipy import constants

from ._lxcat_blocks import KEYWORDS, LXCatBlock, LXCatError, scan
from ._lxcat_names import product_formula, product_target, resolve_names, target_name
from .gases import Gas, Process, Species

__all__ = ["KEYWORDS", "LXCatError", "LXCatWarning", "LXCatBlock", "parse_lxcat", "read_lxcat", "lxcat_contents"]

PRESERVING = ("ELASTIC", "MOMENTUM", "EFFECTIVE", "ROTATIONAL", "ROTATION", "VIBRATIONAL")  # the target is unchanged
MOMENTUM_KINDS = ("elastic", "effective")


class LXCatWarning(UserWarning):
    """A note about an LXCat read: skipped blocks, clipped values, a set completed from another file.

    Examples
    --------
    >>> import warnings
    >>> from collisionkit.transport import LXCatWarning
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     warnings.warn("a note", LXCatWarning)
    >>> caught[0].category.__name__
    'LXCatWarning'
    """


# the laws read_lxcat converts itself (screened Coulomb: the file's momentum-transfer table to the integral one);
# the others are set with Gas.with_scattering, whose tables convert sigma_m in the kernel tables
READER_SCATTERING = ("isotropic", "screened_coulomb")


def _note(message: str) -> None:
    warnings.warn(message, LXCatWarning, stacklevel=3)


def parse_lxcat(text: str, source: str = "<string>") -> list[LXCatBlock]:
    """All process blocks of an LXCat file's text, each checked (LXCatError at the first malformed one).

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
    blocks = scan(text, source)
    if not blocks:
        raise LXCatError(f"{source}: no cross-section blocks found (expected {', '.join(KEYWORDS)} keywords)")
    return [block.check() for block in blocks]


def _read_file(path: Path) -> list[LXCatBlock]:
    """The blocks of one file, each with its species name resolved within the file (``name`` attribute)."""
    if path.is_dir():
        raise LXCatError(f"cross-section file {path} is a folder, not a file")
    try:
        text = path.read_text(encoding="utf-8", errors="replace")
    except FileNotFoundError:
        raise LXCatError(f"cross-section file not found: {path}") from None
    except OSError as failure:
        raise LXCatError(f"cross-section file {path} cannot be read: {failure.strerror or failure}") from None
    blocks = scan(text, str(path))
    if not blocks:
        raise LXCatError(f"{path}: no cross-section blocks found (expected {', '.join(KEYWORDS)} keywords)")
    products: dict[str, set] = {}
    for block in blocks:
        formula = product_formula(block.process) if block.keyword in PRESERVING and block.process else None
        if formula is not None:
            products.setdefault(block.target, set()).add(formula)
    resolved = resolve_names([block.target for block in blocks], products)
    for block in blocks:
        block.name = resolved.get(block.target, block.target)
        if block.kind in MOMENTUM_KINDS and block.target in resolved:  # elastic on a state: E + Oxygen -> E + O(1D)
            block.name = product_target(block.process) or block.name
    return blocks


def _paths(path) -> list[Path]:
    if isinstance(path, (str, Path)) or hasattr(path, "__fspath__"):
        return [Path(path)]
    paths = [Path(item) for item in path]
    if not paths:
        raise LXCatError("give at least one cross-section file")
    return paths


def _chosen_species(blocks, species) -> list[str]:
    names = list(dict.fromkeys(block.name for block in blocks))
    if species is None:
        return names
    chosen = []
    for wanted in ([species] if isinstance(species, str) else list(species)):
        spelled = target_name(str(wanted))
        match = next((b.name for b in blocks if spelled in (b.name, b.target) or wanted == b.species), None)
        if match is None:
            files = list(dict.fromkeys(Path(block.source).name for block in blocks))
            where = f"the file {files[0]}" if len(files) == 1 else f"the files {', '.join(files)}"
            raise LXCatError(f"species {wanted!r} is not in {where} (found {', '.join(names)})")
        chosen.append(match)
    return chosen


def _files(blocks) -> str:
    return ", ".join(dict.fromkeys(Path(block.source).name for block in blocks))


def _database_blocks(name, blocks, database):
    """The blocks of species ``name`` from one database (``database``: str, mapping or None)."""
    databases = list(dict.fromkeys(block.database for block in blocks))
    wanted = database.get(name) if isinstance(database, Mapping) else database
    if wanted is not None:
        key = str(wanted).lower()
        picked = [b for b in blocks if b.database.lower() == key or Path(b.source).name.lower() == key]
        if picked:
            return picked
        if len(databases) > 1 or isinstance(database, Mapping):
            raise LXCatError(f"species {name} is not in the database {wanted!r} in {_files(blocks)} "
                             f"(its databases: {', '.join(databases)})")
    if len(databases) > 1:
        raise LXCatError(f"species {name} is in {len(databases)} databases in {_files(blocks)}: "
                         f"{', '.join(databases)}; choose one with database= (--database), e.g. {databases[0]!r}")
    return blocks


def _momentum_block(name, blocks):
    momentum = [b for b in blocks if b.kind in MOMENTUM_KINDS]
    if not momentum:
        raise LXCatError(f"species {name} has no ELASTIC or EFFECTIVE block in {_files(blocks)} (its mass ratio and "
                         "momentum transfer): add the file of its complete set (a rotational set needs the file with "
                         "its elastic cross section), or leave the species out with species= (--species)")
    if len(momentum) > 1:
        places = "; ".join(f"{b.keyword or b.kind.upper()} in {b.where}" for b in momentum)
        raise LXCatError(f"species {name} has {len(momentum)} momentum-transfer blocks ({places}): a complete set "
                         "has one ELASTIC or one EFFECTIVE; choose the files or database= of one set")
    for source in dict.fromkeys(b.source for b in blocks):
        if source != momentum[0].source:
            count = sum(b.source == source for b in blocks)
            _note(f"{source}: its {count} processes of {name} have no elastic or effective block in this file; "
                  f"the elastic one comes from {momentum[0].source}")
    return momentum[0]


def _elastic_from_effective(effective: LXCatBlock, inelastic) -> np.ndarray:
    """sigma_eff - sum(inelastic) at the effective table's energies, clipped at 0 with a warning."""
    sigma = effective.cross_section.copy()
    for other in inelastic:
        sigma -= np.interp(effective.energy, other.energy, other.cross_section, left=0.0,
                           right=other.cross_section[-1])
    negative = sigma < 0
    if np.any(negative):
        worst = int(np.argmin(sigma))
        low, high = effective.energy[negative].min(), effective.energy[negative].max()
        _note(f"{effective.where} ({effective.title}): effective minus inelastic cross sections is negative at "
              f"{int(negative.sum())} of {sigma.size} energies, {low:g} to {high:g} eV (down to {sigma[worst]:.3g} "
              "m^2; inelastic tables count as constant beyond their last energy); clipped to 0")
    return np.maximum(sigma, 0.0)


def _process(block: LXCatBlock, effective_elastic=None) -> Process:
    label = block.process or f"{block.keyword.lower() or block.kind} {block.species}".strip()
    if block.kind in MOMENTUM_KINDS:
        sigma = block.cross_section if effective_elastic is None else effective_elastic
        return Process("elastic", block.energy, sigma, label=label, scattering="isotropic")
    threshold = block.parameter if block.kind in ("excitation", "ionization") else 0.0
    ratio = 0.0
    if block.kind == "excitation" and (block.reversible or block.weight_ratio is not None):
        ratio = block.weight_ratio if block.weight_ratio is not None else 1.0
    try:
        return Process(block.kind, block.energy, block.cross_section, threshold=threshold, label=label,
                       weight_ratio=ratio)
    except ValueError as refused:
        raise LXCatError(f"{block.where}: {refused} ({block.title})") from None


def _species(name, blocks, scattering, screening_energy) -> Species:
    for block in blocks:
        block.check()
    momentum = _momentum_block(name, blocks)
    inelastic = [b for b in blocks if b.kind not in MOMENTUM_KINDS]
    elastic = None
    if momentum.kind == "effective":
        elastic = _elastic_from_effective(momentum, [b for b in inelastic if b.source == momentum.source])
    processes = [_process(b, elastic if b is momentum else None) for b in blocks if b.kind not in MOMENTUM_KINDS
                 or b is momentum]
    levels = [b for b in inelastic if b.initial_level() is not None]
    if levels:
        _note(f"{_files(levels)}: {len(levels)} processes of {name} start from a given rotational or vibrational "
              f"level (e.g. {levels[0].process or levels[0].species!r}, from {levels[0].initial_level()}); the swarm "
              f"applies each to the whole {name} density (collisionkit has no populations of these levels), so "
              "their rates are those of a gas wholly in that level")
    species = Species(name, constants.m_e / momentum.parameter, tuple(processes))
    if scattering != "screened_coulomb":
        return species
    from .gases import screened_coulomb_momentum_ratio

    converted = []
    for p in species.processes:
        if p.kind == "elastic":
            ratio = screened_coulomb_momentum_ratio(p.energy, screening_energy)
            p = Process("elastic", p.energy, p.cross_section / ratio, label=p.label, scattering=scattering,
                        screening_energy=screening_energy)
        converted.append(p)
    return Species(name, species.mass, tuple(converted))


def _skipped_note(blocks, used) -> None:
    used = {id(block) for block in used}
    for source in dict.fromkeys(b.source for b in blocks):
        skipped = [b for b in blocks if b.source == source and id(b) not in used]
        if not skipped:
            continue
        names = list(dict.fromkeys(f"{b.name} ({b.database})" if b.database != Path(b.source).name else b.name
                                   for b in skipped))
        broken = sum(b.problem is not None for b in skipped)
        fault = f"; {broken} of them malformed, not read" if broken else ""
        shown = ", ".join(names[:8]) + (f" and {len(names) - 8} more" if len(names) > 8 else "")
        _note(f"{source}: skipped {len(skipped)} blocks of {shown} (not asked for{fault})")


def read_lxcat(path, species=None, fractions=None, database=None, scattering="isotropic",
               screening_energy=1.0) -> Gas:
    """Read LXCat files into a :class:`~collisionkit.transport.Gas`.

    Parameters
    ----------
    path : str or Path, or a sequence of them
        One file or several (joined: a species may take its processes from
        several files, e.g. a rotational set next to its complete set).
    species : str or sequence of str, optional
        Targets to keep (default: every target of the files), by name
        (``N2``; ``N2(X)`` or the file's spelling also find it).
    fractions : sequence of float, optional
        Number fractions of those targets (default: equal).
    database : str or mapping, optional
        The database to take a species from when the files hold it from
        several (a multi-database export): the ``PERMLINK`` name (``Biagi``,
        ``IST-Lisbon``) or the file name; a mapping ``{species: database}``
        chooses per species.
    scattering : {"isotropic", "screened_coulomb"}
        Angular model of elastic collisions; for screened Coulomb the file's
        momentum-transfer cross section is divided by <1 - cos chi>.
    screening_energy : float
        eV, see :func:`~collisionkit.transport.screened_coulomb_momentum_ratio`.

    Raises
    ------
    LXCatError
        A missing file, a species not in the files, a species in several
        databases without ``database``, a malformed block of a species used
        (naming file, line and block), a species without elastic block.

    Warns
    -----
    LXCatWarning
        Blocks skipped, effective-minus-inelastic values clipped, a species
        completed from another file, level-resolved processes.

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
    if scattering not in READER_SCATTERING:
        # the other laws convert sigma_m in the kernel tables: converting here too would do it twice
        raise ValueError(f"scattering must be one of {READER_SCATTERING} here; got {scattering!r}: for "
                         "okhrimovskyy, vahedi-surendra or forward call .with_scattering(law) on the gas read")
    blocks = [block for file in _paths(path) for block in _read_file(file)]
    chosen = _chosen_species(blocks, species)
    if fractions is not None and len(list(fractions)) != len(chosen):
        raise LXCatError(f"fractions: give one per species ({len(chosen)}: {', '.join(chosen)}); got {len(list(fractions))}")
    if isinstance(database, str):
        key = database.lower()
        if not any(b.database.lower() == key or Path(b.source).name.lower() == key for b in blocks if b.name in chosen):
            found = ", ".join(dict.fromkeys(b.database for b in blocks if b.name in chosen))
            raise LXCatError(f"database {database!r} holds none of {', '.join(chosen)} in {_files(blocks)} "
                             f"(their databases: {found})")
    used, members = [], []
    for name in chosen:
        own = _database_blocks(name, [b for b in blocks if b.name == name], database)
        used.extend(own)
        members.append(own)
    if species is not None or database is not None:
        _skipped_note(blocks, used)
    gas_species = tuple(_species(name, own, scattering, screening_energy) for name, own in zip(chosen, members))
    return Gas(gas_species, tuple(fractions) if fractions is not None else ())


def lxcat_contents(path) -> list[dict]:
    """What LXCat files hold: one entry per species and database, with its processes counted by kind.

    Nothing is checked (a malformed block is counted, marked in ``malformed``).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from collisionkit.transport.lxcat import lxcat_contents
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (folder / "x.txt").write_text("ELASTIC\\nX\\n1e-4\\n-----\\n0 1e-20\\n-----\\n")
    >>> lxcat_contents(folder / "x.txt")[0]["processes"]
    {'elastic': 1}
    """
    entries: dict[tuple[str, str], dict] = {}
    for block in (block for file in _paths(path) for block in _read_file(file)):
        entry = entries.setdefault((block.name, block.database), {
            "species": block.name, "database": block.database, "processes": {}, "malformed": 0, "files": []})
        kind = "elastic" if block.kind in MOMENTUM_KINDS else block.kind or "unknown"
        entry["processes"][kind] = entry["processes"].get(kind, 0) + 1
        entry["malformed"] += block.problem is not None
        if block.source not in entry["files"]:
            entry["files"].append(block.source)
    return list(entries.values())
