"""LXCat reader: both formats, mixtures and errors that name the line.

The files in tests/data/ were written for these tests (not copied from a database).
"""

from pathlib import Path

import numpy as np
import pytest
from scipy import constants

from collisionkit.transport import LXCatError, parse_lxcat, read_lxcat, simulate_swarm

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
