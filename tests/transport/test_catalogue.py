"""The catalogue of real gases: shipped sets, sets placed in the data folder, mixtures by mole fraction.

Every test runs with COLLISIONKIT_DATA set to an empty folder of its own (tests/conftest.py).
"""

from __future__ import annotations

import hashlib
import os
import re
import shutil
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

from collisionkit.transport import (
    CATALOGUE, LXCatError, LXCatWarning, SwarmParameters, SwarmScan, catalogue, catalogue_entry, catalogue_files,
    catalogue_gas, data_folder, parse_gas_spec, read_lxcat,
)
from collisionkit.transport.catalogue import DATA, catalogue_rows

TESTS = Path(__file__).parent.parent / "data"


@pytest.fixture(autouse=True)
def _no_notes():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", LXCatWarning)
        yield


def test_argon_nitrogen_and_an_attaching_gas_ship_with_their_original_headers():
    terms = (DATA / "README.md").read_text(encoding="utf-8")
    for name in ("Ar", "N2", "O2", "He"):
        entry = CATALOGUE[name]
        assert entry.status() == "shipped" and entry.path() == DATA / f"IST-Lisbon_{name}.txt"
        raw = entry.path().read_bytes()
        assert raw.startswith(b"LXCat, www.lxcat.net\r\nGenerated on ")  # the export as its authors distribute it
        assert b"DATABASE:         IST-Lisbon database" in raw and b"HOW TO REFERENCE: L.L. Alves" in raw
        recorded = re.search(rf"`{entry.file}` \|.*`([0-9a-f]{{64}})` \|", terms).group(1)
        assert hashlib.sha256(raw).hexdigest() == recorded  # byte for byte the file README.md names
    assert any(p.kind == "attachment" for p in catalogue_gas("O2").species[0].processes)
    words = " ".join(terms.split())
    assert "GNU General Public License version 3" in words and (DATA / "LICENSE-GPL-3.0.txt").is_file()
    assert "not to be distributed by third parties" in words  # the LXCat policy is recorded next to the data


def test_a_catalogue_gas_is_the_file_read_by_the_reader():
    by_name = catalogue_gas("N2").species[0]
    by_file = read_lxcat(DATA / "IST-Lisbon_N2.txt").species[0]
    assert by_name.mass == by_file.mass and len(by_name.processes) == len(by_file.processes) == 26
    for a, b in zip(by_name.processes, by_file.processes):
        assert a.label == b.label and np.array_equal(a.cross_section, b.cross_section)


def test_a_mixture_by_mole_fraction():
    gas = catalogue_gas("Ar:0.9,N2:0.1")
    assert [s.name for s in gas.species] == ["Ar", "N2"] and gas.fractions == pytest.approx((0.9, 0.1), rel=1e-12)
    assert catalogue_gas("Ar:0.9, N2:0.1000005").fractions[1] == pytest.approx(0.1000005 / 1.0000005, rel=1e-12)
    assert parse_gas_spec("O2") == [("O2", 1.0)]


@pytest.mark.parametrize(
    ("spec", "words"),
    [
        ("Ar:0.9,N2:0.10001", "mole fractions must sum to 1 (within 1e-06); they sum to 1.00001"),
        ("Ar:0.9,N2:0.0999", "they sum to 0.9999"),
        ("Ar:1.5,N2:-0.5", "the fraction of Ar must lie in [0, 1]"),
        ("Ar:0.5,Ar:0.5", "Ar is named twice"),
        ("Ar:half,N2:0.5", "the fraction of Ar must be a number; got 'half'"),
        ("Ar:0.5,N2", "write each part as NAME:FRACTION"),
        ("", "gas must be a catalogue name or a mixture"),
        ("Xe", "gas 'Xe' is not in the catalogue; choose one of Ar, N2, O2, He, Ar-Biagi, Ar-Phelps, N2-Biagi, N2-Phelps, "
               "O2-Phelps (collisionkit gases lists them)"),
        ("Ar-Biagi", "gas 'Ar-Biagi' is not here: download Ar from https://www.lxcat.net/Biagi"),
    ],
)
def test_bad_names_and_fractions_are_refused_saying_what_to_do(spec, words):
    with pytest.raises(ValueError) as caught:
        catalogue_gas(spec)
    assert words in str(caught.value)


def test_a_set_that_may_not_ship_says_where_to_get_it_and_is_used_once_placed():
    entry = catalogue_entry("Ar-Biagi")
    assert (entry.shipped, entry.status(), entry.path()) == (False, "missing", None)
    assert entry.url == "https://www.lxcat.net/Biagi" and str(data_folder() / "Ar-Biagi.txt") in entry.where()
    data_folder().mkdir(parents=True, exist_ok=True)
    shutil.copy(TESTS / "lxcat" / "Alves_Ar.txt", data_folder() / "Ar-Biagi.txt")  # stands in for the download
    assert entry.status() == "placed" and catalogue_files("Ar-Biagi") == [data_folder() / "Ar-Biagi.txt"]
    assert catalogue_gas("Ar-Biagi").species[0].name == "Ar"
    with pytest.raises(ValueError, match=r"Ar and Ar-Biagi are both the species Ar; take one"):
        catalogue_gas("Ar:0.5,Ar-Biagi:0.5")


def test_any_file_placed_in_the_data_folder_is_a_gas_by_its_name():
    data_folder().mkdir(parents=True, exist_ok=True)
    shutil.copy(TESTS / "lxcat_classic_reid.txt", data_folder() / "MyReid.txt")
    shutil.copy(TESTS / "lxcat_new_mixture.txt", data_folder() / "TwoGases.txt")
    names = [entry.name for entry in catalogue()]
    assert names[-2:] == ["MyReid", "TwoGases"] and catalogue_entry("MyReid").status() == "placed"
    assert catalogue_gas("MyReid").species[0].name == "Reid"
    with pytest.raises(LXCatError, match=r"gas 'TwoGases' holds 2 species \(A, B\): read it with --cross-sections"):
        catalogue_gas("TwoGases")
    row = next(row for row in catalogue_rows() if row["name"] == "MyReid")
    assert (row["species"], row["processes"], row["status"]) == ("Reid", {"elastic": 1, "excitation": 1}, "placed")


def test_the_catalogue_rows_count_the_processes_of_each_file():
    rows = {row["name"]: row for row in catalogue_rows()}
    assert rows["Ar"]["processes"] == {"elastic": 1, "excitation": 37, "ionization": 1}
    assert rows["O2"]["processes"] == {"attachment": 1, "elastic": 1, "excitation": 11, "ionization": 1}
    assert rows["N2-Phelps"]["processes"] == {} and rows["N2-Phelps"]["status"] == "missing"


def test_the_data_folder_is_the_environment_variable_else_the_platform_user_data_folder(monkeypatch, tmp_path):
    monkeypatch.setenv("COLLISIONKIT_DATA", str(tmp_path / "mine"))
    assert data_folder() == tmp_path / "mine"
    monkeypatch.delenv("COLLISIONKIT_DATA")
    monkeypatch.setattr(Path, "home", classmethod(lambda cls: tmp_path / "home"))
    monkeypatch.setattr(sys, "platform", "linux")
    monkeypatch.setenv("XDG_DATA_HOME", str(tmp_path / "xdg"))
    assert data_folder() == tmp_path / "xdg" / "collisionkit"
    monkeypatch.delenv("XDG_DATA_HOME")
    assert data_folder() == tmp_path / "home" / ".local" / "share" / "collisionkit"
    monkeypatch.setattr(sys, "platform", "darwin")
    assert data_folder() == tmp_path / "home" / "Library" / "Application Support" / "collisionkit"
    monkeypatch.setattr(sys, "platform", "win32")
    monkeypatch.setenv("LOCALAPPDATA", str(tmp_path / "local"))
    assert data_folder() == tmp_path / "local" / "collisionkit"


def test_swarm_parameters_take_a_catalogue_gas_and_its_files():
    parameters = SwarmParameters(gas="Ar:0.9,N2:0.1", reduced_field=[50.0])
    assert [path.name for path in parameters.gas_files()] == ["IST-Lisbon_Ar.txt", "IST-Lisbon_N2.txt"]
    assert parameters.make_gas().fractions == pytest.approx((0.9, 0.1), rel=1e-12)
    assert SwarmParameters.from_mapping(parameters.to_dict()) == parameters
    with pytest.raises(ValueError, match="give exactly one of model, gas and cross_sections"):
        SwarmParameters(gas="Ar", model="reid")


def test_a_resumed_scan_of_a_placed_gas_refuses_a_changed_file(tmp_path):
    data_folder().mkdir(parents=True, exist_ok=True)
    placed = data_folder() / "MyReid.txt"
    shutil.copy(TESTS / "lxcat_classic_reid.txt", placed)
    parameters = SwarmParameters(gas="MyReid", reduced_field=[12.0, 24.0], particles=640, seed=3, tolerance=0.05,
                                 collision_budget=2e6)
    scan = SwarmScan(parameters, checkpoint=tmp_path / "scan.npz")
    scan.gas = scan.gas  # the gas read from the placed file
    scan.save()  # as after no point
    assert not SwarmScan.resume(tmp_path / "scan.npz").finished
    placed.write_text(placed.read_text().replace("6.000000e-20", "5.000000e-20"))
    with pytest.raises(ValueError, match=r"MyReid.txt has changed since .*scan.npz was written"):
        SwarmScan.resume(tmp_path / "scan.npz")


def test_a_resumed_scan_of_joined_files_refuses_any_changed_one(tmp_path):
    first, second = tmp_path / "reid.txt", tmp_path / "b.txt"
    shutil.copy(TESTS / "lxcat_classic_reid.txt", first)
    shutil.copy(TESTS / "lxcat_new_mixture.txt", second)
    parameters = SwarmParameters(cross_sections=[first, second], species=["Reid", "B"], fractions=[0.5, 0.5],
                                 reduced_field=[12.0], particles=640)
    SwarmScan(parameters, checkpoint=tmp_path / "scan.npz").save()
    assert SwarmScan.resume(tmp_path / "scan.npz").parameters.cross_sections == (first, second)
    second.write_text(second.read_text().replace("2.0e-4", "3.0e-4"))
    with pytest.raises(ValueError, match=r"reid.txt, .*b.txt has changed since"):
        SwarmScan.resume(tmp_path / "scan.npz")
    assert os.environ["COLLISIONKIT_DATA"] == str(data_folder())
