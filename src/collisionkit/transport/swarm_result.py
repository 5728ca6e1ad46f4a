"""The result of a swarm run: :class:`SwarmResult`, with its dictionary (JSON) and table-row forms."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import MISSING, dataclass, field

import numpy as np

__all__ = ["SwarmResult"]


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
    ``extras["bound_violations"]`` (only when the module switch
    ``collisionkit.transport.swarm.CHECK_BOUND`` is on) counts the trial
    collisions at which the true collision rate exceeded the trial bound:
    0 for an exact run.

    Examples
    --------
    >>> from collisionkit.transport import maxwell_model, simulate_swarm
    >>> result = simulate_swarm(maxwell_model(), 10.0, particles=1000, groups=4, seed=1,
    ...                         tolerances={"mean_energy": 0.05})
    >>> result.mean_energy > 0, result.drift_velocity_bulk.shape
    (True, (3,))
    """

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
        return cls(**values)

    def to_row(self) -> dict:
        """The scalars as one flat row for a table (CSV, pandas): vectors split into ``_x``, ``_y``, ``_z``,
        rate coefficients as ``rate_coefficient[label]``; the EEDF arrays and ``extras`` left out.

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
            if name in ("eedf_energy", "eedf", "extras"):
                continue
            if isinstance(value, np.ndarray):
                row |= {f"{name}_{axis}": float(component) for axis, component in zip("xyz", value)}
            elif isinstance(value, dict):
                prefix = "rate_coefficient" if name == "rate_coefficients" else "rate_coefficient_error"
                row |= {f"{prefix}[{label}]": float(rate) for label, rate in value.items()}
            else:
                row[name] = value
        row["collisions_per_second"] = self.collisions_per_second
        return row


def _from_json(value, kind: str):
    """A to_dict value of a field of type ``kind`` ("float", "np.ndarray", "dict" ...), None read as NaN."""
    if kind == "np.ndarray":
        return np.array([math.nan if item is None else item for item in value], dtype=float)
    if kind == "float":
        return math.nan if value is None else float(value)
    if kind == "dict" and isinstance(value, Mapping):
        return {key: math.nan if item is None else item for key, item in value.items()}
    return value
