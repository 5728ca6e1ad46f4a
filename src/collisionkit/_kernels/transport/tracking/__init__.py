"""Kernels of particle tracking in non-uniform fields and bounded volumes (Krasov, sec. 5.5, in full).

:mod:`.codes` (field, surface and record codes), :mod:`.fields` (E, B and
weighting fields at a point), :mod:`.geometry` (signed distances of the
bounding surfaces), :mod:`.integrator` (Dormand-Prince steps and dense
output), :mod:`.rates` (collision frequencies along the path and the choice
of a process), :mod:`.track` (the kernel) and :mod:`.ions` (ions drifting at
a constant mobility). The collision kinematics, cross-section lookup and
random streams are those of the swarm kernels (:mod:`collisionkit._kernels.transport`).
"""

from __future__ import annotations

from .track import track_particles

__all__ = ["track_particles"]
