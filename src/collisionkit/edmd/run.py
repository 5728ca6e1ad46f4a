"""An EDMD run as a library object: set up, equilibrate, measure, checkpoint, resume, compare with theory.

The run is a fixed, deterministic sequence of chunks: equilibration in
chunks of ``max(N, 10^4)`` pair collisions, then ``blocks`` measurement
blocks of ``collisions // blocks``. With a checkpoint, the full state is
written atomically after set-up and after every chunk and block, so a run
resumed from it continues bit for bit as if it had never stopped.
Trajectory frames are written at chunk and block ends (they never change
the dynamics)::

    run = EdmdRun(EdmdParameters(particles=500, packing_fraction=0.3, seed=1), checkpoint="run.npz")
    run.run()                          # killed? then:
    run = EdmdRun.resume("run.npz")
    run.run()
    run.summary()["compressibility_factor"]
"""

from __future__ import annotations

import contextlib
import dataclasses
import secrets
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .._io import CheckpointError, exclusive, read_checkpoint, write_checkpoint
from .._params import Parameters, check_integer, check_unchanged
from ._run_checks import check_saved_run, checked_parameters
from ._summary import edmd_summary
from .initial import lattice, lattice_cells, maxwell_boltzmann, random_fluid
from .measurement import Measurement, Sampler
from .system import HardSphereSystem

__all__ = ["EdmdParameters", "EdmdRun"]

EQUILIBRATION_PER_PARTICLE = 20
COLLISIONS_PER_PARTICLE = 200
# a transport run's default: 10 blocks of 200 per particle (400 mean free times) outlast the fit window tenfold
TRANSPORT_COLLISIONS_PER_PARTICLE = 2000
MIN_CHUNK = 10_000
CHECKPOINT_KIND = "edmd"
# kT above which an inelastic run with an elastic floor is reported as not cooled (under 1 % of the energy lost)
BARELY_COOLED = 0.99


@dataclasses.dataclass(frozen=True)
class EdmdParameters(Parameters):
    """The physics of an EDMD run, checked when made (units: diameter 1, mass 1, initial kT = 1).

    Parameters
    ----------
    dim : {2, 3}
        Discs or spheres.
    particles : int
        2 to 1e8.
    packing_fraction : float
        In (0, 0.5] in 3D, (0, 0.7] in 2D (:data:`MAX_PACKING_FRACTION`).
    restitution : float
        Coefficient of restitution in [0, 1].
    elastic_below : float, optional
        Contacts with a normal approach speed below this are elastic (>= 0).
    equilibration : int, optional
        Pair collisions before measuring (>= 0; default 20 per particle).
    collisions : int, optional
        Pair collisions measured (>= blocks; default 200 per particle, 2000
        with ``transport``).
    blocks : int
        Measurement blocks for the error bars, 2 to 100000.
    seed : int, optional
        Random seed (>= 0; default: drawn and reported).
    initial : str
        ``random`` (a compressed fluid) or a lattice: ``fcc``, ``sc`` (3D),
        ``square``, ``hexagonal`` (2D), which needs N = basis * cells^d.
    transport : bool
        Also measure the transport coefficients (shear and bulk viscosity,
        thermal conductivity, self-diffusion; the interdiffusion of a binary
        mixture), the pressure tensor and the velocity autocorrelation
        (:class:`~collisionkit.edmd.Sampler`); needs restitution 1.
    yeh_hummer : bool
        Also report D corrected to the infinite system (Yeh & Hummer, from
        the measured shear viscosity: :func:`~collisionkit.edmd.yeh_hummer_correction`);
        needs ``transport`` and dim 3.
    shear_rate : float
        Lees-Edwards shear at this rate (>= 0; 0: none): the summary gives
        the shear stress and ``shear_viscosity`` = -P_xy / G with errors
        (:class:`~collisionkit.edmd.HardSphereSystem`, ``shear_rate``);
        not with ``transport``.
    thermostat : bool
        Under shear: hold kT = 1 by rescaling the peculiar velocities after
        every 4 N pair collisions (elastic spheres heat up under shear; in
        between kT rises, and the summary's ``temperature_mean`` is its time
        average, at which ``shear_viscosity_enskog`` is given).
    engine : {"auto", "lists", "cells"}
        The event engine of the system (:class:`~collisionkit.edmd.HardSphereSystem`,
        ``engine``); "cells" not with ``shear_rate``. The summary's ``engine``
        is the one that ran ("auto": cells for dilute straight flights).

    Examples
    --------
    >>> EdmdParameters(particles=108, initial="fcc").resolved(seed=1).collisions
    21600
    >>> EdmdParameters(packing_fraction=0.55)
    Traceback (most recent call last):
    ...
    ValueError: packing_fraction must lie in (0, 0.5] for dim=3; got 0.55
    """

    dim: int = 3
    particles: int = 500
    packing_fraction: float = 0.3
    restitution: float = 1.0
    elastic_below: float | None = None
    equilibration: int | None = None
    collisions: int | None = None
    blocks: int = 10
    seed: int | None = None
    initial: str = "random"
    transport: bool = False
    yeh_hummer: bool = False
    shear_rate: float = 0.0
    thermostat: bool = False
    engine: str = "auto"

    def __post_init__(self):
        for name, value in checked_parameters(self).items():  # (._run_checks: every value, the rules between them)
            object.__setattr__(self, name, value)

    def resolved(self, seed=None) -> EdmdParameters:
        """A copy with the defaults that depend on other parameters filled in (and a seed drawn if none).

        Raises
        ------
        ValueError
            If the default number of collisions is below ``blocks``.

        Examples
        --------
        >>> resolved = EdmdParameters(particles=100).resolved(seed=5)
        >>> resolved.equilibration, resolved.collisions, resolved.seed
        (2000, 20000, 5)
        """
        per_particle = TRANSPORT_COLLISIONS_PER_PARTICLE if self.transport else COLLISIONS_PER_PARTICLE
        collisions = self.collisions if self.collisions is not None else per_particle * self.particles
        if collisions < self.blocks:
            raise ValueError(f"collisions ({collisions} by default for {self.particles} particles) must be >= "
                             f"blocks ({self.blocks}); set collisions")
        equilibration = self.equilibration
        if equilibration is None:
            equilibration = EQUILIBRATION_PER_PARTICLE * self.particles
        if seed is None:
            seed = self.seed if self.seed is not None else secrets.randbits(32)
        return self.replace(collisions=collisions, equilibration=equilibration, seed=seed)

    @property
    def total_collisions(self) -> int:
        """Pair collisions of the whole (resolved) run: equilibration and whole blocks.

        Examples
        --------
        >>> EdmdParameters(equilibration=100, collisions=1005, blocks=10).total_collisions
        1100
        """
        return self.equilibration + (self.collisions // self.blocks) * self.blocks


def _initial_system(parameters: EdmdParameters, progress: Callable[[float], Any] | None = None) -> HardSphereSystem:
    """The starting state: a compressed random fluid or a lattice with Maxwell-Boltzmann velocities."""
    p = parameters
    if p.initial == "random":
        fluid = random_fluid(p.dim, p.particles, p.packing_fraction, seed=p.seed, progress=progress)
        positions, velocities, box = fluid.positions(), fluid.velocities(), fluid.box[: p.dim]
    else:
        positions, box = lattice(p.initial, lattice_cells(p.initial, p.dim, p.particles), p.packing_fraction)
        velocities = maxwell_boltzmann(np.ones(p.particles), p.dim, kT=1.0, seed=p.seed)
    return HardSphereSystem(positions, velocities, 0.5, box, restitution=p.restitution, elastic_below=p.elastic_below,
                            shear_rate=p.shear_rate, thermostat=1.0 if p.thermostat else None, engine=p.engine)


class EdmdRun:
    """An EDMD run: equilibration chunks then measurement blocks, with checkpoints and trajectory frames.

    Parameters
    ----------
    parameters : EdmdParameters
        Resolved on creation (defaults per particle, a seed drawn if none).
    checkpoint : path, optional
        ``.npz`` written after set-up and every chunk and block.
    trajectory : path, optional
        GSD file for frames (needs ``gsd``); the last frame is always written.
    frame_every : int, optional
        A frame at the first chunk or block end after every this many pair collisions.
    progress : callable, optional
        ``progress(fraction)`` while compressing the random initial state.

    Examples
    --------
    >>> run = EdmdRun(EdmdParameters(particles=108, initial="fcc", collisions=4000, equilibration=2000, blocks=2, seed=1))
    >>> summary = run.run().summary()
    >>> summary["collisions"], abs(summary["compressibility_factor_relative_deviation"]) < 0.1  # eta = 0.3
    (4000, True)
    """

    def __init__(self, parameters: EdmdParameters, checkpoint=None, trajectory=None, frame_every: int | None = None,
                 progress=None, *, _state=None):
        if not isinstance(parameters, EdmdParameters):
            raise TypeError(f"parameters must be EdmdParameters; got {type(parameters).__name__}")
        if frame_every is not None:
            frame_every = check_integer("frame_every", frame_every, 1)
            if trajectory is None:
                raise ValueError("frame_every needs a trajectory file to write the frames to")
        self.parameters = parameters.resolved() if _state is None else parameters
        self.checkpoint = None if checkpoint is None else Path(checkpoint)
        self.trajectory = None if trajectory is None else Path(trajectory)
        self.frame_every = frame_every
        self._writer = None
        self._continued = False
        if _state is None:
            self.system = _initial_system(self.parameters, progress)
            self.sampler: Sampler | None = None
            self.equilibrated, self.frames, self.last_frame = 0, 0, -1
            self.initial_energy = self.system.kinetic_energy()
        else:
            self._restore(_state)

    # ---------------------------------------------------------------- checkpoints

    def save(self, path=None) -> Path | None:
        """Write the run's full state (``.npz``, atomically) to ``path`` or the run's checkpoint.

        Examples
        --------
        >>> EdmdRun(EdmdParameters(dim=2, particles=64, initial="square", seed=1)).save() is None  # no checkpoint
        True
        """
        path = self.checkpoint if path is None else Path(path)
        if path is None:
            return None
        arrays = dict(self.system.state_dict())
        if self.sampler is not None:
            arrays |= self.sampler.state_dict()
        state = {"equilibrated": self.equilibrated, "frames": self.frames, "last_frame": self.last_frame,
                 "initial_energy": self.initial_energy, "trajectory": None if self.trajectory is None else
                 str(self.trajectory.resolve()), "frame_every": self.frame_every}
        return write_checkpoint(path, CHECKPOINT_KIND, self.parameters.to_dict(), state, arrays)

    @classmethod
    def resume(cls, path, checkpoint=None, trajectory=None, frame_every=None, **given) -> EdmdRun:
        """The run saved in ``path``, ready to go on from where it stopped.

        Parameters
        ----------
        path : path
            A checkpoint written by :meth:`save`.
        checkpoint : path, optional
            Where to write checkpoints from now on (default: ``path``).
        trajectory : path, optional
            Frames from now on (default: none). The trajectory the run wrote
            before is continued, cut back to the frames the checkpoint knows,
            only when it is given again: a path stored in a checkpoint is data,
            never a place to write.
        frame_every : int, optional
            The frame interval (default: the saved one when the saved
            trajectory is continued).
        \\*\\*given
            Parameters given again (Python names or flags): each must equal
            the saved one (a resumed run keeps its physics).

        Raises
        ------
        ValueError
            If the file is not an EDMD checkpoint, or a damaged one (any of
            its arrays or entries out of shape or range:
            :class:`~collisionkit._io.CheckpointError`), or a parameter
            given differs.

        Examples
        --------
        >>> import pathlib, tempfile
        >>> path = pathlib.Path(tempfile.mkdtemp()) / "run.npz"
        >>> parameters = EdmdParameters(dim=2, particles=64, initial="square", equilibration=0, collisions=400,
        ...                             blocks=2, seed=1)
        >>> _ = EdmdRun(parameters, checkpoint=path).save()   # as after set-up
        >>> resumed = EdmdRun.resume(path, dim=2)             # a parameter given again must agree
        >>> resumed.run().measured
        400
        """
        saved = read_checkpoint(path, CHECKPOINT_KIND)
        try:
            parameters = EdmdParameters.from_mapping(saved.parameters)
        except (TypeError, ValueError) as error:
            raise CheckpointError(f"{path} holds parameters that are not valid now: {error}") from None
        check_unchanged(parameters, given, path)
        saved_trajectory = saved.entry("trajectory", "text", optional=True)
        saved_frame_every = saved.entry("frame_every", "integer", 1, optional=True)
        append = trajectory is not None and saved_trajectory is not None and \
            Path(trajectory).resolve() == Path(saved_trajectory)
        if frame_every is None and append:
            frame_every = saved_frame_every
        return cls(parameters, checkpoint=path if checkpoint is None else checkpoint, trajectory=trajectory,
                   frame_every=frame_every, _state={"saved": saved, "append": append})

    def _restore(self, state) -> None:
        saved = state["saved"]
        try:  # every array is checked before a kernel sees it
            self.system = HardSphereSystem.from_state_dict(saved.arrays)
        except ValueError as error:  # written by another engine version, or arrays out of shape or range
            raise CheckpointError(f"cannot resume from {saved.path}: {error}") from None
        arrays = saved.arrays
        try:
            self.sampler = Sampler.from_state_dict(self.system, arrays) if "sampler_scalars" in arrays else None
        except (KeyError, TypeError, ValueError, IndexError) as error:
            raise saved.damaged(f"its measurement cannot be read (no array {error})" if isinstance(error, KeyError)
                                else f"its measurement cannot be read ({error})") from None
        check_saved_run(saved, self.sampler, self.parameters, self.system)
        self.equilibrated = saved.entry("equilibrated", "integer", 0, self.parameters.equilibration)
        self.frames = saved.entry("frames", "integer", 0) if state["append"] else 0
        self.last_frame = saved.entry("last_frame", "integer", -1)
        self.initial_energy = saved.entry("initial_energy", "number", 0.0)
        self._append = self._continued = state["append"]

    # ---------------------------------------------------------------- running

    @property
    def continues_trajectory(self) -> bool:
        """True if this resumed run appends to the trajectory it wrote before (given again to :meth:`resume`)."""
        return self._continued

    @property
    def measured(self) -> int:
        """Pair collisions measured so far."""
        return 0 if self.sampler is None else self.sampler.done * self.sampler.per_block

    @property
    def finished(self) -> bool:
        """True once every measurement block is done."""
        return self.sampler is not None and self.sampler.finished

    def extend(self, collisions: int) -> int:
        """Measure at least ``collisions`` more pair collisions: whole blocks of the run's block length are added.

        A finished (or unfinished) run goes on with ``ceil(collisions / L)``
        more blocks of L = ``parameters.collisions // parameters.blocks``
        pair collisions, so every block, old and new, has the same length and
        the errors stay standard errors of equal blocks. The parameters (and
        the next checkpoint) record the new totals; call :meth:`run` to do them.

        Parameters
        ----------
        collisions : int
            More pair collisions to measure (>= 1), rounded up to whole blocks.

        Returns
        -------
        int
            The pair collisions added (a multiple of the block length).

        Examples
        --------
        >>> run = EdmdRun(EdmdParameters(dim=2, particles=64, initial="square", collisions=400, blocks=2, seed=1))
        >>> run.run().extend(250), run.parameters.blocks
        (400, 4)
        >>> run.run().measured
        800
        """
        collisions = check_integer("collisions", collisions, 1)
        p = self.parameters
        length = p.collisions // p.blocks
        added_blocks = -(-collisions // length)
        blocks = p.blocks + added_blocks
        self.parameters = p.replace(blocks=blocks, collisions=blocks * length)
        if self.sampler is not None:
            self.sampler.extend(added_blocks)
        return added_blocks * length

    def run(self, progress: Callable[[float], Any] | None = None) -> EdmdRun:
        """Do the equilibration chunks and measurement blocks still to do; write the last frame.

        Parameters
        ----------
        progress : callable, optional
            ``progress(fraction)``: the fraction of the run's pair collisions done, in [0, 1].

        Examples
        --------
        >>> fractions = []
        >>> run = EdmdRun(EdmdParameters(dim=2, particles=64, initial="square", collisions=400, blocks=2, seed=1))
        >>> run.run(progress=fractions.append).finished, fractions[-1]
        (True, 1.0)
        """
        p = self.parameters
        total = p.total_collisions

        def report(done: int):
            return None if progress is None else (lambda fraction: progress(min(1.0, (done + fraction * step) / total)))

        self._open_trajectory()
        try:
            if self.equilibrated == 0 and self.sampler is None:
                self._chunk_done()  # the initial state: a frame (with frame_every) and a checkpoint
            chunk = max(p.particles, MIN_CHUNK)
            while self.equilibrated < p.equilibration:
                step = min(chunk, p.equilibration - self.equilibrated)
                done = self.system.run(collisions=step, progress=report(self.equilibrated))
                if done == 0:
                    raise RuntimeError("the system stopped colliding during equilibration")
                self.equilibrated += done
                self._chunk_done()
            if self.sampler is None:
                self.sampler = Sampler(self.system, p.collisions, p.blocks, transport=p.transport)
            while not self.sampler.finished:
                step = self.sampler.per_block
                self.sampler.run_block(report(self.equilibrated + self.measured))
                self._chunk_done()
            self._frame(final=True)
        finally:
            self._close_trajectory()
        if progress is not None:
            progress(1.0)
        return self

    def _open_trajectory(self) -> None:
        """Lock the checkpoint and the trajectory for the run (a second writer is refused); open the trajectory.

        A resumed run appends to its trajectory: frames after the
        checkpoint's are dropped, and a file without all of the checkpoint's
        frames is refused (it is not this run's trajectory).
        """
        self._locks = contextlib.ExitStack()
        try:
            for path in (self.checkpoint, self.trajectory):
                self._locks.enter_context(exclusive(path))
            if self.trajectory is None:
                return
            from ..trajectory import GSDWriter, truncate_gsd

            append = getattr(self, "_append", False) and self.trajectory.exists()
            last_step = self.last_frame if self.frames > 0 else None
            self.frames = truncate_gsd(self.trajectory, self.frames, last_step=last_step) if append else 0
            self._writer = GSDWriter(self.trajectory, mode="a" if append else "w")
            self._append = True
        except BaseException:
            self._locks.close()
            raise

    def _close_trajectory(self) -> None:
        if self._writer is not None:
            self._writer.close()
            self._writer = None
        self._locks.close()

    def _frame(self, final: bool = False) -> None:
        step = self.system.collisions
        if self._writer is None or step == self.last_frame:
            return
        every = self.frame_every
        due = every is not None and (self.last_frame < 0 or step // every > self.last_frame // every)
        if due or final:
            self._writer.write(self.system, step)
            self.frames += 1
            self.last_frame = step

    def _chunk_done(self) -> None:
        self._frame()
        self.save()

    # ---------------------------------------------------------------- results

    def measurement(self) -> Measurement:
        """The measurement of the finished blocks.

        Examples
        --------
        >>> run = EdmdRun(EdmdParameters(dim=2, particles=64, initial="square", collisions=400, blocks=2, seed=1))
        >>> run.run().measurement().collisions
        400
        """
        if self.sampler is None or self.sampler.done == 0:
            raise RuntimeError("no measurement block has finished yet: call run() first")
        return self.sampler.result()

    def write_xyz(self, path) -> Path:
        """Write the current state as extended XYZ (ASE, OVITO).

        Examples
        --------
        >>> import pathlib, tempfile
        >>> run = EdmdRun(EdmdParameters(dim=2, particles=64, initial="square", seed=1))
        >>> run.write_xyz(pathlib.Path(tempfile.mkdtemp()) / "state.xyz").read_text().splitlines()[0]
        '64'
        """
        from ..trajectory import write_extended_xyz

        return write_extended_xyz(path, self.system, comment=f"collisionkit edmd seed {self.parameters.seed}")

    def summary(self, files: Sequence = ()) -> dict[str, Any]:
        """The run's results: the measurement (each value with ``*_error``), the theory and the parameters.

        Examples
        --------
        >>> run = EdmdRun(EdmdParameters(dim=2, particles=64, initial="square", collisions=400, blocks=2, seed=1))
        >>> summary = run.run().summary()
        >>> summary["theory"], summary["parameters"]["seed"], "compressibility_factor_error" in summary
        ('Henderson (1975)', 1, True)
        """
        return edmd_summary(self, self.measurement(), files)

    def cooling_note(self) -> str | None:
        """What an inelastic run's averages mean (it cooled, maybe to the elastic floor), or an elastic sheared run's
        temperature (the flow heated it by more than 5 % on average); else None.

        Examples
        --------
        >>> EdmdRun(EdmdParameters(dim=2, particles=64, initial="square", seed=1)).cooling_note() is None
        True
        >>> sheared = EdmdRun(EdmdParameters(dim=2, particles=64, initial="square", restitution=0.9, shear_rate=0.1))
        >>> sheared.cooling_note().split(":")[0]
        'restitution < 1 under shear'
        >>> heated = EdmdRun(EdmdParameters(dim=2, particles=64, initial="square", shear_rate=0.5, thermostat=True,
        ...                                 collisions=2560, blocks=2, seed=1))
        >>> heated.run().cooling_note().split(":")[0]
        "the flow heats the fluid between the thermostat's rescalings (every 4 N pair collisions)"
        """
        if self.parameters.restitution == 1.0:
            return None if self.sampler is None or self.sampler.done < 2 else _heating_note(self)
        system = self.system
        kT = system.temperature()
        if self.parameters.shear_rate != 0.0:
            return (f"restitution < 1 under shear: the viscous heating of the flow balances the collisional cooling "
                    f"in a steady state (kT from 1 to {kT:.3g}); compare with granular_shear_flow (dilute gas)")
        if system.elastic_below > 0 and kT > BARELY_COOLED:
            return (f"restitution < 1, but the gas barely cooled (kT from 1 to {kT:.3g}): contacts slower than "
                    f"--elastic-below {system.elastic_below:.3g} are elastic, and nearly all were; this is the run of "
                    "an elastic gas")
        note = (f"restitution < 1: the gas cooled as it ran (homogeneous cooling, Haff's law), kT from 1 to {kT:.3g}; "
                "Z, the collision frequency and D are averages over a cooling state, not equilibrium values")
        if system.elastic_below > 0 and kT < 100.0 * system.elastic_below**2:
            note += (f". It reached the elastic floor: contacts slower than --elastic-below {system.elastic_below:.3g} "
                     "are elastic (against inelastic collapse), so fewer --collisions follow the cooling itself")
        return note


def _heating_note(run) -> str | None:
    """What the temperature of an elastic sheared run means, if the flow heated it by more than 5 % on average."""
    p, m = run.parameters, run.measurement()
    if p.shear_rate == 0.0 or p.restitution != 1.0 or not m.temperature_mean > 1.05:
        return None
    reduced = p.shear_rate / m.collision_frequency
    where = "between the thermostat's rescalings (every 4 N pair collisions)" if p.thermostat else "(no thermostat)"
    note = (f"the flow heats the fluid {where}: kT averaged {m.temperature_mean:.3g}, the temperature the viscosity "
            f"and Enskog's value are taken at; reduced shear rate G / collision frequency {reduced:.2g}")
    if reduced > 0.1:
        note += (": beyond about 0.1 the fluid shear-thins, its viscosity below Enskog's G -> 0 value (0.97 of it at "
                 "0.09 for spheres at eta 0.3, 0.9 at 0.18 for discs)")
    return note
