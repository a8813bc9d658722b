"""Operators on a velocity discretisation: what every solver assembles and none repeats.

- :mod:`~kinetic_fem.operators.grid`: velocity grids, quadrature weights and the O(N)
  cumulative-moment convolutions.
- :mod:`~kinetic_fem.operators.collision`: exact moment identities of the collision operator.
- :mod:`~kinetic_fem.operators.fem_discretisation`, :mod:`~kinetic_fem.operators.fem_thermostat`
  and :mod:`~kinetic_fem.operators.fem_kernels`: the Galerkin weak forms (collision pair
  quadrature, thermostat, time derivative) and their numba kernels.
- :mod:`~kinetic_fem.operators.fem_pair_breaks`: break points of the inner pair integral.
- :mod:`~kinetic_fem.operators.adaptive`: meshes that follow the near-elastic humps and an
  a posteriori indicator of the error of ln f.
- :mod:`~kinetic_fem.operators.fd_kernels`: the strong form (the gain integral) of the
  paper's finite-difference scheme.
- :mod:`~kinetic_fem.operators.sonine_tensors`: the orthonormal Sonine basis and the
  collision tensor of the spectral Galerkin projection.

Operators read the model (:mod:`kinetic_fem.model`) and know nothing of the solvers
(:mod:`kinetic_fem.solvers`) that use them.
"""
