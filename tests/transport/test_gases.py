"""Gas definitions: validation of input and the model gases."""

import math

import numpy as np
import pytest
from scipy import constants

from collisionkit.transport import (
    Gas, Process, Species, hard_sphere_gas, lucas_saelee, maxwell_model, model_gas, reid_ramp,
    screened_coulomb_momentum_ratio,
)


def test_reid_ramp_is_the_published_model():
    # Reid, Aust. J. Phys. 32, 231 (1979); as tabulated in /work/shared/reference/validation-data.md
    species = reid_ramp().species[0]
    assert constants.m_e / species.mass == pytest.approx(1.37145e-4)
    elastic, excitation = species.processes
    assert np.all(elastic.cross_section == 6e-20)
    assert excitation.threshold == 0.2
    assert np.interp(1.2, excitation.energy, excitation.cross_section) == pytest.approx(1e-19)


def test_lucas_saelee_elastic_is_a_constant_rate():
    elastic = lucas_saelee(0.5).species[0].processes[0]
    speed = math.sqrt(2 * 4.0 * constants.e / constants.m_e)  # 4 eV
    assert elastic.rate_coefficient == pytest.approx(4e-20 / math.sqrt(4.0) * speed)


@pytest.mark.parametrize("name", ["maxwell", "hard_sphere", "reid", "lucas_saelee"])
def test_model_gases_by_name(name):
    assert isinstance(model_gas(name), Gas)


def test_unknown_model_names_the_choices():
    with pytest.raises(ValueError, match="reid"):
        model_gas("argon")


def test_negative_threshold_and_kind_are_refused():
    with pytest.raises(ValueError, match="threshold"):
        Process("excitation", [1, 2], [0, 1e-20], threshold=-1.0)
    with pytest.raises(ValueError, match="kind"):
        Process("fusion", [1, 2], [0, 1e-20])
    with pytest.raises(ValueError, match="increasing"):
        Process("elastic", [2, 1], [1e-20, 1e-20])


def test_mixture_fractions_are_normalised_and_checked():
    mix = Gas.mixture({maxwell_model(): 3.0, hard_sphere_gas(): 1.0})
    assert mix.fractions == (0.75, 0.25)
    with pytest.raises(ValueError, match="fractions"):
        Gas((Species("a", 1e-26, (Process("elastic", [0, 1], [1e-20, 1e-20]),)),), (0.5,))


@pytest.mark.parametrize(
    "energy, screening, words",
    [(1.0, -1.0, "screening_energy"), (1.0, 0.0, "screening_energy"), (-1.0, 1.0, "energy"), (np.nan, 1.0, "energy")],
)
def test_screened_coulomb_ratio_rejects_bad_energies(energy, screening, words):
    # (1, -1) returned nan
    with pytest.raises(ValueError, match=words):
        screened_coulomb_momentum_ratio(energy, screening)


@pytest.mark.parametrize("bad", [-1.0, math.nan])
def test_tables_refuse_bad_cross_sections(bad):
    with pytest.raises(ValueError, match="cross_section"):
        Process("elastic", [0, 1], [1e-20, bad])


def test_wrong_types_in_processes_species_and_gases_are_named_not_python_errors():
    # each raised a bare Python error ("'>' not supported between instances of 'str' and 'int'", "'Process' object
    # is not iterable"), and a 2-D table was flattened silently
    from collisionkit.transport import Gas, Process, Species

    elastic = Process("elastic", [0, 1], [1e-20, 1e-20])
    with pytest.raises(TypeError, match="elastic: screening_energy must be a number; got 'a'"):
        Process("elastic", [0, 1], [1e-20, 1e-20], screening_energy="a")
    with pytest.raises(TypeError, match="excitation: threshold must be a number"):
        Process("excitation", [1, 2], [1e-20, 1e-20], threshold="1")
    with pytest.raises(TypeError, match=r"species X: mass \(kg\) must be a number; got '1'"):
        Species("X", "1", (elastic,))
    with pytest.raises(ValueError, match="energy must be a 1-D table; got shape"):
        Process("elastic", [[0, 1], [2, 3]], [[1e-20, 1e-20], [1, 1]])
    one = Species("X", 1e-26, elastic)  # a single process (or species) is taken as one of them
    assert one.processes == (elastic,) and Gas(one).species == (one,)
    with pytest.raises(TypeError, match="species must be Species objects"):
        Gas((elastic,))


def test_a_catalogue_gas_has_a_compact_repr_naming_its_species():
    # repr(catalogue_gas("N2")) was 161 491 characters: every cross-section table in full
    from collisionkit.transport import catalogue_gas

    gas = catalogue_gas("N2")
    assert len(repr(gas)) < 300 and "N2" in repr(gas), repr(gas)
    assert repr(gas) == f"Gas(species=['N2'], fractions=[1.0], processes={len(gas.processes)})"
    assert len(repr(gas.species[0])) < 300 and "N2" in repr(gas.species[0])
    assert all(len(repr(process)) < 300 for _, process in gas.processes)
