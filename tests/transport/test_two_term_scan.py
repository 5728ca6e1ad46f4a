"""TwoTermScan: the boltzmann command's scan from Python (failures kept, warnings collected, tables written)."""

import csv

import pytest

from collisionkit.transport import TwoTermScan, catalogue_gas, lucas_saelee, reid_ramp, two_term_boltzmann


def test_a_scan_is_the_solver_at_each_point_and_writes_the_tables(tmp_path):
    scan = TwoTermScan(reid_ramp(), [1.0, 12.0], gas_temperature=0.0).run()
    for result, value in zip(scan.results, (1.0, 12.0)):
        assert result.mean_energy == two_term_boltzmann(reid_ramp(), value, 0.0).mean_energy
    paths = scan.write(tmp_path / "out")
    with open(paths[0], newline="") as table:
        rows = list(csv.DictReader(table))
    assert [float(row["E_N"]) for row in rows] == [1.0, 12.0]
    assert float(rows[1]["mean_energy"]) == scan.results[1].mean_energy
    with pytest.raises(FileExistsError, match="overwrite=True"):
        scan.write(tmp_path / "out")
    assert scan.write(tmp_path / "out", overwrite=True) == paths


def test_a_failed_point_is_kept_with_its_reason_and_the_scan_goes_on():
    scan = TwoTermScan(lucas_saelee(0.5), [50.0, 3000.0, 100.0], gas_temperature=0.0, growth="spatial").run()
    assert [r.reduced_field for r in scan.results] == [50.0, 100.0]
    assert scan.failed == [{"E_N": 3000.0, "reason": scan.failed[0]["reason"]}]
    assert "no steady-state Townsend growth" in scan.failed[0]["reason"]


def test_warnings_are_collected_not_lost():
    scan = TwoTermScan(catalogue_gas("Ar"), [100.0, 1e4]).run()
    assert len(scan.warnings) == 1 and "above 1000 eV" in scan.warnings[0]
    assert scan.summary()["warnings"] == scan.warnings


def test_an_interrupted_scan_goes_on_from_the_next_point(monkeypatch):
    scan = TwoTermScan(reid_ramp(), [1.0, 12.0, 24.0], gas_temperature=0.0)
    original = TwoTermScan.solve
    calls = []

    def stop_at_the_second(self, value):
        calls.append(value)
        if len(calls) == 2:
            raise KeyboardInterrupt
        original(self, value)

    monkeypatch.setattr(TwoTermScan, "solve", stop_at_the_second)
    with pytest.raises(KeyboardInterrupt):
        scan.run()
    assert [r.reduced_field for r in scan.results] == [1.0]
    scan.run()
    assert [r.reduced_field for r in scan.results] == [1.0, 12.0, 24.0] and calls == [1.0, 12.0, 12.0, 24.0]
