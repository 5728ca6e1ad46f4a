"""The ``slab`` command's physics as checked parameters, and its summary."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from typing import Any

from .._params import Parameters, check_choice, check_integer, check_real, check_seed
from .slab import SlabResult, simulate_slab

__all__ = ["SlabParameters", "run_slab", "slab_summary"]


@dataclasses.dataclass(frozen=True)
class SlabParameters(Parameters):
    """A slab transmission run (see :func:`~collisionkit.transport.simulate_slab`), checked when made.

    ``mass_ratio`` may be given as None (how a JSON summary records an
    infinite ratio): it reads as inf.

    Examples
    --------
    >>> SlabParameters(thickness=2.0, mass_ratio=None).mass_ratio
    inf
    >>> SlabParameters(model="rod", incidence="isotropic")
    Traceback (most recent call last):
    ...
    ValueError: the rod model is one-dimensional and elastic: it takes incidence normal and mass-ratio inf
    """

    thickness: float = 1.0
    albedo: float = 1.0
    incidence: str = "normal"
    model: str = "isotropic"
    mass_ratio: float = math.inf
    particles: int = 100_000
    seed: int = 2026

    def __post_init__(self):
        set_ = object.__setattr__
        set_(self, "thickness", check_real("thickness", self.thickness, 0.0, 1e4))
        set_(self, "albedo", check_real("albedo", self.albedo, 0.0, 1.0))
        check_choice("incidence", self.incidence, ("normal", "isotropic"))
        check_choice("model", self.model, ("isotropic", "rod"))
        ratio = math.inf if self.mass_ratio is None else self.mass_ratio
        set_(self, "mass_ratio", check_real("mass_ratio", ratio, 1.0, allow_inf=True))
        set_(self, "particles", check_integer("particles", self.particles, 64, 1_000_000_000))
        set_(self, "seed", check_seed("seed", self.seed))
        if self.model == "rod" and (self.incidence != "normal" or self.mass_ratio != math.inf):
            raise ValueError("the rod model is one-dimensional and elastic: it takes incidence normal and "
                             "mass-ratio inf")


def run_slab(parameters: SlabParameters, progress: Callable[[float], Any] | None = None) -> SlabResult:
    """Run the slab the parameters describe; ``progress(fraction)`` hears of the histories finished.

    Examples
    --------
    >>> result = run_slab(SlabParameters(thickness=1.0, particles=2000, seed=1))
    >>> abs(result.transmission + result.reflection - 1.0) < 1e-12   # albedo 1: nothing absorbed
    True
    """
    p = parameters
    return simulate_slab(p.thickness, p.albedo, incidence=p.incidence, model=p.model, mass_ratio=p.mass_ratio,
                         particles=p.particles, seed=p.seed, progress=progress)


def slab_summary(parameters: SlabParameters, result: SlabResult) -> dict[str, Any]:
    """The slab command's JSON summary: the flat results (each with ``*_error``) and the parameters.

    Examples
    --------
    >>> parameters = SlabParameters(thickness=1.0, particles=2000, seed=1)
    >>> summary = slab_summary(parameters, run_slab(parameters))
    >>> "transmission_error" in summary, summary["parameters"]["thickness"]
    (True, 1.0)
    """
    return result.to_dict() | {"parameters": parameters.to_dict()}
