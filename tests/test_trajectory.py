"""Tests of collisionkit.trajectory: GSD frames (HOOMD conventions) and extended XYZ."""

import shlex
import sys

import gsd.hoomd as gsd_hoomd  # the io extra is part of collisionkit[test]
import numpy as np
import pytest

from collisionkit import edmd, trajectory


def mixture_3d(periodic=True):
    """108 FCC spheres of two species with different radii and masses."""
    positions, box = edmd.lattice("fcc", 3, 0.2)
    species = np.arange(len(positions)) % 2
    radii = np.where(species == 0, 0.5, 0.35)
    masses = np.where(species == 0, 1.0, 0.4)
    velocities = edmd.maxwell_boltzmann(masses, 3, seed=4)
    return edmd.HardSphereSystem(positions, velocities, radii, box, masses, periodic=periodic, species=species)


def discs_2d():
    positions, box = edmd.lattice("hexagonal", 6, 0.4)
    velocities = edmd.maxwell_boltzmann(np.ones(len(positions)), 2, seed=2)
    return edmd.HardSphereSystem(positions, velocities, 0.5, box)


def test_gsd_frames_follow_the_hoomd_schema_in_3d(tmp_path):
    system = mixture_3d()
    path = tmp_path / "mixture.gsd"
    with trajectory.GSDWriter(path) as writer:
        writer.write(system, 0)
        system.run(collisions=500)
        writer.write(system, 500)
    L = system.box[:3]
    with gsd_hoomd.open(str(path), "r") as frames:
        assert len(frames) == 2
        frame = frames[1]
    assert frame.configuration.step == 500 and frame.configuration.dimensions == 3
    assert np.array_equal(frame.configuration.box, np.float32([*L, 0, 0, 0]))
    position = frame.particles.position
    assert position.dtype == np.float32 and position.shape == (108, 3)
    assert np.all(position >= -L.astype(np.float32) / 2) and np.all(position < L.astype(np.float32) / 2)
    assert position == pytest.approx(system.positions() - L / 2, abs=1e-6)
    assert frame.particles.velocity == pytest.approx(system.velocities(), rel=1e-6, abs=1e-7)
    assert list(frame.particles.types) == ["A", "B"]
    assert np.array_equal(frame.particles.typeid, system.species)
    assert np.array_equal(frame.particles.diameter, np.float32(2 * system.radius))
    assert np.array_equal(frame.particles.mass, np.float32(system.mass))


@pytest.mark.parametrize("system", [mixture_3d, discs_2d, lambda: mixture_3d(periodic=[True, False, True])])
def test_gsd_images_unwrap_the_trajectory(tmp_path, system):
    # position + image * L is the unwrapped path (HOOMD convention; freud and OVITO unwrap with it):
    # the images were all zero, so a GSD file's MSD stopped growing at the box size
    system = system()
    system.run(collisions=40 * system.count)
    assert np.abs(system.image).max() >= 1  # long enough that particles crossed the box
    path = tmp_path / "run.gsd"
    trajectory.write_gsd_frame(path, system, 0)
    with gsd_hoomd.open(str(path), "r") as frames:
        frame = frames[0]
    dim, L = system.dim, system.box[: system.dim]
    assert frame.particles.image.dtype == np.int32 and frame.particles.image.shape == (system.count, 3)
    assert np.all(frame.particles.image[:, dim:] == 0)
    assert np.all(frame.particles.image[:, :dim][:, ~np.asarray(system.periodic[:dim])] == 0)  # walls: no images
    unwrapped = frame.particles.position[:, :dim] + frame.particles.image[:, :dim] * L
    # float32 positions in [-L/2, L/2): half an ulp of L/2
    np.testing.assert_allclose(unwrapped, system.positions(unwrapped=True) - L / 2, rtol=0, atol=4e-7 * L.max())


def test_gsd_frames_in_2d_have_zero_z_and_lz(tmp_path):
    system = discs_2d()
    path = tmp_path / "discs.gsd"
    trajectory.write_gsd_frame(path, system, 3)
    with gsd_hoomd.open(str(path), "r") as frames:
        frame = frames[0]
    assert frame.configuration.dimensions == 2
    assert frame.configuration.box[2] == 0.0 and frame.configuration.box[:2] == pytest.approx(system.box[:2])
    assert np.all(frame.particles.position[:, 2] == 0) and np.all(frame.particles.velocity[:, 2] == 0)
    data = trajectory.read_gsd(path)
    assert data["dim"] == 2 and data["step"] == 3 and data["frames"] == 1
    assert data["positions"].shape == (72, 2)
    assert data["positions"] == pytest.approx(system.positions(), abs=1e-5)
    assert data["velocities"] == pytest.approx(system.velocities(), rel=1e-6, abs=1e-7)
    assert np.all(data["diameters"] == 1.0) and np.all(data["masses"] == 1.0) and data["types"] == ["A"]


def test_write_gsd_frame_appends_to_paths_and_open_files(tmp_path):
    system = discs_2d()
    path = tmp_path / "append.gsd"
    for step in (0, 10):
        trajectory.write_gsd_frame(path, system, step)
    with gsd_hoomd.open(str(path), "a") as handle:
        trajectory.write_gsd_frame(handle, system, 20)
    with trajectory.GSDWriter(path, mode="a") as writer:
        assert writer.frames == 3
        trajectory.write_gsd_frame(writer, system, 30)
    assert [trajectory.read_gsd(path, frame)["step"] for frame in range(4)] == [0, 10, 20, 30]
    assert trajectory.read_gsd(path, -4)["step"] == 0
    with pytest.raises(ValueError, match="frame must lie in"):
        trajectory.read_gsd(path, 4)


def test_truncate_gsd_keeps_the_first_frames(tmp_path):
    system = mixture_3d()
    path = tmp_path / "long.gsd"
    with trajectory.GSDWriter(path) as writer:
        for step in range(5):
            system.run(collisions=50)
            writer.write(system, step)
    third = trajectory.read_gsd(path, 2)
    path.chmod(0o644)
    assert trajectory.truncate_gsd(path, 3) == 3
    assert path.stat().st_mode & 0o777 == 0o644  # not the temporary file's private 0600
    data = trajectory.read_gsd(path)
    assert data["frames"] == 3 and data["step"] == 2
    assert np.array_equal(data["positions"], third["positions"])
    assert trajectory.truncate_gsd(path, 10) == 3
    assert trajectory.truncate_gsd(path, 0) == 0
    with pytest.raises(ValueError, match="holds no frames"):
        trajectory.read_gsd(path)
    assert list(tmp_path.iterdir()) == [path]  # no temporary file left behind


def test_gsd_writer_rejects_bad_arguments(tmp_path):
    with pytest.raises(ValueError, match="mode must be"):
        trajectory.GSDWriter(tmp_path / "x.gsd", mode="r")
    writer = trajectory.GSDWriter(tmp_path / "x.gsd")
    with pytest.raises(ValueError, match="step must be an integer >= 0"):
        writer.write(discs_2d(), -1)
    writer.close()
    writer.close()
    with pytest.raises(ValueError, match="closed"):
        writer.write(discs_2d(), 0)
    with pytest.raises(ValueError, match="frames must be an integer >= 0"):
        trajectory.truncate_gsd(tmp_path / "x.gsd", -1)


def test_missing_gsd_names_the_io_extra(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "gsd.hoomd", None)
    with pytest.raises(ImportError, match=r"collisionkit\[io\]"):
        trajectory.write_gsd_frame(tmp_path / "x.gsd", discs_2d(), 0)
    assert not (tmp_path / "x.gsd").exists()


def parse_extended_xyz(path):
    """The particle count, header fields and particle rows of a one-frame extended XYZ file."""
    lines = path.read_text().splitlines()
    count = int(lines[0])
    header = dict(field.split("=", 1) for field in shlex.split(lines[1]))
    rows = [line.split() for line in lines[2:]]
    assert len(rows) == count == len(lines) - 2
    return count, header, rows


def test_extended_xyz_header_and_exact_values_in_3d(tmp_path):
    system = mixture_3d(periodic=[True, False, True])
    system.run(collisions=300)
    path = trajectory.write_extended_xyz(tmp_path / "mixture.xyz", system, comment="two species")
    count, header, rows = parse_extended_xyz(path)
    assert count == 108
    assert header["Properties"] == "species:S:1:pos:R:3:vel:R:3:momenta:R:3:radius:R:1:masses:R:1:type:S:1"
    assert header["pbc"] == "T F T"
    assert np.array(header["Lattice"].split(), dtype=float).reshape(3, 3) == pytest.approx(np.diag(system.box), abs=0)
    assert int(header["Step"]) == system.collisions == 300
    assert float(header["Time"]) == system.elapsed > 0
    assert header["Comment"] == "two species"
    assert {row[0] for row in rows} == {"X"}
    assert [row[-1] for row in rows] == ["A" if s == 0 else "B" for s in system.species]
    values = np.array([row[1:-1] for row in rows], dtype=float)
    assert np.array_equal(values[:, 0:3], system.positions())  # 17 digits: exact round trip
    assert np.array_equal(values[:, 3:6], system.velocities())
    assert np.array_equal(values[:, 6:9], system.mass[:, None] * system.velocities())
    assert np.array_equal(values[:, 9], system.radius) and np.array_equal(values[:, 10], system.mass)


def test_extended_xyz_of_discs_is_a_slab(tmp_path):
    system = discs_2d()
    count, header, rows = parse_extended_xyz(trajectory.write_extended_xyz(tmp_path / "discs.xyz", system))
    lattice = np.array(header["Lattice"].split(), dtype=float).reshape(3, 3)
    assert lattice == pytest.approx(np.diag([system.box[0], system.box[1], 1.0]), abs=0)
    assert header["pbc"] == "T T F" and "Comment" not in header
    values = np.array([row[1:-1] for row in rows], dtype=float)
    assert np.all(values[:, 2] == 0) and np.all(values[:, 5] == 0)
    assert np.array_equal(values[:, :2], system.positions())
    with pytest.raises(ValueError, match="comment"):
        trajectory.write_extended_xyz(tmp_path / "bad.xyz", system, comment='say "hi"')
    assert not (tmp_path / "bad.xyz").exists()


@pytest.mark.parametrize("dim", [2, 3])
def test_ase_reads_the_extended_xyz_file(tmp_path, dim):
    import ase.io as ase_io  # the test extra installs ASE
    system = mixture_3d(periodic=[True, False, True]) if dim == 3 else discs_2d()
    system.run(collisions=200)
    atoms = ase_io.read(trajectory.write_extended_xyz(tmp_path / "run.xyz", system))
    assert len(atoms) == system.count
    np.testing.assert_array_equal(atoms.positions[:, :dim], system.positions())
    np.testing.assert_array_equal(atoms.arrays["vel"][:, :dim], system.velocities())
    np.testing.assert_array_equal(atoms.arrays["radius"], system.radius)
    np.testing.assert_array_equal(atoms.get_masses(), system.mass)  # ASE's names: not its dummy-atom mass
    np.testing.assert_allclose(atoms.get_velocities()[:, :dim], system.velocities(), rtol=4e-16, atol=0)
    assert list(atoms.arrays["type"]) == list(np.asarray(trajectory.type_names(system.species))[system.species])
    assert list(atoms.pbc) == list(system.periodic) + ([False] if dim == 2 else [])
    assert np.diag(atoms.cell)[:dim] == pytest.approx(system.box[:dim], abs=0)
    assert atoms.info["Step"] == system.collisions


def test_type_names_need_integer_species():
    with pytest.raises(TypeError, match="species must hold integers"):
        trajectory.type_names([0.5, 1.7])  # was ['A', 'B']
    assert trajectory.type_names(np.array([0.0, 2.0])) == ["A", "B", "C"]  # integral floats are indices


def test_type_names_beyond_the_alphabet():
    assert trajectory.type_names([0, 27])[-3:] == ["Z", "T26", "T27"]
    with pytest.raises(ValueError, match="species"):
        trajectory.type_names([-1, 0])


def test_read_gsd_frames_thins_and_caps_the_frames_read_gsd_reads(tmp_path):
    system = discs_2d()
    path = tmp_path / "run.gsd"
    with trajectory.GSDWriter(path) as writer:
        for step in range(5):
            writer.write(system, 10 * step)
            system.run(collisions=20)
    assert [frame["step"] for frame in trajectory.read_gsd_frames(path)] == [0, 10, 20, 30, 40]
    thinned = trajectory.read_gsd_frames(path, every=2)
    assert [frame["step"] for frame in thinned] == [0, 20, 40]
    assert all(frame["frames"] == 5 for frame in thinned)  # the file's frame count, not the frames read
    one_by_one = trajectory.read_gsd(path, 2)
    assert thinned[1].keys() == one_by_one.keys()
    assert all(np.array_equal(thinned[1][key], one_by_one[key]) for key in one_by_one)
    assert [frame["step"] for frame in trajectory.read_gsd_frames(path, every=2, max_frames=2)] == [0, 20]
    assert [frame["step"] for frame in trajectory.read_gsd_frames(path, every=np.int64(3), max_frames=9)] == [0, 30]


@pytest.mark.parametrize(
    ("options", "words"),
    [
        ({"every": 0}, "every must be an integer >= 1"),
        ({"every": 1.5}, "every must be an integer >= 1"),
        ({"max_frames": 0}, "max_frames must be an integer >= 1 or None"),
        ({"max_frames": 2.0}, "max_frames must be an integer >= 1 or None"),
    ],
)
def test_read_gsd_frames_rejects_bad_thinning(tmp_path, options, words):
    path = tmp_path / "one.gsd"
    trajectory.write_gsd_frame(path, discs_2d(), 0)
    with pytest.raises(ValueError, match=words):
        trajectory.read_gsd_frames(path, **options)


def test_read_gsd_frames_of_an_empty_file_is_an_error(tmp_path):
    path = tmp_path / "empty.gsd"
    trajectory.write_gsd_frame(path, discs_2d(), 0)
    trajectory.truncate_gsd(path, 0)
    with pytest.raises(ValueError, match="holds no frames"):
        trajectory.read_gsd_frames(path)


# ------------------------------------------------------------------ damaged files, locks, resumes that append


def _three_frames(path):
    system = discs_2d()
    with trajectory.GSDWriter(path) as writer:
        for step in (0, 10, 20):
            writer.write(system, step)
    return system


@pytest.mark.parametrize(
    "damage",
    [lambda data: data[: len(data) // 2], lambda data: data[:-100], lambda data: b"not a trajectory" * 9,
     lambda _: b""],
    ids=["cut in half", "cut short", "not GSD", "empty"],
)
def test_a_damaged_gsd_file_is_a_value_error_naming_it(tmp_path, damage):
    # gsd raised RuntimeError("Corrupt GSD file: ...") through truncate_gsd and GSDWriter at a resume
    path = tmp_path / "run.gsd"
    _three_frames(path)
    path.write_bytes(damage(path.read_bytes()))
    for action in (lambda: trajectory.truncate_gsd(path, 2), lambda: trajectory.GSDWriter(path, mode="a"),
                   lambda: trajectory.read_gsd(path), lambda: trajectory.read_gsd_frames(path)):
        with pytest.raises(ValueError) as caught:
            action()
        message = str(caught.value)
        assert message.startswith(f"{path} is damaged or is not a GSD trajectory") and "\n" not in message, message
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.gsd"]  # no lock or temporary file left behind


def test_a_resume_never_cuts_the_frames_its_checkpoint_knows_and_refuses_a_file_without_them(tmp_path):
    path = tmp_path / "run.gsd"
    system = _three_frames(path)
    before = path.read_bytes()
    assert trajectory.truncate_gsd(path, 3, last_step=20) == 3 and path.read_bytes() == before  # nothing to cut
    with pytest.raises(ValueError, match=r"holds 3 frames, fewer than the 5 its checkpoint wrote: it is not that run"):
        trajectory.truncate_gsd(path, 5, last_step=40)
    with pytest.raises(ValueError, match=r"has frame 1 at step 10, where its checkpoint wrote step 11"):
        trajectory.truncate_gsd(path, 2, last_step=11)
    assert path.read_bytes() == before  # refused: the file as it was
    trajectory.write_gsd_frame(path, system, 30)  # written after the checkpoint: dropped at the resume
    assert trajectory.truncate_gsd(path, 3, last_step=20) == 3
    assert trajectory.read_gsd(path)["step"] == 20


def test_an_open_gsd_writer_locks_its_file_against_other_processes(tmp_path):
    from collisionkit._io import FileLockedError
    from tests._io.processes import held_by_another_process

    path = tmp_path / "run.gsd"
    writing = "from collisionkit.trajectory import GSDWriter\nwriter = GSDWriter(sys.argv[1])"
    with held_by_another_process(writing, path) as pid:
        for action in (lambda: trajectory.GSDWriter(path, mode="a"), lambda: trajectory.truncate_gsd(path, 0),
                       lambda: trajectory.write_gsd_frame(path, discs_2d(), 0)):
            with pytest.raises(FileLockedError) as caught:
                action()
            assert f"run.gsd is being written by another collisionkit process (pid {pid})" in str(caught.value)
    with trajectory.GSDWriter(path, mode="a") as writer:  # closed (its process ended): free again
        assert (tmp_path / ".run.gsd.lock").exists()
        writer.write(discs_2d(), 0)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.gsd"]
