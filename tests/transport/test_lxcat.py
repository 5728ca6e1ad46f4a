"""LXCat reader: both formats, mixtures and errors that name the line.

The files in tests/data/ were written for these tests (not copied from a database).
"""

from pathlib import Path

import numpy as np
import pytest
from scipy import constants

from collisionkit.transport import (
    Gas, LXCatError, LXCatWarning, Process, Species, parse_lxcat, read_lxcat, simulate_swarm,
)

E_CHARGE, ME = constants.e, constants.m_e

DATA = Path(__file__).parent.parent / "data"


def test_classic_block_format_gives_reids_ramp():
    gas = read_lxcat(DATA / "lxcat_classic_reid.txt")
    (species,) = gas.species
    assert species.name == "Reid"
    assert constants.m_e / species.mass == pytest.approx(1.37145e-4)
    kinds = [p.kind for p in species.processes]
    assert kinds == ["elastic", "excitation"]
    assert species.processes[1].threshold == 0.2


def test_new_format_with_species_process_param_lines_and_a_mixture():
    gas = read_lxcat(DATA / "lxcat_new_mixture.txt", fractions=(0.7, 0.3))
    a, b = gas.species
    assert (a.name, b.name) == ("A", "B")
    assert gas.fractions == (0.7, 0.3)
    assert constants.m_e / b.mass == pytest.approx(2e-4)
    assert [p.kind for p in a.processes] == ["elastic", "excitation", "ionization"]
    assert [p.kind for p in b.processes] == ["elastic", "attachment"]
    # EFFECTIVE minus the inelastic processes: 5e-20 - 1e-20 (exc) - 2e-20 (ion) at 100 eV
    np.testing.assert_allclose(a.processes[0].cross_section, [5e-20, 4e-20, 2e-20])
    assert a.processes[2].threshold == 12.0


def test_species_selection_and_missing_species():
    with pytest.warns(LXCatWarning, match=r"lxcat_new_mixture.txt: skipped 3 blocks of A \(not asked for\)"):
        gas = read_lxcat(DATA / "lxcat_new_mixture.txt", species=["B"])
    assert [s.name for s in gas.species] == ["B"]
    with pytest.raises(LXCatError, match="not in the file"):
        read_lxcat(DATA / "lxcat_new_mixture.txt", species=["C"])


def test_negative_cross_section_error_names_the_line():
    with pytest.raises(LXCatError, match=r"line 8: negative cross section"):
        read_lxcat(DATA / "lxcat_bad_negative.txt")


@pytest.mark.parametrize(
    "text, message",
    [
        ("EXCITATION\nX -> X*\n-0.5\n-----\n1 0\n2 1e-20\n-----\n", "line 1: threshold below zero"),
        ("ELASTIC\nX\n1e-4\n-----\n0 1e-20\n1 oops\n-----\n", "line 6: expected a number"),
        ("ELASTIC\nX\n1e-4\n-----\n0 1e-20\n0 1e-20\n-----\n", "line 6: energies must increase"),
        ("ELASTIC\nX\n1e-4\n-----\n0 1e-20\n", "table not closed"),
        ("IONIZATION\nX -> X+\n-----\n1 0\n-----\n", "needs a threshold"),
        ("just text\n", "no cross-section blocks"),
    ],
)
def test_malformed_files_are_refused_with_the_line(text, message):
    with pytest.raises(LXCatError, match=message):
        parse_lxcat(text) if "threshold" not in message and "needs" not in message else parse_lxcat(text)


def test_the_lxcat_reid_file_drives_a_swarm_like_the_builtin_model():
    from collisionkit.transport import reid_ramp

    options = dict(particles=640, seed=3, tolerances={"mean_energy": 0.02}, threads=1, collision_budget=3e6)
    from_file = simulate_swarm(read_lxcat(DATA / "lxcat_classic_reid.txt"), 12.0, **options)
    builtin = simulate_swarm(reid_ramp(), 12.0, **options)
    assert from_file.mean_energy == builtin.mean_energy  # the same tables, the same streams


# ------------------------------------------------------------------ found by a mutation audit


def test_screened_coulomb_reading_keeps_the_files_momentum_transfer_cross_section(tmp_path):
    """An LXCat ELASTIC/EFFECTIVE table is a momentum-transfer cross section sigma_m. Read with screened
    Coulomb scattering, the elastic cross section the engine samples must give back sigma_m =
    sigma_el <1 - cos chi>, with <1 - cos chi> of the engine's angular law: screened_coulomb_momentum_ratio,
    which the engine's sampling reproduces at these energies (tests/_kernels/test_transport.py).
    Kills: sigma_m / ratio -> sigma_m * ratio."""
    from collisionkit.transport import read_lxcat, screened_coulomb_momentum_ratio

    (tmp_path / "x.txt").write_text("ELASTIC\nX\n1.37e-4\n-----\n0 6e-20\n1 6e-20\n10 5e-20\n100 2e-20\n-----\n")
    gas = read_lxcat(tmp_path / "x.txt", scattering="screened_coulomb", screening_energy=0.5)
    process = gas.species[0].processes[0]
    assert process.scattering == "screened_coulomb"
    assert process.screening_energy == 0.5
    for energy, sigma_m in ((1.0, 6e-20), (10.0, 5e-20), (100.0, 2e-20)):
        sigma_el = np.interp(energy, process.energy, process.cross_section)
        transfer = sigma_el * screened_coulomb_momentum_ratio(energy, process.screening_energy)
        assert transfer == pytest.approx(sigma_m, rel=1e-12)


def test_attachment_and_ionization_frequencies_of_constant_rate_channels_are_their_rate_coefficients():
    """A Maxwell-model gas (k_el = 1e-13) with constant-rate attachment (k_att = 2e-15 m^3/s) and
    ionization (k_ion = 3e-15, threshold 0) channels: nu = N k whatever the energy distribution, so
    attachment_frequency_N = k_att and ionization_frequency_N = k_ion in expectation (and equal the channels'
    rate coefficients). Tolerance 5 standard errors (~0.5 %). Kills: the attachment frequency's
    normalisation (x 1/1.5 passed the existing 0.05-2 band), the ionization frequency's (x 1/2)."""
    k_att, k_ion = 2e-15, 3e-15
    species = Species("m", 10 * ME, (Process("elastic", rate_coefficient=1e-13, label="elastic"),
                                     Process("attachment", rate_coefficient=k_att, label="attachment"),
                                     Process("ionization", rate_coefficient=k_ion, label="ionization")))
    r = simulate_swarm(Gas((species,)), 5.0, particles=1600, seed=5, threads=2, tolerances={"mean_energy": 1e-2})
    for name, k in (("attachment", k_att), ("ionization", k_ion)):
        value, error = getattr(r, f"{name}_frequency_N"), getattr(r, f"{name}_frequency_N_error")
        assert error < 0.05 * k
        assert abs(value - k) < 5 * error
        assert r.rate_coefficients[f"m:{name}"] == pytest.approx(value, rel=1e-12, abs=0)


def test_effective_cross_section_below_the_inelastic_sum_is_clipped_at_zero(tmp_path):
    """EFFECTIVE = elastic momentum transfer + inelastic: the elastic part sigma_eff - sum(inelastic) cannot be
    negative (BOLSIG+ clips it at 0). Here at 20 eV the excitation (3e-20) exceeds the effective (2e-20).
    Kills: the clip dropped (a negative table, refused by Process)."""
    from collisionkit.transport import read_lxcat

    text = ("EFFECTIVE\nX\n1e-4\n-----\n0 5e-20\n10 4e-20\n20 2e-20\n-----\n"
            "EXCITATION\nX -> X*\n5.0\n-----\n5 0\n10 1e-20\n20 3e-20\n-----\n")
    (tmp_path / "x.txt").write_text(text)
    with pytest.warns(LXCatWarning, match=r"x.txt, line 1 \(the EFFECTIVE block of X at line 1\): effective minus "
                                          r"inelastic cross sections is negative at 1 of 3 energies, 20 to 20 eV"):
        elastic = read_lxcat(tmp_path / "x.txt").species[0].processes[0]
    np.testing.assert_allclose(elastic.cross_section, [5e-20, 3e-20, 0.0], atol=1e-35)


# ------------------------------------------------------------------ target lines, parameter lines and kinds


SYNTAX = """\
MOMENTUM
e + N2 -> e + N2
 1.95e-5 / mass ratio
-----
 0 1e-20
 100 1e-20
-----
EXCITATION
e + N2 -> e + N2(v=1)
 0.29 / threshold energy
-----
 0.29 0
 10 1e-21
-----
EXCITATION
N2 <-> N2(A)
 6.2 / 3.0
-----
 6.2 0
 20 1e-21
-----
EXCITATION
N2(X,v=0) <-> N2(B)
 7.4
-----
 7.4 0
 20 1e-21
-----
EXCITATION
N2 -> N2(C)
 11.0  2.0
-----
 11 0
 20 1e-21
-----
VIBRATIONAL
SPECIES: e / N2
PROCESS: E + N2 -> E + N2(v=2), Vibrational
PARAM.:  E = 0.58 eV
-----
 0.58 0
 10 1e-21
-----
IONIZATION
N2 -> N2^+
 15.6
-----
 15.6 0
 100 1e-20
-----
ATTACHMENT
O2 -> O2^-
-----
 0 1e-22
 1 0
-----
EFFECTIVE
O2
 1.71e-5
-----
 0 1e-20
 100 1e-20
-----
"""


def test_every_target_line_syntax_parameter_line_and_kind_of_the_format(tmp_path):
    """The target lines of the LXCat format's description (``N2``, ``e + N2 -> e + N2(v=1)``, ``N2 -> N2^+``,
    ``O2 -> O2^-``, ``<->``, a ground-state designation) and its parameter lines (a comment after the number,
    ``threshold / ratio``, ``threshold ratio``), with every kind keyword."""
    (tmp_path / "syntax.txt").write_text(SYNTAX)
    gas = read_lxcat(tmp_path / "syntax.txt")
    n2, o2 = gas.species
    assert (n2.name, o2.name) == ("N2", "O2")
    assert constants.m_e / n2.mass == pytest.approx(1.95e-5) and constants.m_e / o2.mass == pytest.approx(1.71e-5)
    kinds = [(p.kind, p.threshold, p.weight_ratio) for p in n2.processes]
    assert kinds == [("elastic", 0.0, 0.0), ("excitation", 0.29, 0.0),
                     ("excitation", 6.2, 3.0),   # <-> with its ratio after a slash
                     ("excitation", 7.4, 1.0),   # <-> without a ratio: 1, the BOLSIG+ convention
                     ("excitation", 11.0, 2.0),  # a second number makes the excitation reversible
                     ("excitation", 0.58, 0.0),  # VIBRATIONAL from its PARAM.: line
                     ("ionization", 15.6, 0.0)]
    assert [p.kind for p in o2.processes] == ["attachment", "elastic"]



def test_the_reader_refuses_an_angular_law_the_gas_tables_convert_themselves():
    # read_lxcat(scattering="okhrimovskyy") divided the elastic table by the screened-Coulomb ratio, and the
    # kernel tables then divided it by 1 - <cos chi> again
    from collisionkit.transport import read_lxcat

    with pytest.raises(ValueError, match="call .with_scattering"):
        read_lxcat(DATA / "lxcat_classic_reid.txt", scattering="okhrimovskyy")
