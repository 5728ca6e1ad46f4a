"""Star files: the GADGET/SWIFT HDF5 snapshot layout read back through h5py, .npz, other codes' files, bad files."""

from __future__ import annotations

import sys

import h5py
import numpy as np
import pytest
import scipy.constants as const

from collisionkit.encounters import GM_SUN, StarFileError, StarModel, read_star, unit_system, write_star

HEADER = {
    "NumPart_ThisFile", "NumPart_Total", "NumPart_Total_HighWord", "MassTable", "Time", "Redshift", "BoxSize",
    "NumFilesPerSnapshot", "Flag_Entropy_ICs", "Dimension", "Flag_Sfr", "Flag_Cooling", "Flag_StellarAge",
    "Flag_Metals", "Flag_Feedback", "Flag_DoublePrecision", "Omega0", "OmegaLambda", "HubbleParam", "UnitSystem",
}  # fmt: skip


def pair_of_stars(units="solar", count=60):
    rng = np.random.default_rng(8)
    return StarModel(
        positions=rng.normal(size=(count, 3)) * 0.01,
        velocities=rng.normal(size=(count, 3)),
        masses=rng.uniform(1e-3, 2e-3, count),
        smoothing_lengths=rng.uniform(1e-3, 2e-3, count),
        internal_energies=rng.uniform(0.0, 5.0, count),
        ids=np.arange(count) + 2**40,  # beyond 32 bits: the IDs are 64-bit
        units=units,
        star_ids=np.repeat([1, 2], [count // 3, count - count // 3]),
    )


def test_the_hdf5_layout_read_back_through_h5py(tmp_path):
    star = pair_of_stars("solar")
    path = write_star(star, tmp_path / "pair.hdf5")
    count = len(star)
    with h5py.File(path, "r") as file:
        assert set(file) == {"Header", "Units", "PartType0"}
        header = file["Header"].attrs
        assert set(header) == HEADER
        assert header["NumPart_ThisFile"].tolist() == [count, 0, 0, 0, 0, 0]
        assert header["NumPart_Total"].tolist() == [count, 0, 0, 0, 0, 0]
        assert header["NumPart_Total_HighWord"].tolist() == [0] * 6
        assert header["MassTable"].tolist() == [0.0] * 6
        assert (header["Time"], header["Redshift"], header["NumFilesPerSnapshot"]) == (0.0, 0.0, 1)
        assert (header["Flag_Entropy_ICs"], header["Dimension"], header["Flag_DoublePrecision"]) == (0, 3, 1)
        assert all(header[name] == 0 for name in ("Flag_Sfr", "Flag_Cooling", "Flag_StellarAge", "Flag_Metals",
                                                   "Flag_Feedback", "Omega0", "OmegaLambda"))
        assert header["HubbleParam"] == 1.0 and header["UnitSystem"] == "solar"
        reach = np.max(np.abs(star.positions) + star.smoothing_lengths[:, None])
        assert header["BoxSize"] == 2 * reach
        units = file["Units"].attrs
        msun_g, au_cm, year_s = GM_SUN / const.G * 1e3, const.au * 1e2, const.Julian_year
        assert units["Unit mass in cgs (U_M)"] == pytest.approx(msun_g, rel=2e-16, abs=0)
        assert units["Unit length in cgs (U_L)"] == pytest.approx(au_cm, rel=2e-16, abs=0)
        assert units["Unit time in cgs (U_t)"] == year_s
        assert units["Unit current in cgs (U_I)"] == 1.0 and units["Unit temperature in cgs (U_T)"] == 1.0
        assert units["UnitMass_in_g"] == units["Unit mass in cgs (U_M)"]
        assert units["UnitLength_in_cm"] == units["Unit length in cgs (U_L)"]
        assert units["UnitVelocity_in_cm_per_s"] == pytest.approx(au_cm / year_s, rel=2e-16, abs=0)
        gas = file["PartType0"]
        assert set(gas) == {"Coordinates", "Velocities", "Masses", "SmoothingLength", "InternalEnergy", "ParticleIDs",
                            "StarID"}
        for name, field in (("Coordinates", "positions"), ("Velocities", "velocities"), ("Masses", "masses"),
                            ("SmoothingLength", "smoothing_lengths"), ("InternalEnergy", "internal_energies")):
            assert gas[name].dtype == np.float64 and np.array_equal(gas[name][()], getattr(star, field)), name
        assert gas["ParticleIDs"].dtype == np.uint64 and np.array_equal(gas["ParticleIDs"][()], star.ids)
        assert gas["StarID"].dtype == np.int32 and np.array_equal(gas["StarID"][()], star.star_ids)
    again = read_star(path)
    assert again.units is unit_system("solar")
    for name, array in star.arrays().items():
        assert np.array_equal(getattr(again, name), array), name


def test_n_body_units_have_no_units_group_and_come_back(tmp_path):
    path = write_star(pair_of_stars("nbody"), tmp_path / "pair.h5")
    with h5py.File(path, "r") as file:
        assert "Units" not in file and file["Header"].attrs["UnitSystem"] == "nbody"
    assert read_star(path).units.name == "nbody"


@pytest.mark.parametrize("units", ["nbody", "cgs", "stellar"])
def test_the_npz_file_holds_the_same_datasets(tmp_path, units):
    star = pair_of_stars(units)
    path = write_star(star, tmp_path / "pair.npz")
    with np.load(path) as data:
        assert set(data.files) == {"Coordinates", "Velocities", "Masses", "SmoothingLength", "InternalEnergy",
                                   "ParticleIDs", "StarID", "UnitSystem", "Units_cgs"}
        assert str(data["UnitSystem"]) == units
    again = read_star(path)
    assert again.units is unit_system(units)
    for name, array in star.arrays().items():
        assert np.array_equal(getattr(again, name), array), name


def swift_file(path, units=True):
    """An initial-conditions file as SWIFT's examples write it: one-element unit attributes, a mass table."""
    count = 20
    rng = np.random.default_rng(2)
    with h5py.File(path, "w") as file:
        header = file.create_group("Header")
        header.attrs["NumPart_ThisFile"] = [count, 0, 0, 0, 0, 0]
        header.attrs["NumPart_Total"] = [count, 0, 0, 0, 0, 0]
        header.attrs["MassTable"] = [0.25, 0.0, 0.0, 0.0, 0.0, 0.0]
        header.attrs["BoxSize"] = [10.0, 10.0, 10.0]
        if units:
            group = file.create_group("Units")
            for name, value in (("Unit mass in cgs (U_M)", 1.98841e33), ("Unit length in cgs (U_L)", 6.957e10),
                                ("Unit time in cgs (U_t)", 6.957e5), ("Unit current in cgs (U_I)", 1.0),
                                ("Unit temperature in cgs (U_T)", 1.0)):
                group.attrs[name] = [value]
        gas = file.create_group("PartType0")
        gas["Coordinates"] = rng.uniform(0, 10, (count, 3)).astype(np.float32)
        gas["Velocities"] = rng.normal(size=(count, 3)).astype(np.float32)
        gas["SmoothingLengths"] = np.full(count, 0.5, dtype=np.float32)
        gas["InternalEnergies"] = np.full(count, 2.0, dtype=np.float32)
        gas["ParticleIDs"] = np.arange(1, count + 1, dtype=np.uint32)
    return count


def test_a_swift_file_is_read_in_its_own_units_exactly(tmp_path):
    count = swift_file(tmp_path / "swift.hdf5")
    star = read_star(tmp_path / "swift.hdf5")
    assert star.units.name == "custom" and len(star) == count
    assert (star.units.mass_si, star.units.length_si, star.units.time_si) == (1.98841e30, 6.957e8, 6.957e5)
    assert np.all(star.masses == 0.25) and np.all(star.smoothing_lengths == 0.5)
    cgs = star.in_units("cgs")
    assert np.allclose(cgs.masses, 0.25 * 1.98841e33, rtol=2e-16, atol=0)
    assert np.allclose(cgs.velocities, star.velocities * 1e5, rtol=4e-16, atol=0)  # Rsun / (Rsun / (km/s)) = 1e5 cm/s
    assert np.allclose(cgs.internal_energies, 2.0e10, rtol=4e-16, atol=0)


def test_a_file_without_units_takes_the_units_it_is_said_to_be_in(tmp_path):
    swift_file(tmp_path / "gadget.hdf5", units=False)
    with pytest.raises(StarFileError, match="does not state its units"):
        read_star(tmp_path / "gadget.hdf5")
    assert read_star(tmp_path / "gadget.hdf5", default_units="stellar").units.name == "stellar"


def test_gadget_unit_names_in_the_header_are_read(tmp_path):
    swift_file(tmp_path / "gadget.hdf5", units=False)
    with h5py.File(tmp_path / "gadget.hdf5", "a") as file:
        file["Header"].attrs["UnitMass_in_g"] = 1.0
        file["Header"].attrs["UnitLength_in_cm"] = 1.0
        file["Header"].attrs["UnitVelocity_in_cm_per_s"] = 1.0
    assert read_star(tmp_path / "gadget.hdf5", default_units="stellar").units.name == "cgs"  # the file wins


def _edit(path, change):
    with h5py.File(path, "a") as file:
        change(file)


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (lambda f: f["Header"].attrs.__setitem__("NumFilesPerSnapshot", 4), "snapshot in 4 files"),
        (lambda f: f["Header"].attrs.__setitem__("Flag_Entropy_ICs", 1), "holds entropies"),
        (lambda f: f["Header"].attrs.__setitem__("NumPart_ThisFile", [20, 0, 0, 0, 5, 0]), "5 particles of type 4"),
        (lambda f: f["PartType0"].__delitem__("Velocities"), "no Velocities"),
        (lambda f: f.__delitem__("PartType0"), "no PartType0"),
        (lambda f: f["PartType0"]["ParticleIDs"].__setitem__(slice(0, 2), [7, 7]), "distinct"),
    ],
)
def test_a_file_that_is_not_a_star_is_one_line(tmp_path, change, message):
    path = tmp_path / "star.hdf5"
    swift_file(path)
    _edit(path, change)
    with pytest.raises(StarFileError, match=message) as caught:
        read_star(path)
    assert "\n" not in str(caught.value) and str(path) in str(caught.value)


def test_a_file_of_another_kind_is_one_line(tmp_path):
    for name in ("star.hdf5", "star.npz"):
        (tmp_path / name).write_text("not a star")
        with pytest.raises(StarFileError, match="not an"):
            read_star(tmp_path / name)
    with pytest.raises(ValueError, match="must end in"):
        read_star(tmp_path / "star.txt")
    with pytest.raises(FileNotFoundError):
        read_star(tmp_path / "missing.hdf5")


def test_without_h5py_the_message_names_the_extra(tmp_path, monkeypatch):
    star = pair_of_stars()
    write_star(star, tmp_path / "star.hdf5")
    monkeypatch.setitem(sys.modules, "h5py", None)  # import h5py now raises ImportError
    for attempt in (lambda: write_star(star, tmp_path / "other.hdf5"), lambda: read_star(tmp_path / "star.hdf5")):
        with pytest.raises(ImportError, match=r"pip install 'collisionkit\[stars\]'"):
            attempt()
    assert not (tmp_path / "other.hdf5").exists()
    write_star(star, tmp_path / "star.npz")  # .npz needs no h5py
    assert np.array_equal(read_star(tmp_path / "star.npz").ids, star.ids)
