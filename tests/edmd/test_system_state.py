"""Tests of system checkpoints (collisionkit.edmd._system_state): bit-for-bit resumes, engine formats."""

import numpy as np
import pytest

from collisionkit import edmd
from tests.edmd.systems import fcc_system


def test_checkpoint_resume_is_bit_for_bit(tmp_path):
    straight = fcc_system(cells=4, eta=0.4)
    straight.run(collisions=10_000)
    straight.run(collisions=10_000)

    interrupted = fcc_system(cells=4, eta=0.4)
    interrupted.run(collisions=10_000)
    interrupted.save(tmp_path / "state.npz")
    resumed = edmd.HardSphereSystem.load(tmp_path / "state.npz")
    resumed.run(collisions=10_000)
    np.testing.assert_array_equal(resumed.positions(), straight.positions())
    np.testing.assert_array_equal(resumed.velocities(), straight.velocities())
    np.testing.assert_array_equal(resumed.acc, straight.acc)
    assert resumed.elapsed == straight.elapsed


def test_a_checkpoint_of_another_engine_format_is_refused():
    state = fcc_system(cells=2, eta=0.3).state_dict()
    edmd.HardSphereSystem.from_state_dict(state)  # its own format: fine
    del state["format"]  # as written before formats were numbered
    with pytest.raises(ValueError, match="engine format 1"):
        edmd.HardSphereSystem.from_state_dict(state)
