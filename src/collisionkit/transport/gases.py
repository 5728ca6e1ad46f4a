"""Gases for the transport engine: collision processes, species, mixtures, model gases.

A :class:`Process` is one collision channel of a projectile with a target
species: a cross section tabulated against the projectile energy in the
target's rest frame (linear interpolation, constant beyond the last point,
zero below the threshold) plus an optional constant rate coefficient
``k`` (``nu = N (sigma g + k)``; the Maxwell model is ``sigma = 0``, ``k > 0``).
A :class:`Species` is a target with its mass and processes; a :class:`Gas`
is a mixture of species with number fractions.

Units: energies in eV, cross sections in m^2, rate coefficients in m^3/s,
masses in kg.
"""

from __future__ import annotations

import dataclasses
import math
import numbers
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
from scipy import constants

from .. import _arrays
from .angular import SCATTERING_LAWS, screened_coulomb_momentum_ratio

__all__ = [
    "PROCESS_KINDS",
    "SCATTERING_KINDS",
    "SCATTERING_MODELS",
    "Process",
    "Species",
    "Gas",
    "maxwell_model",
    "hard_sphere_gas",
    "reid_ramp",
    "lucas_saelee",
    "model_gas",
    "MODEL_GASES",
    "screened_coulomb_momentum_ratio",
]

PROCESS_KINDS = ("elastic", "excitation", "ionization", "attachment")
# the kinds an angular law is chosen for: the process kinds and the superelastic inverses of reversible excitations
SCATTERING_KINDS = PROCESS_KINDS + ("superelastic",)
SCATTERING_MODELS = SCATTERING_LAWS + ("screened_coulomb",)

ELECTRON_MASS = constants.m_e
AMU = constants.atomic_mass


def _number(value, name: str, owner: str):
    """``value`` if it is a real number (numpy's too), else a TypeError naming ``owner``'s ``name``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{owner}: {name} must be a number; got {value!r}")
    return value


def _checked_table(energy, cross_section, label):
    energy = _arrays.as_float_array(energy, f"{label} energy")
    cross_section = _arrays.as_float_array(cross_section, f"{label} cross_section")
    for name, table in (("energy", energy), ("cross_section", cross_section)):
        if table.ndim > 1:
            raise ValueError(f"{label}: {name} must be a 1-D table; got shape {table.shape}")
    energy, cross_section = energy.reshape(-1), cross_section.reshape(-1)
    if energy.shape != cross_section.shape:
        raise ValueError(f"{label}: energy and cross_section must have the same length; got {energy.size} and {cross_section.size}")
    _arrays.require_finite(energy, f"{label} energy")
    _arrays.require_finite(cross_section, f"{label} cross_section")
    _arrays.require_in_range(energy, f"{label} energy", 0.0, math.inf)
    _arrays.require_in_range(cross_section, f"{label} cross_section (m^2)", 0.0, math.inf)
    if energy.size and np.any(np.diff(energy) <= 0):
        raise ValueError(f"{label}: energies must be strictly increasing")
    return energy, cross_section


@dataclass(frozen=True, eq=False)
class Process:
    """One collision process with a target species.

    Parameters
    ----------
    kind : {"elastic", "excitation", "ionization", "attachment"}
    energy : array_like
        Projectile energies of the table (eV, strictly increasing, >= 0).
    cross_section : array_like
        Cross sections at those energies (m^2, >= 0).
    threshold : float
        Energy lost (excitation) or ionization energy (eV, >= 0); the cross
        section is zero below it.
    rate_coefficient : float
        Constant rate coefficient k (m^3/s, >= 0) added to ``sigma * g``.
    scattering : {"isotropic", "okhrimovskyy", "vahedi-surendra", "forward", "screened_coulomb"}
        Angular distribution in the centre-of-mass frame
        (:mod:`collisionkit.transport.angular`). An elastic table (or rate
        coefficient) is a momentum-transfer cross section: with
        ``okhrimovskyy`` or ``vahedi-surendra`` the swarm samples
        ``sigma_m / (1 - <cos chi>)``; ``forward`` transfers no momentum, so
        an elastic process refuses it. ``screened_coulomb`` takes the table
        as the integral cross section (convert a momentum-transfer one with
        :func:`screened_coulomb_momentum_ratio`). The tables of the other
        kinds are integral cross sections under every law.
    screening_energy : float
        Screened Coulomb only: eta = screening_energy / (4 eps) (eV, > 0).
    label : str
    weight_ratio : float
        Excitation only: the ratio g_final / g_initial of the statistical
        weights of the excited and the ground level (LXCat writes it after
        the threshold of a reversible ``<->`` process). 0 (the default) makes
        the process one-way; > 0 allows its superelastic inverse by detailed
        balance (Klein-Rosseland; :mod:`collisionkit.transport.superelastic`).
        A reversible process needs a cross-section table (no rate coefficient).
    superelastic_scattering : str
        Angular law of the superelastic inverse (one of ``scattering``'s).
    population : float or None
        Reversible excitations only: the fraction of the species in the
        excited level, in [0, 1). None (the default): Boltzmann at the gas
        temperature (:func:`~collisionkit.transport.superelastic.level_populations`).

    Examples
    --------
    >>> from collisionkit.transport import Process
    >>> p = Process("excitation", [0.2, 10.0], [0.0, 9.8e-19], threshold=0.2, label="ramp")
    >>> p.kind, p.threshold
    ('excitation', 0.2)
    """

    kind: str
    energy: np.ndarray = field(default_factory=lambda: np.zeros(0))
    cross_section: np.ndarray = field(default_factory=lambda: np.zeros(0))
    threshold: float = 0.0
    rate_coefficient: float = 0.0
    scattering: str = "isotropic"
    screening_energy: float = 1.0
    label: str = ""
    weight_ratio: float = 0.0
    superelastic_scattering: str = "isotropic"
    population: float | None = None

    def __repr__(self) -> str:
        """A line, not the table: ``Process('excitation', label='ramp', threshold=0.2, points=2)``."""
        return (f"Process({self.kind!r}, label={self.label!r}, threshold={float(self.threshold):g}, "
                f"points={len(self.energy)})")

    def __post_init__(self):
        if self.kind not in PROCESS_KINDS:
            raise ValueError(f"kind must be one of {PROCESS_KINDS}; got {self.kind!r}")
        for name in ("scattering", "superelastic_scattering"):
            if getattr(self, name) not in SCATTERING_MODELS:
                raise ValueError(f"{name} must be one of {SCATTERING_MODELS}; got {getattr(self, name)!r}")
        label = self.label or self.kind
        energy, sigma = _checked_table(self.energy, self.cross_section, label)
        object.__setattr__(self, "energy", energy)
        object.__setattr__(self, "cross_section", sigma)
        object.__setattr__(self, "label", label)
        for name in ("threshold", "rate_coefficient", "weight_ratio", "screening_energy"):
            _number(getattr(self, name), name, label)
        for name, low in (("threshold", 0.0), ("rate_coefficient", 0.0), ("weight_ratio", 0.0)):
            value = float(getattr(self, name))
            if not (math.isfinite(value) and value >= low):
                raise ValueError(f"{label}: {name} must be finite and >= 0; got {value}")
            object.__setattr__(self, name, value)
        if not (self.screening_energy > 0 and math.isfinite(self.screening_energy)):
            raise ValueError(f"{label}: screening_energy must be > 0 (eV); got {self.screening_energy}")
        if energy.size == 0 and self.rate_coefficient == 0.0:
            raise ValueError(f"{label}: give a cross-section table or a rate_coefficient > 0")
        if self.weight_ratio > 0.0 and self.kind != "excitation":
            raise ValueError(f"{label}: weight_ratio (a superelastic inverse) applies to excitation only")
        if self.weight_ratio > 0.0 and self.rate_coefficient > 0.0:
            raise ValueError(f"{label}: a reversible excitation (weight_ratio > 0) needs a cross-section table, not a "
                             "rate coefficient (its superelastic rate would diverge at zero energy)")
        if self.kind == "elastic" and self.scattering == "forward":
            raise ValueError(f"{label}: forward scattering transfers no momentum, so an elastic (momentum-transfer) "
                             "cross section cannot be scattered forward: sigma_m / (1 - <cos chi>) is infinite; use "
                             "isotropic, okhrimovskyy or vahedi-surendra")
        if self.population is not None:
            if self.weight_ratio <= 0.0:
                raise ValueError(f"{label}: population (of the excited level) applies to a reversible excitation "
                                 "(weight_ratio > 0) only")
            value = float(self.population)
            if not (0.0 <= value < 1.0):
                raise ValueError(f"{label}: population must lie in [0, 1) (fraction of the species in the excited "
                                 f"level); got {value}")
            object.__setattr__(self, "population", value)

    def cross_section_at(self, energy):
        """The tabulated cross section (m^2) at ``energy`` (eV): linear between the points, constant beyond the last;
        below the first point constant for elastic, zero for the other kinds, and zero below the threshold.

        Examples
        --------
        >>> from collisionkit.transport import reid_ramp
        >>> excitation = reid_ramp().species[0].processes[1]
        >>> [float(x) for x in excitation.cross_section_at([0.1, 1.2])]
        [0.0, 1e-19]
        """
        energy = _arrays.as_finite_in_range(energy, "energy", 0.0)
        if self.energy.size == 0:
            return np.zeros_like(energy)
        left = self.cross_section[0] if self.kind == "elastic" else 0.0
        sigma = np.interp(energy, self.energy, self.cross_section, left=left, right=self.cross_section[-1])
        if self.kind != "elastic":
            sigma = np.where(energy < self.threshold, 0.0, sigma)
        return sigma

    @property
    def reversible(self) -> bool:
        """True for an excitation with a superelastic inverse (``weight_ratio > 0``)."""
        return self.weight_ratio > 0.0

    def with_scattering(self, scattering: str, screening_energy: float = 1.0) -> "Process":
        """The same process with another angular model.

        Examples
        --------
        >>> from collisionkit.transport import reid_ramp
        >>> elastic = reid_ramp().species[0].processes[0]
        >>> elastic.with_scattering("screened_coulomb", screening_energy=0.5).scattering
        'screened_coulomb'
        """
        return dataclasses.replace(self, scattering=scattering, screening_energy=screening_energy)


@dataclass(frozen=True, eq=False)
class Species:
    """A target species: name, mass (kg) and its processes.

    Examples
    --------
    >>> from collisionkit.transport import Species, Process
    >>> he = Species("He", 4 * 1.66053906660e-27, (Process("elastic", [0, 100], [6e-20, 6e-20]),))
    >>> he.name, len(he.processes)
    ('He', 1)
    """

    name: str
    mass: float
    processes: tuple[Process, ...]

    def __post_init__(self):
        _number(self.mass, "mass (kg)", f"species {self.name}")
        if not (self.mass > 0 and math.isfinite(self.mass)):
            raise ValueError(f"mass of {self.name} must be > 0 and finite (kg); got {self.mass}")
        processes = (self.processes,) if isinstance(self.processes, Process) else tuple(self.processes)
        if not processes:
            raise ValueError(f"species {self.name} needs at least one process")
        if not all(isinstance(p, Process) for p in processes):
            raise TypeError(f"processes of {self.name} must be Process objects")
        object.__setattr__(self, "processes", processes)

    def __repr__(self) -> str:
        """A line, not the tables: ``Species('N2', mass=4.652e-26, processes=26)``."""
        return f"Species({self.name!r}, mass={self.mass:.4g}, processes={len(self.processes)})"


@dataclass(frozen=True, eq=False)
class Gas:
    """A gas: species with number fractions (summing to 1).

    Examples
    --------
    >>> from collisionkit.transport import reid_ramp, hard_sphere_gas, Gas
    >>> mix = Gas.mixture({reid_ramp(): 0.5, hard_sphere_gas(1e-19, name="HS"): 0.5})
    >>> [s.name for s in mix.species], mix.fractions
    (['reid', 'HS'], (0.5, 0.5))
    """

    species: tuple[Species, ...]
    fractions: tuple[float, ...] = ()

    def __post_init__(self):
        species = (self.species,) if isinstance(self.species, Species) else tuple(self.species)
        if not species:
            raise ValueError("a gas needs at least one species")
        if not all(isinstance(s, Species) for s in species):
            raise TypeError(f"species must be Species objects; got {[type(s).__name__ for s in species]}")
        fractions = tuple(float(f) for f in self.fractions) or tuple(1.0 / len(species) for _ in species)
        if len(fractions) != len(species):
            raise ValueError(f"fractions must have one value per species ({len(species)}); got {len(fractions)}")
        if any(not (f >= 0 and math.isfinite(f)) for f in fractions) or not math.isclose(sum(fractions), 1.0, rel_tol=1e-9):
            raise ValueError(f"fractions must be >= 0 and sum to 1; got {fractions}")
        object.__setattr__(self, "species", species)
        object.__setattr__(self, "fractions", fractions)

    def __repr__(self) -> str:
        """A line, not the tables: ``Gas(species=['N2'], fractions=[1.0], processes=26)``."""
        return (f"Gas(species={[member.name for member in self.species]!r}, "
                f"fractions={[float(fraction) for fraction in self.fractions]!r}, processes={len(self.processes)})")

    @classmethod
    def mixture(cls, parts) -> "Gas":
        """Mix gases: ``{gas_or_species: fraction}``; fractions are normalised to sum 1.

        Examples
        --------
        >>> from collisionkit.transport import Gas, hard_sphere_gas, reid_ramp
        >>> mixture = Gas.mixture({reid_ramp(): 3.0, hard_sphere_gas(): 1.0})
        >>> [float(f) for f in mixture.fractions]
        [0.75, 0.25]
        """
        species, fractions = [], []
        total = float(sum(parts.values()))
        if not total > 0:
            raise ValueError(f"mixture fractions must sum to > 0; got {total}")
        for part, fraction in parts.items():
            if fraction < 0:
                raise ValueError(f"mixture fractions must be >= 0; got {fraction}")
            members = part.species if isinstance(part, Gas) else (part,)
            inner = part.fractions if isinstance(part, Gas) else (1.0,)
            for member, share in zip(members, inner):
                species.append(member)
                fractions.append(fraction / total * share)
        return cls(tuple(species), tuple(fractions))

    @property
    def processes(self) -> list[tuple[int, Process]]:
        """(species index, process) for every process of every species."""
        return [(s, p) for s, member in enumerate(self.species) for p in member.processes]

    def with_scattering(self, scattering, screening_energy: float = 1.0, kinds=("elastic",)) -> "Gas":
        """The gas with another angular law for the processes of ``kinds``.

        Parameters
        ----------
        scattering : str or mapping
            A law of :data:`SCATTERING_MODELS` for every kind in ``kinds``, or
            a mapping ``{kind: law}`` (then ``kinds`` is not used). Kinds are
            those of :data:`SCATTERING_KINDS`: ``"superelastic"`` sets the law
            of the inverses of reversible excitations.
        screening_energy : float
            eV, for ``screened_coulomb``.
        kinds : sequence of str

        Examples
        --------
        >>> from collisionkit.transport import reid_ramp
        >>> gas = reid_ramp().with_scattering("screened_coulomb")
        >>> [process.scattering for process in gas.species[0].processes]
        ['screened_coulomb', 'isotropic']
        >>> gas = reid_ramp().with_scattering({"elastic": "okhrimovskyy", "excitation": "forward"})
        >>> [process.scattering for process in gas.species[0].processes]
        ['okhrimovskyy', 'forward']
        """
        laws = _laws_by_kind(scattering, kinds)

        def changed(p: Process) -> Process:
            inverse = p.kind == "excitation" and "superelastic" in laws
            if p.kind not in laws and not inverse:
                return p
            return dataclasses.replace(p, scattering=laws.get(p.kind, p.scattering), screening_energy=screening_energy,
                                       superelastic_scattering=laws["superelastic"] if inverse else
                                       p.superelastic_scattering)

        species = tuple(Species(s.name, s.mass, tuple(changed(p) for p in s.processes)) for s in self.species)
        return Gas(species, self.fractions)

    def with_populations(self, populations) -> "Gas":
        """The gas with set populations of excited levels: ``{"species:label": fraction}`` of reversible excitations.

        A fraction is that of the species' density in the process's excited
        level (see :func:`~collisionkit.transport.superelastic.level_populations`);
        ``None`` puts a level back to Boltzmann at the gas temperature.

        Examples
        --------
        >>> from collisionkit.transport import Gas, Process, Species
        >>> gas = Gas((Species("x", 6.6e-27, (Process("elastic", [0, 10], [1e-20, 1e-20]),
        ...            Process("excitation", [0.1, 10], [0, 1e-20], threshold=0.1, weight_ratio=3.0, label="x*"))),))
        >>> gas.with_populations({"x:x*": 0.2}).species[0].processes[1].population
        0.2
        """
        if not isinstance(populations, Mapping):
            raise TypeError(f"populations must be a mapping of 'species:label' to fractions; got {populations!r}")
        reversible = {f"{s.name}:{p.label}": (i, k) for i, s in enumerate(self.species)
                      for k, p in enumerate(s.processes) if p.reversible}
        counts: dict[str, int] = {}
        for s in self.species:
            for p in s.processes:
                counts[f"{s.name}:{p.label}"] = counts.get(f"{s.name}:{p.label}", 0) + 1
        unknown = [key for key in populations if key not in reversible]
        if unknown:
            choices = ", ".join(sorted(reversible)) or "none: the gas has no reversible excitation (weight_ratio > 0)"
            raise ValueError(f"populations: {unknown[0]!r} is not a reversible excitation of the gas; "
                             f"choices: {choices}")
        ambiguous = [key for key in populations if counts[key] > 1]
        if ambiguous:
            raise ValueError(f"populations: {ambiguous[0]!r} names more than one process of the gas")
        species = [list(s.processes) for s in self.species]
        for key, fraction in populations.items():
            i, k = reversible[key]
            species[i][k] = dataclasses.replace(species[i][k], population=fraction)
        return Gas(tuple(Species(s.name, s.mass, tuple(processes)) for s, processes in zip(self.species, species)),
                   self.fractions)


def _laws_by_kind(scattering, kinds) -> dict[str, str]:
    """``{kind: law}`` from a law and kinds, or from a mapping; ValueError naming an unknown kind or law."""
    laws = dict(scattering) if isinstance(scattering, Mapping) else {kind: scattering for kind in (
        [kinds] if isinstance(kinds, str) else kinds)}
    for kind, law in laws.items():
        if kind not in SCATTERING_KINDS:
            raise ValueError(f"scattering: kind must be one of {', '.join(SCATTERING_KINDS)}; got {kind!r}")
        if law not in SCATTERING_MODELS:
            raise ValueError(f"scattering[{kind!r}] must be one of {', '.join(SCATTERING_MODELS)}; got {law!r}")
    return laws


# ------------------------------------------------------------------ model gases


def maxwell_model(rate_coefficient=1e-13, mass=4 * AMU, name="maxwell") -> Gas:
    r"""Maxwell model gas: elastic, isotropic, constant collision frequency ``nu = N k``.

    Exact swarm results (any mass ratio): drift velocity
    :math:`W = qE/(\mu \nu)` and mean energy
    :math:`\langle\epsilon\rangle = \tfrac32 kT + \tfrac12 (m + M) W^2`
    (Wannier; see e.g. White, Robson, Dujko et al., J. Phys. D 42, 194001 (2009)).

    Examples
    --------
    >>> from collisionkit.transport import maxwell_model
    >>> gas = maxwell_model(2e-13)
    >>> gas.species[0].processes[0].rate_coefficient
    2e-13
    """
    return Gas((Species(name, float(mass), (Process("elastic", rate_coefficient=rate_coefficient, label="elastic"),)),))


def hard_sphere_gas(cross_section=6e-20, mass=4 * AMU, name="hard_sphere", top_energy=1000.0) -> Gas:
    """Hard-sphere gas: elastic, isotropic, constant cross section (m^2).

    Examples
    --------
    >>> from collisionkit.transport import hard_sphere_gas
    >>> float(hard_sphere_gas(1e-19).species[0].processes[0].cross_section[0])
    1e-19
    """
    process = Process("elastic", [0.0, top_energy], [cross_section, cross_section], label="elastic")
    return Gas((Species(name, float(mass), (process,)),))


REID_MASS_RATIO = 1.37145e-4


def reid_ramp(top_energy=100.0) -> Gas:
    r"""Reid's ramp model (Reid, Aust. J. Phys. 32, 231 (1979)).

    Elastic :math:`\sigma = 6 \times 10^{-20}` m^2, m/M = 1.37145e-4;
    excitation :math:`\sigma = 10^{-19} (\epsilon - 0.2)` m^2 (eps in eV)
    above 0.2 eV; gas at 0 K. Tabulated up to ``top_energy`` (eV), far above
    the energies reached at E/N <= 100 Td.

    Examples
    --------
    >>> from collisionkit.transport import reid_ramp
    >>> [p.label for p in reid_ramp().species[0].processes]
    ['elastic', 'excitation']
    """
    elastic = Process("elastic", [0.0, top_energy], [6e-20, 6e-20], label="elastic")
    excitation = Process("excitation", [0.2, top_energy], [0.0, 1e-19 * (top_energy - 0.2)], threshold=0.2,
                         label="excitation")
    return Gas((Species("reid", ELECTRON_MASS / REID_MASS_RATIO, (elastic, excitation)),))


def lucas_saelee(F=0.5, mass=4 * AMU, top_energy=1000.0) -> Gas:
    r"""Lucas-Saelee model (Lucas & Saelee, J. Phys. D 8, 640 (1975)).

    Elastic :math:`\sigma = 4 \epsilon^{-1/2}` Angstrom^2, i.e. a constant
    rate coefficient :math:`k = 4\times10^{-20}\,\sqrt{2e/m_e}` m^3/s;
    excitation :math:`0.1 (1 - F)(\epsilon - 15.6)` Angstrom^2 and
    ionization :math:`0.1 F (\epsilon - 15.6)` Angstrom^2 above 15.6 eV.
    The gas mass is a parameter (4 amu by default).

    Examples
    --------
    >>> from collisionkit.transport import lucas_saelee
    >>> [p.kind for p in lucas_saelee(0.5).species[0].processes]
    ['elastic', 'excitation', 'ionization']
    """
    if not 0.0 <= F <= 1.0:
        raise ValueError(f"F must lie in [0, 1]; got {F}")
    k = 4e-20 * math.sqrt(2.0 * constants.e / ELECTRON_MASS)
    ramp = 1e-21 * (top_energy - 15.6)
    processes = [Process("elastic", rate_coefficient=k, label="elastic"),
                 Process("excitation", [15.6, top_energy], [0.0, (1 - F) * ramp], threshold=15.6, label="excitation"),
                 Process("ionization", [15.6, top_energy], [0.0, F * ramp], threshold=15.6, label="ionization")]
    processes = [p for p in processes if p.kind == "elastic" or p.cross_section[-1] > 0]
    return Gas((Species("lucas_saelee", float(mass), tuple(processes)),))


MODEL_GASES = {
    "maxwell": maxwell_model,
    "hard_sphere": hard_sphere_gas,
    "reid": reid_ramp,
    "lucas_saelee": lucas_saelee,
}


def model_gas(name: str) -> Gas:
    """A built-in model gas by name: maxwell, hard_sphere, reid, lucas_saelee.

    Examples
    --------
    >>> from collisionkit.transport import model_gas
    >>> model_gas("reid").species[0].name
    'reid'
    """
    if name not in MODEL_GASES:
        raise ValueError(f"model must be one of {sorted(MODEL_GASES)}; got {name!r}")
    return MODEL_GASES[name]()
