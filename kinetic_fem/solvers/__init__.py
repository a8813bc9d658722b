"""Deterministic solvers, one module per method (registered in :mod:`kinetic_fem.solve`).

- One Newton driver for every deterministic solver: :mod:`~kinetic_fem.solvers.newton`
  (Armijo line search, constraints by an update hook, stall at round-off reported as
  converged, one :class:`~kinetic_fem.solvers.newton.NewtonResult`).
- FEM (scikit-fem Galerkin): :mod:`~kinetic_fem.solvers.fem` (heated steady state, with
  :mod:`~kinetic_fem.solvers.fem.newton` and the warm-started curve
  :mod:`~kinetic_fem.solvers.fem.curve`),
  :mod:`~kinetic_fem.solvers.fem.cooling` (homogeneous cooling state, with
  :mod:`~kinetic_fem.solvers.fem.cooling_mesh` and
  :mod:`~kinetic_fem.solvers.fem.cooling_newton`),
  :mod:`~kinetic_fem.solvers.fem.evolution`, :mod:`~kinetic_fem.solvers.fem.transient`
  and :mod:`~kinetic_fem.solvers.fem.cooling_transient` (transients),
  :mod:`~kinetic_fem.solvers.fem.defaults` (meshes and cut-offs from the
  model's scales), :mod:`~kinetic_fem.solvers.relaxation` (the relaxation spectrum: the
  linearised system about the steady state).
- The paper's finite differences (Biben): :mod:`~kinetic_fem.solvers.finite_difference`
  (heated), :mod:`~kinetic_fem.solvers.fd_cooling` (cooling), with
  :mod:`~kinetic_fem.solvers.fd_march`, :mod:`~kinetic_fem.solvers.fd_newton`,
  :mod:`~kinetic_fem.solvers.hcs_newton`, :mod:`~kinetic_fem.solvers.fd_scales` and
  :mod:`~kinetic_fem.solvers.richardson`.
- Sonine spectral Galerkin: :mod:`~kinetic_fem.solvers.spectral`; the exact moment
  hierarchy of the Maxwell model: :mod:`~kinetic_fem.solvers.maxwell`.
- Quasi-elastic limits (phi, psi): :mod:`~kinetic_fem.solvers.scaling`, with
  :mod:`~kinetic_fem.solvers.scaling_common` and :mod:`~kinetic_fem.solvers.scaling_psi`.

Users call :func:`kinetic_fem.solve_heated`, :func:`kinetic_fem.solve_cooling`,
:func:`kinetic_fem.evolve_heated` and :func:`kinetic_fem.evolve_cooling`, which pick the
solver by its registry key (``"fem"``, ``"fd"``, ``"spectral"``).
"""
