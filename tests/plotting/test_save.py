"""collisionkit.plotting.save: an image is written whole or not at all (a temporary file, then os.replace)."""

from __future__ import annotations

import pytest
from matplotlib.figure import Figure

from collisionkit import plotting


def _half_then_fail(self, fname, *args, **kwargs):
    """A savefig that writes half an image where it is told to, then fails (a full disk, a killed drawing)."""
    if hasattr(fname, "write"):
        fname.write(b"\x89PNG half")
    else:
        with open(fname, "wb") as stream:
            stream.write(b"\x89PNG half")
    raise OSError(28, "No space left on device")


@pytest.mark.parametrize("existing", [None, b"the old image"])
def test_a_failed_save_leaves_no_partial_image_and_no_temporary_file(tmp_path, monkeypatch, existing):
    target = tmp_path / "eedf.png"
    if existing is not None:
        target.write_bytes(existing)
    monkeypatch.setattr(Figure, "savefig", _half_then_fail)
    with pytest.raises(OSError, match="No space left"):
        plotting.save(plotting.plot_deflection_laws(), target)
    assert [path.name for path in tmp_path.iterdir()] == ([] if existing is None else ["eedf.png"])
    if existing is not None:
        assert target.read_bytes() == existing


def test_an_existing_image_is_replaced_whole_not_rewritten_in_place(tmp_path):
    target = tmp_path / "eedf.png"
    target.write_bytes(b"the old image")
    with open(target, "rb") as reader:  # a reader of the old file sees the old file, never a mix
        assert plotting.save(plotting.plot_deflection_laws(), target) == target
        assert reader.read() == b"the old image"
    assert target.read_bytes()[:4] == b"\x89PNG"
    assert [path.name for path in tmp_path.iterdir()] == ["eedf.png"]


@pytest.mark.parametrize("name, magic", [("plot.svg", b"<?xml"), ("plot.pdf", b"%PDF"), ("plot.PNG", b"\x89PNG")])
def test_the_suffix_still_sets_the_format(tmp_path, name, magic):
    target = plotting.save(plotting.plot_deflection_laws(), tmp_path / name)
    assert target.read_bytes().startswith(magic)
    assert [path.name for path in tmp_path.iterdir()] == [name]


def test_a_missing_folder_is_an_error_and_no_folder_is_made(tmp_path):
    """As matplotlib's savefig: a mistyped folder fails instead of being created (the demo's and Deliveries'
    doctests write to /no/such/folder to show the failure, and found it made by an earlier run)."""
    import matplotlib.pyplot as plt
    import pytest

    from collisionkit import plotting

    figure, ax = plt.subplots()
    with pytest.raises(FileNotFoundError, match="does not exist"):
        plotting.save(ax, tmp_path / "missing" / "plot.png")
    assert list(tmp_path.iterdir()) == []
