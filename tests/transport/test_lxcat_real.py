"""The LXCat reader on real files: the shipped IST-Lisbon sets and whole exports of the IST-Lisbon and Alves databases.

The files (src/collisionkit/transport/data/ and tests/data/lxcat/) are LXCat exports as
their authors, the N-PRiME group of IST Lisbon, distribute them in LoKI-B and LoKI-MC
(GPL-3.0; see src/collisionkit/transport/data/README.md). The expected counts and values
are read from the files here with plain text searches, independently of the reader.
"""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy import constants

from collisionkit.transport import LXCatError, LXCatWarning, read_lxcat
from collisionkit.transport.lxcat import lxcat_contents

SHIPPED = Path(__file__).parents[2] / "src" / "collisionkit" / "transport" / "data"
DATA = Path(__file__).parent.parent / "data" / "lxcat"
AR, N2, O2, HE = (SHIPPED / f"IST-Lisbon_{gas}.txt" for gas in ("Ar", "N2", "O2", "He"))
ALVES_AR = DATA / "Alves_Ar.txt"              # LoKI-MC: Ar of the Alves database (LXCat, 20 Apr 2018)
N2_ROT = DATA / "IST-Lisbon_N2_rot.txt"       # LoKI-B: J-resolved rotations, species "Nitrogen" (2022)
N2_ROT_2018 = DATA / "IST-Lisbon_N2-rot_2018.txt"  # LoKI-MC: the same, species "N2-rot" (2018)
N2_VIB = DATA / "IST-Lisbon_N2_vib.txt"       # LoKI-B: VIBRATIONAL blocks between excited levels
ATOMIC_O = DATA / "IST-Lisbon_O.txt"          # LoKI-MC: atomic oxygen, species written "Oxygen"


def _lines(path):
    return path.read_text(encoding="utf-8").splitlines()


def _keyword_count(path, keywords):
    """Blocks of the given kinds, counted as keyword lines."""
    return sum(line.strip() in keywords for line in _lines(path))


def _quiet(*args, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", LXCatWarning)
        return read_lxcat(*args, **kwargs)


def test_the_shipped_argon_set_is_read_whole():
    (argon,) = _quiet(AR).species
    kinds = [p.kind for p in argon.processes]
    assert (argon.name, kinds.count("elastic"), kinds.count("ionization")) == ("Ar", 1, 1)
    assert kinds.count("excitation") == _keyword_count(AR, {"EXCITATION"}) == 37
    assert constants.m_e / argon.mass == pytest.approx(1.371e-5, rel=1e-12)  # the ELASTIC block's m/M
    first = argon.processes[1]
    assert (first.label, first.threshold) == ("E + Ar -> E + Ar(3P2), Excitation", 11.548)
    assert all(p.weight_ratio == 0.0 for p in argon.processes)  # the file writes every excitation one-way (->)
    ionization = argon.processes[-1]
    assert ionization.threshold == 15.76 and ionization.cross_section.max() > 2e-20


def test_reversible_excitations_take_the_statistical_weight_ratio_after_the_threshold():
    """He: every excitation is written ``He <-> He(2S3)`` with ``threshold ratio`` on its third line."""
    (helium,) = _quiet(HE).species
    expected = {}  # target line -> second number of the following line, read from the text
    lines = _lines(HE)
    for i, line in enumerate(lines):
        if line.strip() == "EXCITATION":
            expected[lines[i + 1].strip()] = float(lines[i + 2].split()[1])
    read = {p.label: p.weight_ratio for p in helium.processes if p.kind == "excitation"}
    assert len(read) == len(expected) == 42
    for target, ratio in expected.items():
        label = f"E + He <-> E + {target.split('<->')[1].strip()}, Excitation"
        assert read[label] == ratio
    assert read["E + He <-> E + He(2S3), Excitation"] == 3.0 and read["E + He <-> E + He(2P3), Excitation"] == 9.0
    assert [p.weight_ratio for p in helium.processes if p.kind != "excitation"] == [0.0, 0.0]


def test_the_effective_set_of_n2_becomes_an_elastic_cross_section_with_a_warning_for_the_clipped_energies():
    with pytest.warns(LXCatWarning, match=r"IST-Lisbon_N2.txt, line 80 \(the EFFECTIVE block of N2 at line 80\): "
                                          r"effective minus inelastic cross sections is negative at 6 of 108 energies, "
                                          r"1500 to 10000 eV"):
        (nitrogen,) = read_lxcat(N2).species
    elastic = nitrogen.processes[0]
    # independently: sum the inelastic tables of the file (constant beyond their last point) at 5 eV and 100 eV
    tables = re.split(r"\n-{5,}\n", "\n".join(_lines(N2)))
    def table(index):
        return np.array([[float(x) for x in row.split()[:2]] for row in tables[index].strip().splitlines()])
    effective = table(1)
    inelastic = [table(k) for k in range(3, len(tables), 2)]
    assert len(inelastic) == len(nitrogen.processes) - 1 == 25
    for energy in (5.0, 100.0):
        total = sum(np.interp(energy, t[:, 0], t[:, 1], left=0.0, right=t[-1, 1]) for t in inelastic)
        expected = np.interp(energy, effective[:, 0], effective[:, 1]) - total
        assert np.interp(energy, elastic.energy, elastic.cross_section) == pytest.approx(expected, rel=1e-9)
    assert elastic.cross_section.min() == 0.0  # the clipped energies


def test_the_attaching_o2_set_reads_its_attachment_block_without_parameter_line():
    (oxygen,) = _quiet(O2).species
    attachment = [p for p in oxygen.processes if p.kind == "attachment"]
    assert len(attachment) == _keyword_count(O2, {"ATTACHMENT"}) == 1
    assert attachment[0].threshold == 0.0 and attachment[0].label == "E + O2 -> O- + O, Attachment"
    peak = attachment[0].energy[np.argmax(attachment[0].cross_section)]
    assert 6.0 < peak < 7.5  # dissociative attachment of O2: the 6.5 eV resonance


def test_a_rotational_set_without_elastic_block_is_refused_alone_and_read_with_its_complete_set():
    with pytest.raises(LXCatError, match=r"species N2 has no ELASTIC or EFFECTIVE block in IST-Lisbon_N2_rot.txt"):
        read_lxcat(N2_ROT)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        (nitrogen,) = read_lxcat([N2, N2_ROT]).species
    notes = [str(w.message) for w in caught if w.category is LXCatWarning]
    assert any("IST-Lisbon_N2_rot.txt: its 31 processes of N2 have no elastic or effective block in this file; the "
               "elastic one comes from" in note for note in notes)
    assert any("31 processes of N2 start from a given rotational or vibrational level" in note for note in notes)
    rotations = [p for p in nitrogen.processes if "Rotational" in p.label]
    assert len(rotations) == _keyword_count(N2_ROT, {"ROTATIONAL"}) == 31
    first = rotations[0]  # PARAM.:  E = 0.0015 eV, g1/g0 = 5 (no target or parameter line in these blocks)
    assert (first.threshold, first.weight_ratio) == (0.0015, 5.0)
    assert len(nitrogen.processes) == 26 + 31


def test_an_older_export_names_the_rotational_group_n2_rot_and_is_read_as_n2_too():
    (nitrogen,) = _quiet([N2, N2_ROT_2018]).species
    assert nitrogen.name == "N2" and len(nitrogen.processes) == 26 + 31


def test_vibrational_blocks_between_excited_levels_are_read_with_a_note_on_their_levels():
    with pytest.warns(LXCatWarning, match=r"processes of N2 start from a given rotational or vibrational level"):
        (nitrogen,) = read_lxcat([N2, N2_VIB]).species
    vibrational = [p for p in nitrogen.processes if p.label.endswith("Vibrational")]
    assert len(vibrational) == _keyword_count(N2_VIB, {"VIBRATIONAL"}) == 45
    assert all(p.kind == "excitation" and p.weight_ratio > 0 for p in vibrational)  # written E + Nitrogen <-> ...


def test_a_group_named_oxygen_whose_elastic_block_keeps_o_is_atomic_oxygen():
    species = _quiet(ATOMIC_O).species
    assert [s.name for s in species] == ["O", "O(1D)", "O(1S)"]  # elastic blocks E + Oxygen -> E + O(1D): on O(1D)
    oxygen = species[0]
    assert [p.kind for p in oxygen.processes].count("elastic") == 1
    assert constants.m_e / oxygen.mass == pytest.approx(3.43e-5, rel=1e-2)  # an O atom, not O2
    assert _quiet(ATOMIC_O, species=["Oxygen"]).species[0].name == "O"  # the file's spelling finds it too


def test_files_are_joined_with_species_and_fractions_across_them():
    gas = _quiet([AR, N2, O2], species=["N2", "O2"], fractions=[0.8, 0.2])
    assert [s.name for s in gas.species] == ["N2", "O2"] and gas.fractions == (0.8, 0.2)
    assert [len(s.processes) for s in gas.species] == [26, 14]


def _export(tmp_path, *parts):
    """Whole LXCat exports written one after the other into one file, as LXCat writes a multi-database export."""
    path = tmp_path / "export.txt"
    path.write_bytes(b"".join(part.read_bytes() for part in parts))
    return path


def test_a_multi_database_export_asks_for_the_database_of_a_species_it_holds_twice(tmp_path):
    export = _export(tmp_path, ALVES_AR, AR, N2, O2, ATOMIC_O)
    contents = {(c["species"], c["database"]) for c in lxcat_contents(export)}
    assert contents == {("Ar", "Alves"), ("Ar", "IST-Lisbon"), ("N2", "IST-Lisbon"), ("O2", "IST-Lisbon"),
                        ("O", "IST-Lisbon"), ("O(1D)", "IST-Lisbon"), ("O(1S)", "IST-Lisbon")}
    with pytest.raises(LXCatError, match=r"species Ar is in 2 databases in export.txt: Alves, IST-Lisbon; choose one "
                                         r"with database="):
        read_lxcat(export, species=["Ar"])
    with pytest.warns(LXCatWarning, match=r"export.txt: skipped \d+ blocks of Ar \(Alves\), O2 \(IST-Lisbon\), O \(IST-Lisbon\), "
                                          r"O\(1D\) \(IST-Lisbon\), O\(1S\) \(IST-Lisbon\) \(not asked for\)"):
        gas = read_lxcat(export, species=["Ar", "N2"], fractions=[0.9, 0.1], database="IST-Lisbon")
    alone = _quiet(AR).species[0]
    ar = gas.species[0]
    assert len(ar.processes) == len(alone.processes)
    for joined, single in zip(ar.processes, alone.processes):
        assert joined.label == single.label and np.array_equal(joined.cross_section, single.cross_section)
    alves = _quiet(export, species=["Ar"], database={"Ar": "alves"}).species[0]  # per species, any case
    assert len(alves.processes) == _keyword_count(ALVES_AR, {"ELASTIC", "EXCITATION", "IONIZATION"})
    with pytest.raises(LXCatError, match=r"database 'Biagi' holds none of Ar in export.txt \(their databases: Alves, "
                                         r"IST-Lisbon\)"):
        read_lxcat(export, species=["Ar"], database="Biagi")
    with pytest.raises(LXCatError, match=r"species Ar is not in the database 'Biagi'.*its databases: Alves, IST-Lisbon"):
        read_lxcat(export, species=["Ar"], database={"Ar": "Biagi"})
    with pytest.raises(LXCatError, match=r"database 'Phelps' holds none of Ar in IST-Lisbon_Ar.txt"):
        read_lxcat(AR, database="Phelps")  # a database named for a file of one database must be its own


def test_a_broken_block_of_another_species_does_not_stop_the_reading_and_is_named_when_used(tmp_path):
    export = _export(tmp_path, N2, O2)
    lines = export.read_text(encoding="utf-8").splitlines(keepends=True)
    o2_start = next(i for i, line in enumerate(lines) if line.strip() == "EFFECTIVE" and lines[i + 1].strip() == "O2")
    table = next(i for i in range(o2_start, len(lines)) if re.match(r"^-{5,}\s*$", lines[i])) + 1
    lines[table + 2] = " 2.000000e-3\toops\r\n"
    export.write_text("".join(lines), encoding="utf-8")
    with pytest.warns(LXCatWarning, match=r"skipped 14 blocks of O2 \(IST-Lisbon\) \(not asked for\)"):
        (nitrogen,) = read_lxcat(export, species=["N2"]).species
    assert nitrogen.name == "N2" and len(nitrogen.processes) == 26
    with pytest.raises(LXCatError) as caught:
        _quiet(export, species=["O2"])
    assert str(caught.value) == (f"{export}, line {table + 3}: expected a number, got 'oops' "
                                 f"(the EFFECTIVE block of O2 at line {o2_start + 1})")


def test_a_block_left_without_closing_dashes_is_named_and_the_next_block_still_read(tmp_path):
    export = _export(tmp_path, AR, O2)
    lines = export.read_text(encoding="utf-8").splitlines(keepends=True)
    start = next(i for i, line in enumerate(lines) if line.strip() == "IONIZATION" and lines[i + 1].startswith("Ar"))
    dashes = [i for i in range(start, len(lines)) if re.match(r"^-{5,}\s*$", lines[i])]
    del lines[dashes[1]]  # the ionization table of Ar runs into the O2 section
    export.write_text("".join(lines), encoding="utf-8")
    with pytest.warns(LXCatWarning, match=r"skipped 39 blocks of Ar \(IST-Lisbon\) \(not asked for; 1 of them malformed, "
                                          r"not read\)"):
        (oxygen,) = read_lxcat(export, species=["O2"]).species
    assert len(oxygen.processes) == 14  # every O2 block, the first one right after the broken table included
    with pytest.raises(LXCatError, match=rf"line {start + 1}: table not closed by a line of dashes \(a new block "
                                         rf"starts at line \d+\) \(the IONIZATION block of Ar \(Ar -> Ar\+\)"):
        _quiet(export, species=["Ar"])
