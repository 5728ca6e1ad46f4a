"""The result of a swarm run: :class:`SwarmResult`, with its dictionary (JSON) and table-row forms."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import MISSING, dataclass, field

import numpy as np

from .._repr import dataclass_repr

__all__ = ["SwarmResult"]

# the phase-resolved arrays of an oscillating field (empty for a static one)
PHASE_FIELDS = ("phases", "mean_energy_by_phase", "mean_energy_by_phase_error", "drift_velocity_flux_by_phase",
                "drift_velocity_flux_by_phase_error")


@dataclass
class SwarmResult:
    """Transport coefficients of one swarm run (SI units, energies in eV).

    Every value has an ``*_error`` partner (standard error over the
    independent groups). N-scaled coefficients are per unit gas density.
    ``eedf`` is the energy distribution (1/eV) at the bin centres
    ``eedf_energy``, which span [0, 4 <e>) of the swarm when sampling began;
    ``eedf_above`` is the fraction of it beyond the last bin (in no bin, so
    the EEDF integrates to ``1 - eedf_above``). ``alpha_N`` and ``eta_N``
    are the Townsend ionization and attachment coefficients over N (m^2) of
    steady-state Townsend conditions, from the bulk coefficients
    (:func:`~collisionkit.transport.townsend_coefficients`; NaN where the
    SST relation has no root, and in results saved before they existed).
    ``drift_diffusion_L_correlation`` and ``drift_diffusion_T_correlation``
    are the correlations over the groups of the bulk drift along E with
    N D_L and N D_T (for the error of a ratio of them, as
    :func:`~collisionkit.transport.detector_coefficients` takes it; NaN in
    results saved before they existed).
    ``extras["bound_violations"]`` (only when the module switch
    ``collisionkit.transport.swarm.CHECK_BOUND`` is on) counts the trial
    collisions at which the true collision rate exceeded the trial bound:
    0 for an exact run.

    The frame is right-handed with E along +z and B in the y-z plane at
    ``field_angle`` degrees from E: ``B = |B| (0, sin psi, cos psi)``. The
    drift velocities are 3-vectors in it; ``diffusion_N_flux`` and
    ``diffusion_N_bulk`` are the full 3x3 tensors N D (1/m/s): bulk, half
    the time slope of the position covariance, ``(1/2) d/dt (<r_i r_j> -
    <r_i><r_j>)``; flux, the symmetrised correlation ``(1/2) (<r_i v_j> +
    <r_j v_i>) - (1/2) (<r_i><v_j> + <r_j><v_i>)`` (only the symmetric part
    enters the diffusion equation, ``D : grad grad n``; Robson, Ness, White).
    The scalar ``diffusion_L_N`` is the zz element and ``diffusion_T_N`` the
    mean of xx and yy (which differ in a magnetic field: use the tensor).

    An oscillating field E0 cos(omega t) (``reduced_frequency`` = omega/N,
    rad m^3/s, 0 for a static field) adds the quantities resolved in phase
    over a period: ``phases`` (omega t mod 2 pi, radians),
    ``mean_energy_by_phase`` and ``drift_velocity_flux_by_phase`` (one
    3-vector per phase), each with its error; ``mean_energy`` and
    ``drift_velocity_flux`` are then their averages over the phases (the
    cycle averages) and the bulk quantities slopes over whole cycles. Empty
    for a static field.

    Examples
    --------
    >>> from collisionkit.transport import maxwell_model, simulate_swarm
    >>> result = simulate_swarm(maxwell_model(), 10.0, particles=1000, groups=4, seed=1,
    ...                         tolerances={"mean_energy": 0.05})
    >>> result.mean_energy > 0, result.drift_velocity_bulk.shape
    (True, (3,))
    """

    __repr__ = dataclass_repr  # arrays by their shape, not printed whole

    reduced_field: float
    reduced_magnetic_field: float
    gas_temperature: float
    mean_energy: float
    mean_energy_error: float
    drift_velocity_flux: np.ndarray
    drift_velocity_flux_error: np.ndarray
    drift_velocity_bulk: np.ndarray
    drift_velocity_bulk_error: np.ndarray
    diffusion_L_N_flux: float
    diffusion_L_N_flux_error: float
    diffusion_T_N_flux: float
    diffusion_T_N_flux_error: float
    diffusion_L_N: float
    diffusion_L_N_error: float
    diffusion_T_N: float
    diffusion_T_N_error: float
    rate_coefficients: dict
    rate_coefficient_errors: dict
    ionization_frequency_N: float
    ionization_frequency_N_error: float
    attachment_frequency_N: float
    attachment_frequency_N_error: float
    eedf_energy: np.ndarray
    eedf: np.ndarray
    eedf_above: float
    collisions: int
    null_collisions: int
    seconds: float
    simulated_time: float
    steady_from: float
    particles: int
    groups: int
    converged: bool
    extras: dict = field(default_factory=dict)
    alpha_N: float = math.nan
    alpha_N_error: float = math.nan
    eta_N: float = math.nan
    eta_N_error: float = math.nan
    drift_diffusion_L_correlation: float = math.nan
    drift_diffusion_T_correlation: float = math.nan
    field_angle: float = 90.0
    reduced_frequency: float = 0.0
    diffusion_N_flux: np.ndarray = field(default_factory=lambda: np.full((3, 3), math.nan))
    diffusion_N_flux_error: np.ndarray = field(default_factory=lambda: np.full((3, 3), math.nan))
    diffusion_N_bulk: np.ndarray = field(default_factory=lambda: np.full((3, 3), math.nan))
    diffusion_N_bulk_error: np.ndarray = field(default_factory=lambda: np.full((3, 3), math.nan))
    phases: np.ndarray = field(default_factory=lambda: np.zeros(0))
    mean_energy_by_phase: np.ndarray = field(default_factory=lambda: np.zeros(0))
    mean_energy_by_phase_error: np.ndarray = field(default_factory=lambda: np.zeros(0))
    drift_velocity_flux_by_phase: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    drift_velocity_flux_by_phase_error: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))

    @property
    def collisions_per_second(self) -> float:
        """Real collisions per wall-clock second."""
        return self.collisions / self.seconds if self.seconds > 0 else 0.0

    def relative_error(self, name: str) -> float:
        """Relative standard error of ``mean_energy``, ``drift_velocity_bulk`` (z), ``diffusion_L_N`` ...

        Examples
        --------
        >>> from collisionkit.transport import maxwell_model, simulate_swarm
        >>> result = simulate_swarm(maxwell_model(), 10.0, particles=1000, groups=4, seed=1,
        ...                         tolerances={"mean_energy": 0.05})
        >>> result.relative_error("mean_energy") < 0.05
        True
        """
        value = np.asarray(getattr(self, name), dtype=float)
        error = np.asarray(getattr(self, f"{name}_error"), dtype=float)
        if value.ndim:
            value, error = value[2], error[2]
        return float(abs(error / value)) if value != 0 else math.inf

    def to_dict(self) -> dict:
        """A JSON-ready dictionary (vectors as lists, with ``collisions_per_second``).

        Examples
        --------
        >>> import json
        >>> from collisionkit.transport import maxwell_model, simulate_swarm
        >>> data = simulate_swarm(maxwell_model(), 10.0, particles=1000, groups=4, seed=1,
        ...                       tolerances={"mean_energy": 0.05}).to_dict()
        >>> "collisions_per_second" in data, len(json.dumps(data)) > 100
        (True, True)
        """
        out = {}
        for name in self.__dataclass_fields__:
            value = getattr(self, name)
            out[name] = value.tolist() if isinstance(value, np.ndarray) else value
        out["collisions_per_second"] = self.collisions_per_second
        return out

    @classmethod
    def from_dict(cls, data: Mapping) -> SwarmResult:
        """The result back from :meth:`to_dict` output (after a JSON round trip too: the ``null`` that
        strict JSON writers put for NaN and infinities reads back as NaN).

        Examples
        --------
        >>> import json
        >>> from collisionkit.transport import maxwell_model, simulate_swarm
        >>> result = simulate_swarm(maxwell_model(), 10.0, particles=1000, groups=4, seed=1,
        ...                         tolerances={"mean_energy": 0.05})
        >>> SwarmResult.from_dict(json.loads(json.dumps(result.to_dict()))).mean_energy == result.mean_energy
        True
        """
        if not isinstance(data, Mapping):
            raise TypeError(f"data must be a mapping (SwarmResult.to_dict output); got {type(data).__name__}")
        missing = [name for name, spec in cls.__dataclass_fields__.items() if name not in data
                   and spec.default is MISSING and spec.default_factory is MISSING]  # with a default: may be older
        if missing:
            raise ValueError(f"data is not a SwarmResult.to_dict output: missing {', '.join(missing)}")
        values = {}
        for name, spec in cls.__dataclass_fields__.items():
            if name not in data:
                continue
            values[name] = _from_json(data[name], spec.type)
            if name.startswith("drift_velocity_flux_by_phase") and values[name].size == 0:
                values[name] = values[name].reshape(0, 3)  # a static run's empty table of 3-vectors
        return cls(**values)

    def to_row(self) -> dict:
        """The scalars as one flat row for a table (CSV, pandas): vectors split into ``_x``, ``_y``, ``_z``,
        tensors into ``_xx``, ``_xy`` ... ``_zz``, rate coefficients as ``rate_coefficient[label]``; the EEDF
        arrays, the phase-resolved arrays and ``extras`` left out.

        Examples
        --------
        >>> from collisionkit.transport import maxwell_model, simulate_swarm
        >>> row = simulate_swarm(maxwell_model(), 10.0, particles=1000, groups=4, seed=1,
        ...                      tolerances={"mean_energy": 0.05}).to_row()
        >>> row["reduced_field"], "drift_velocity_bulk_z" in row, "rate_coefficient[maxwell:elastic]" in row
        (10.0, True, True)
        """
        row = {}
        for name in self.__dataclass_fields__:
            value = getattr(self, name)
            if name in ("eedf_energy", "eedf", "extras") or name in PHASE_FIELDS:
                continue
            if isinstance(value, np.ndarray) and value.ndim == 2:
                row |= {f"{name}_{first}{second}": float(value[i, j]) for i, first in enumerate("xyz")
                        for j, second in enumerate("xyz")}
            elif isinstance(value, np.ndarray):
                row |= {f"{name}_{axis}": float(component) for axis, component in zip("xyz", value)}
            elif isinstance(value, dict):
                prefix = "rate_coefficient" if name == "rate_coefficients" else "rate_coefficient_error"
                row |= {f"{prefix}[{label}]": float(rate) for label, rate in value.items()}
            else:
                row[name] = value
        row["collisions_per_second"] = self.collisions_per_second
        return row


def _nan_for_none(value):
    """A (nested) list with None read as NaN."""
    if isinstance(value, (list, tuple)):
        return [_nan_for_none(item) for item in value]
    return math.nan if value is None else value


def _from_json(value, kind: str):
    """A to_dict value of a field of type ``kind`` ("float", "np.ndarray", "dict" ...), None read as NaN."""
    if kind == "np.ndarray":
        return np.array(_nan_for_none(value), dtype=float)
    if kind == "float":
        return math.nan if value is None else float(value)
    if kind == "dict" and isinstance(value, Mapping):
        return {key: math.nan if item is None else item for key, item in value.items()}
    return value
