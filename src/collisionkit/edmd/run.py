"""An EDMD run as a library object: set up, equilibrate, measure, checkpoint, resume, compare with theory.

The run is a fixed, deterministic sequence of chunks: equilibration in
chunks of ``max(N, 10^4)`` pair collisions, then ``blocks`` measurement
blocks of ``collisions // blocks``. With a checkpoint, the full state is
written atomically after set-up and after every chunk and block, so a run
resumed from it continues bit for bit as if it had never stopped.
With a trajectory file, its last frame is always written, and with
``frame_every`` a frame at the first chunk or block end after every that
many pair collisions (frames never change the dynamics)::

    run = EdmdRun(EdmdParameters(particles=500, packing_fraction=0.3, seed=1), checkpoint="run.npz")
    run.run()                          # killed? then:
    run = EdmdRun.resume("run.npz")
    run.run()
    run.summary()["compressibility_factor"]

The run keeps its parameters, system, sampler and counters; its checkpoint
is written and read in ``_run_state``, its files are locked and its frames
written in ``_run_files``, and its summary and notes made in ``_summary``.
"""

from __future__ import annotations

import dataclasses
import secrets
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .._params import Parameters, check_integer
from ._run_checks import checked_parameters, species_counts
from ._run_files import RunFiles
from ._run_setup import SPIN_STREAM, initial_system, refuse_existing  # noqa: F401 (SPIN_STREAM: importable here)
from ._system_run import elastic_contacts
from ._run_state import CHECKPOINT_KIND, restore_run, resume_arguments, save_run  # noqa: F401 (CHECKPOINT_KIND)
from ._summary import BARELY_COOLED, cooling_note, edmd_summary  # noqa: F401 (BARELY_COOLED: the CLI's)
from .measurement import Measurement, Sampler
from .restitution_laws import BRIDGES_EXPONENT
from .system import HardSphereSystem

__all__ = ["EdmdParameters", "EdmdRun"]

EQUILIBRATION_PER_PARTICLE = 20
COLLISIONS_PER_PARTICLE = 200
# a transport run's default: 10 blocks of 200 per particle (400 mean free times) outlast the fit window tenfold
TRANSPORT_COLLISIONS_PER_PARTICLE = 2000
MIN_CHUNK = 10_000
# CHECKPOINT_KIND (the kind of the run's checkpoints) is defined in ._run_state, BARELY_COOLED (the kT above which an
# inelastic run with an elastic floor is reported as not cooled) in ._summary: both are importable from here as before


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
        Coefficient of normal restitution in [0, 1]. With ``fractions`` it
        may be a symmetric matrix over the species (alpha_ab of each pair):
        an inelastic mixture's summary then gives each species' temperature
        against the homogeneous cooling state's
        (:func:`~collisionkit.edmd.homogeneous_cooling_temperatures`).
    elastic_below : float, optional
        Contacts with a normal approach speed below this are elastic (>= 0).
    restitution_law : {"constant", "bridges", "viscoelastic"}
        The restitution of a contact as a function of its normal approach
        speed u_n (:func:`~collisionkit.edmd.restitution_coefficient`): the
        smaller of ``restitution`` and the law's e(u_n). "bridges":
        (u_n / law_speed)^-law_exponent above law_speed (ice, planetary
        rings); "viscoelastic": viscoelastic spheres, 1 - e = (u_n /
        law_speed)^(1/5) + ... A cooling gas of one species is compared with
        :func:`~collisionkit.edmd.maxwellian_cooling_rate`.
    law_speed : float
        The law's speed u_c, in (0, 1e30] thermal speeds (default 1).
    law_exponent : float
        The Bridges law's exponent, in (0, 10] (default 0.234, ice).
    tangential_restitution : float, optional
        Rough spheres (default None: smooth): beta in [-1, 1], the ratio of
        the touching surfaces' tangential relative velocity after a contact
        to before, reversed (:class:`~collisionkit.edmd.HardSphereSystem`).
        The spins start at rotational kT = 1 (equipartition) unless
        ``initial_rotational_temperature`` says otherwise; the summary
        gives the rotational temperature, and a cooling gas of one species
        with a constant restitution its ratio T_r / T and cooling rate
        against the homogeneous cooling state of rough spheres
        (:func:`~collisionkit.edmd.rough_cooling_state`). Not with
        ``transport``, ``shear_rate`` or ``well_width``.
    inertia_factor : float, optional
        kappa = I / (m a^2) in (0, 1] of rough spheres (default 2/5 for
        spheres, 1/2 for discs: uniform bodies).
    friction : float, optional
        Walton's friction coefficient mu > 0 of rough contacts (default None:
        no Coulomb limit): a contact sticks, or slides when its tangential
        impulse would exceed mu times the normal one. The Maxwellian theory
        is of a constant beta: with friction none is given.
    initial_rotational_temperature : float
        Rough spheres' rotational kT at the start, in [0, 100] (default 1,
        equipartition; 0 starts them without spin).
    equilibration : int, optional
        Pair collisions before measuring (>= 0; default 20 N, each particle
        colliding 40 times on average).
    elastic_equilibration : bool
        Equilibrate with every contact elastic and smooth, so that a cooling
        run starts from an equilibrium fluid at kT = 1 when the measurement
        begins (default False: the equilibration cools it too).
    collisions : int, optional
        Pair collisions measured (>= blocks; default 200 N, 2000 N with
        ``transport``).
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
    well_width : float, optional
        Square wells of this width lambda in (1, 5] (in diameters; default
        None: hard spheres): :class:`~collisionkit.edmd.HardSphereSystem`'s
        ``well_width``. The equilibration then holds kT = 1 by rescaling the
        velocities after every chunk of N pair collisions; the measurement
        runs at constant energy, and the summary's ``temperature_mean`` is
        its exact time-mean kT and ``potential_energy`` the mean potential
        energy per particle. Not with ``shear_rate``, ``transport`` or
        engine "cells".
    well_depth : float
        epsilon > 0 of the wells, in units of the kT = 1 the run equilibrates
        at: the reduced temperature is T* = 1 / ``well_depth``. With
        ``fractions``, ``well_width`` and ``well_depth`` may each be a
        symmetric matrix over the species (a depth of 0: that pair has hard
        cores only; T* is then taken with the deepest well).
    fractions : sequence of float, optional
        A mixture: the number fractions of its species (> 0, summing to 1;
        default None: one species). The counts are N x_i rounded by the
        largest remainders (:attr:`species_counts`), each at least 1. Needs
        ``initial`` "random". The summary then compares Z with the BMCSL
        (spheres) or SYH (discs) equation of state and the collision
        frequency with Enskog's for mixtures (:mod:`~collisionkit.edmd.mixture_theory`).
    diameters : sequence of float, optional
        One per species, relative to the largest, which is the unit of
        length: the largest is 1, the others in [0.1, 1] (default: all 1).
    masses : sequence of float, optional
        One per species, in [1e-3, 1e3] (default: all 1, the unit of mass).

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
    restitution: float | tuple[tuple[float, ...], ...] = 1.0
    elastic_below: float | None = None
    restitution_law: str = "constant"
    law_speed: float = 1.0
    law_exponent: float = BRIDGES_EXPONENT
    tangential_restitution: float | None = None
    inertia_factor: float | None = None
    friction: float | None = None
    initial_rotational_temperature: float = 1.0
    equilibration: int | None = None
    elastic_equilibration: bool = False
    collisions: int | None = None
    blocks: int = 10
    seed: int | None = None
    initial: str = "random"
    transport: bool = False
    yeh_hummer: bool = False
    shear_rate: float = 0.0
    thermostat: bool = False
    engine: str = "auto"
    well_width: float | tuple[tuple[float, ...], ...] | None = None
    well_depth: float | tuple[tuple[float, ...], ...] = 1.0
    fractions: tuple[float, ...] | None = None
    diameters: tuple[float, ...] | None = None
    masses: tuple[float, ...] | None = None

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
    def elastic(self) -> bool:
        """True if every pair's restitution is 1, no law lowers it and rough spheres (if any) are smooth or perfectly
        rough (beta = -1 or 1).

        Examples
        --------
        >>> EdmdParameters().elastic, EdmdParameters(restitution=0.9).elastic
        (True, False)
        >>> EdmdParameters(restitution_law="viscoelastic", law_speed=1e6).elastic
        False
        >>> EdmdParameters(fractions=(0.5, 0.5), restitution=((1.0, 0.9), (0.9, 1.0))).elastic
        False
        >>> EdmdParameters(tangential_restitution=1.0).elastic, EdmdParameters(tangential_restitution=0.5).elastic
        (True, False)
        """
        rough_losses = self.tangential_restitution is not None and self.tangential_restitution != -1.0 and (
            self.tangential_restitution != 1.0 or self.friction is not None)  # (sliding loses energy)
        return (bool(np.all(np.asarray(self.restitution) == 1.0)) and self.restitution_law == "constant"
                and not rough_losses)

    @property
    def species_counts(self) -> tuple[int, ...]:
        """The particles of each species: N x_i rounded by the largest remainders (one species: N).

        Examples
        --------
        >>> EdmdParameters(particles=10, fractions=(0.25, 0.75), diameters=(1.0, 0.5)).species_counts
        (3, 7)
        """
        return species_counts(self.particles, self.fractions)

    @property
    def total_collisions(self) -> int:
        """Pair collisions of the whole (resolved) run: equilibration and whole blocks.

        Examples
        --------
        >>> EdmdParameters(equilibration=100, collisions=1005, blocks=10).total_collisions
        1100
        """
        return self.equilibration + (self.collisions // self.blocks) * self.blocks


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
    overwrite : bool
        Replace an existing ``checkpoint`` or ``trajectory`` file (another
        run's); without it such a file is refused (FileExistsError) before
        any work. A resumed run (:meth:`resume`) writes to its own files.

    Examples
    --------
    >>> run = EdmdRun(EdmdParameters(particles=108, initial="fcc", collisions=4000, equilibration=2000, blocks=2, seed=1))
    >>> summary = run.run().summary()
    >>> summary["collisions"], abs(summary["compressibility_factor_relative_deviation"]) < 0.1  # eta = 0.3
    (4000, True)
    """

    def __init__(self, parameters: EdmdParameters, checkpoint=None, trajectory=None, frame_every: int | None = None,
                 progress=None, *, overwrite: bool = False, _state=None):
        if not isinstance(parameters, EdmdParameters):
            raise TypeError(f"parameters must be EdmdParameters; got {type(parameters).__name__}")
        if _state is None and not overwrite:
            refuse_existing(checkpoint=checkpoint, trajectory=trajectory)
        if frame_every is not None:
            frame_every = check_integer("frame_every", frame_every, 1)
            if trajectory is None:
                raise ValueError("frame_every needs a trajectory file to write the frames to")
        self.parameters = parameters.resolved() if _state is None else parameters
        self.checkpoint = None if checkpoint is None else Path(checkpoint)
        self.trajectory = None if trajectory is None else Path(trajectory)
        self.frame_every = frame_every
        self._continued = False
        if _state is None:
            self.system = initial_system(self.parameters, progress)
            self.sampler: Sampler | None = None
            self.equilibrated, self.frames, self.last_frame = 0, 0, -1
            self.initial_energy = self.system.total_kinetic_energy()
        else:
            restore_run(self, _state)

    # ---------------------------------------------------------------- checkpoints

    def save(self, path=None) -> Path | None:
        """Write the run's full state (``.npz``, atomically) to ``path`` or the run's checkpoint.

        Examples
        --------
        >>> EdmdRun(EdmdParameters(dim=2, particles=64, initial="square", seed=1)).save() is None  # no checkpoint
        True
        """
        path = self.checkpoint if path is None else Path(path)
        return None if path is None else save_run(self, path)

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
        return cls(**resume_arguments(EdmdParameters, path, checkpoint, trajectory, frame_every, given))

    # ---------------------------------------------------------------- running

    @property
    def continues_trajectory(self) -> bool:
        """True if this resumed run appends to the trajectory it wrote before (given again to :meth:`resume`)."""
        return self._continued

    def __repr__(self) -> str:
        p = self.parameters
        return (f"EdmdRun({p.particles} particles in {p.dim}D, eta={p.packing_fraction:g}, equilibrated "
                f"{self.equilibrated} of {p.equilibration}, measured {self.measured} of {p.collisions} collisions, "
                f"checkpoint={None if self.checkpoint is None else str(self.checkpoint)!r})")

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

        with RunFiles(self) as files:
            if self.equilibrated == 0 and self.sampler is None:
                self._chunk_done(files)  # the initial state: a frame (with frame_every) and a checkpoint
            chunk = max(p.particles, MIN_CHUNK)
            while self.equilibrated < p.equilibration:
                step = min(chunk, p.equilibration - self.equilibrated)
                with elastic_contacts(self.system, p.elastic_equilibration):
                    done = self.system.run(collisions=step, progress=report(self.equilibrated))
                if done == 0:
                    raise RuntimeError("the system stopped colliding during equilibration")
                self.equilibrated += done
                if p.well_width is not None:  # a square-well fluid equilibrates at kT = 1
                    self.system.rescale_temperature(1.0)
                self._chunk_done(files)
            if self.sampler is None:
                self.sampler = Sampler(self.system, p.collisions, p.blocks, transport=p.transport)
            while not self.sampler.finished:
                step = self.sampler.per_block
                self.sampler.run_block(report(self.equilibrated + self.measured))
                self._chunk_done(files)
            files.frame(final=True)
        if progress is not None:
            progress(1.0)
        return self

    def _chunk_done(self, files: RunFiles) -> None:
        """After set-up and every chunk and block: a frame if one is due, and the checkpoint."""
        files.frame()
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
        return cooling_note(self)
