"""What every particle run returns and how it is checkpointed.

:class:`ParticleRun` is the base of the DSMC and MD results; :class:`Checkpointing`
the one spelling of checkpoints, resume and the wall-time limit of both
(``checkpoint=``, ``checkpoint_every=``, ``resume=``, ``max_wall_time=``).

:class:`particles.dsmc.DSMCRun` and :class:`particles.md.MDRun` are frozen dataclasses
deriving from it; it holds the properties they share, so that a study can treat a
DSMC and an MD run alike (``run.distribution``, ``run.a2``, ``run.a2_error``,
``run.temperature``, ``run.n_collisions``, ``run.collisions_per_particle``,
``run.info``).  Each run's samples end in a
:class:`kinetic_fem.VelocityDistribution` with batch error bars.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from kinetic_fem.distribution import RunInfo, VelocityDistribution
from kinetic_fem.exceptions import FileFormatError
from kinetic_fem.files import npz_path, output_path
from kinetic_fem.model import check_nonnegative, check_positive

from .sampling import load_checkpoint

__all__ = ["ParticleRun", "Checkpointing", "MAX_EVENTS", "MEASUREMENT_EVENTS", "check_seed",
           "check_work", "check_memory", "check_measurements"]

MAX_EVENTS = 1e13
"""Most collisions (or time steps times particles) a run may plan: about a day at 1e8 per
second.  Longer studies are several checkpointed runs; raise it here to go beyond."""

MEASUREMENT_EVENTS = 5000.0
"""Cost of one measurement (a sample, record or snapshot of the N particles) beyond its N,
in events of :data:`MAX_EVENTS`: the Python around it, about 50 us at 1e8 events per
second."""


def check_seed(seed: object) -> object:
    """A root seed: None, a ``numpy.random.SeedSequence`` or an integer ``>= 0``.

    Parameters
    ----------
    seed : object
        The ``seed`` argument.

    Returns
    -------
    None, SeedSequence or int

    Raises
    ------
    TypeError
        For a bool (``seed=True`` is not the seed 1) or another type.
    ValueError
        For a negative integer.
    """
    if seed is None or isinstance(seed, np.random.SeedSequence):
        return seed
    if isinstance(seed, (bool, np.bool_)) or not isinstance(seed, (int, np.integer)):
        raise TypeError(f"seed must be None, an integer >= 0 or a numpy SeedSequence, got "
                        f"{type(seed).__name__} {seed!r}")
    if seed < 0:
        raise ValueError(f"seed={seed!r} is not allowed; seeds are integers >= 0")
    return int(seed)


def check_work(events: float, what: str,
               advice: str = "shorten the run or split it into checkpointed runs") -> None:
    """Refuse up front a run of more than :data:`MAX_EVENTS` planned events.

    Parameters
    ----------
    events : float
        The estimate (collisions, or time steps times particles).
    what : str
        How the estimate arose, for the message.
    advice : str
        What to change, for the message.
    """
    if not events <= MAX_EVENTS:
        raise ValueError(f"{what} plans about {events:.3g} events, more than "
                         f"particles.run.MAX_EVENTS = {MAX_EVENTS:.3g} (a day at 1e8 per "
                         f"second): {advice}")


def available_memory() -> float:
    """Bytes of memory available now (physical pages free; inf where unknown)."""
    try:
        return float(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):  # not POSIX
        return math.inf


def check_memory(n_bytes: float, what: str, advice: str = "use fewer particles") -> None:
    """Refuse up front a run whose arrays would not fit in the available memory.

    Parameters
    ----------
    n_bytes : float
        Estimated bytes of the run's arrays.
    what : str
        The run, for the message.
    advice : str
        What to change, for the message.

    Raises
    ------
    MemoryError
        If ``n_bytes`` exceeds :func:`available_memory`.
    """
    free = available_memory()
    if n_bytes > free:
        raise MemoryError(f"{what} needs about {n_bytes / 2**30:.3g} GiB of arrays; "
                          f"{free / 2**30:.3g} GiB are available: {advice}")


def check_measurements(count: float, n: int, n_bytes: float, what: str,
                       advice: str = "take fewer samples") -> None:
    """Refuse up front the measurements of a run beyond :data:`MAX_EVENTS` or the memory.

    Each of the ``count`` measurements reads the N particles and costs
    :data:`MEASUREMENT_EVENTS` more (:func:`check_work`); ``n_bytes`` is the memory of the
    run with them (:func:`check_memory`).

    Parameters
    ----------
    count : float
        Planned measurements (samples, records, snapshots), an estimate where the run
        decides (samples uniform in time).
    n : int
        Particles read by each.
    n_bytes : float
        Estimated bytes of the run's arrays with those measurements.
    what : str
        The measurements and the arguments that set them, for the message.
    advice : str
        What to change, for the message.

    Raises
    ------
    ValueError
        Beyond :data:`MAX_EVENTS`.
    MemoryError
        Beyond the available memory.
    """
    check_work(count * (n + MEASUREMENT_EVENTS), what, advice)
    check_memory(n_bytes, what, advice)


class ParticleRun:
    """Shared interface of particle results (no fields: the subclasses hold them).

    Subclasses (frozen dataclasses) hold the fields ``distribution``
    (:class:`~kinetic_fem.VelocityDistribution`), ``n_particles``, ``n_collisions``
    and ``info`` (:class:`~kinetic_fem.distribution.RunInfo`), and define
    ``temperature``.
    """

    distribution: VelocityDistribution
    n_particles: int
    n_collisions: int
    info: RunInfo

    @property
    def a2(self) -> float:
        """Kurtosis coefficient :math:`a_2` of :attr:`distribution`."""
        return self.distribution.a2

    @property
    def a2_error(self) -> float:
        """Standard error of :attr:`a2` from the batch spread."""
        return self.distribution.a2_error

    @property
    def collisions_per_particle(self) -> float:
        """Total collisions per particle, ``2 n_collisions / N``."""
        return 2.0 * self.n_collisions / self.n_particles

    @property
    def temperature(self) -> float:
        """Temperature of the run (the subclass says which: averaged or final)."""
        raise NotImplementedError


@dataclass(frozen=True)
class Checkpointing:
    """Checkpoints and wall-time limit of a DSMC or MD run.

    Attributes
    ----------
    path : Path, optional
        Checkpoint file (``.npz`` is appended unless it is the suffix: the path given
        is the path written); None: no checkpoints.
    every : float
        Write the state every ``every`` seconds of wall time (at the next stop point)
        and at the end of the run.
    resume : bool
        Continue from ``path`` if it exists (bit-identical to an uninterrupted run).
    max_wall_time : float, optional
        Stop after this many seconds (checkpoint written; ``info.message`` says so).
    """

    path: Path | None = None
    every: float = 300.0
    resume: bool = False
    max_wall_time: float | None = None

    @classmethod
    def from_arguments(cls, checkpoint: str | Path | None, checkpoint_every: float,
                       resume: bool, max_wall_time: float | None) -> Checkpointing:
        """Validate the public arguments of :mod:`particles.dsmc` and :mod:`particles.md`.

        Parameters
        ----------
        checkpoint : str or Path, optional
            Checkpoint file (``.npz`` appended unless it is the suffix, never replacing
            another one: ``"ck_alpha0.6"`` writes ``ck_alpha0.6.npz``); its directory
            must exist and be writable.  None: no checkpoints.
        checkpoint_every : float
            Seconds of wall time between checkpoints (``>= 0``).
        resume : bool
            Continue from ``checkpoint`` if the file exists.
        max_wall_time : float, optional
            Seconds after which the run stops (``> 0``).

        Raises
        ------
        TypeError
            If ``resume`` is not a bool (it once was a path: pass the path as
            ``checkpoint``).
        ValueError
            For ``resume=True`` without a path, negative intervals or wall times.
        OSError
            If the checkpoint cannot be written there (missing directory, no permission).
        """
        if not isinstance(resume, (bool, np.bool_)):
            raise TypeError(f"resume must be True or False (as in particles.dsmc), got "
                            f"{resume!r}; pass the file as checkpoint=<path>, resume=True")
        if resume and checkpoint is None:
            raise ValueError("resume=True needs a checkpoint path")
        every = check_nonnegative("checkpoint_every", checkpoint_every)
        wall = None if max_wall_time is None else check_positive("max_wall_time", max_wall_time)
        path = None if checkpoint is None else output_path(npz_path(checkpoint),
                                                           name="checkpoint")
        return cls(path, every, bool(resume), wall)

    def guard(self, engine: str, identity: tuple[str, Any]) -> None:
        """Refuse, before any work, a checkpoint file that is not one of this run.

        An existing file at :attr:`path` must be a valid checkpoint of ``engine`` (format,
        checksum) whose metadata entry ``identity[0]`` equals ``identity[1]``: it is then
        resumed (``resume=True``) or replaced.  Anything else is never overwritten.

        Raises
        ------
        kinetic_fem.exceptions.FileFormatError
            If the file is not a valid checkpoint of ``engine``.
        FileExistsError
            If it is a checkpoint of another run and ``resume`` is False.
        ValueError
            If it is a checkpoint of another run and ``resume`` is True.
        """
        if self.path is None or not self.path.exists():
            return
        try:
            _, meta = load_checkpoint(self.path, engine=engine)
        except FileFormatError as err:
            raise FileFormatError(f"{err}; it is left untouched: choose another checkpoint "
                                  "path") from None
        key, value = identity
        if meta.get(key) != value:
            if self.resume:
                raise ValueError(f"checkpoint {self.path} belongs to a different run (other "
                                 f"parameters): {meta.get(key)} != {value}")
            raise FileExistsError(f"checkpoint {str(self.path)!r} holds another run "
                                  f"({key} {meta.get(key)}); it is not overwritten: choose "
                                  "another checkpoint path or delete the file")
