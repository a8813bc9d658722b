"""Particle simulations of the one-dimensional inelastic gas.

``particles.dsmc``: Direct Simulation Monte Carlo of the homogeneous Boltzmann
equation.  ``particles.md``: event-driven molecular dynamics of hard rods on a ring.
Both return :class:`kinetic_fem.VelocityDistribution` results.
"""

import logging

logging.getLogger(__name__).addHandler(logging.NullHandler())
