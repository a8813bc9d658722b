"""What every particle run returns: :class:`ParticleRun`, the base of DSMC and MD results.

:class:`particles.dsmc.DSMCRun` and :class:`particles.md.MDRun` are frozen dataclasses
deriving from it; it holds the properties they share, so that a study can treat a
DSMC and an MD run alike (``run.distribution``, ``run.a2``, ``run.a2_error``,
``run.temperature``, ``run.n_collisions``, ``run.collisions_per_particle``,
``run.info``).  Each run's samples end in a
:class:`kinetic_fem.VelocityDistribution` with batch error bars.
"""

from __future__ import annotations

from kinetic_fem.distribution import RunInfo, VelocityDistribution

__all__ = ["ParticleRun"]


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
