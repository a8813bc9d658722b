"""Warnings and errors shared by the solvers (one public home, as :mod:`numpy.exceptions`).

Every solver raises or warns with these classes, so a caller filters one category for
all methods: ``warnings.simplefilter("ignore", kinetic_fem.exceptions.ResolutionWarning)``.
The model layer's :class:`~kinetic_fem.model.UnsupportedModelError` (a ``ValueError``)
stays with the model it validates.
"""

from __future__ import annotations

__all__ = ["ResolutionWarning", "ConvergenceWarning", "AsymptoticSeriesWarning",
           "ConvergenceError", "FileFormatError"]


class ResolutionWarning(UserWarning):
    """The grid, mesh or cut-off does not resolve the solution to the requested level.

    Raised (as a warning) by the FEM and finite-difference solvers when the distribution
    at the cut-off is not small enough, or the spacing is too coarse for the solution
    found; the message says which option to change.
    """


class ConvergenceWarning(UserWarning):
    """An iteration stopped before its stopping criterion was met.

    The result is returned (with ``info.converged = False``) instead of raising, so that
    a sweep can continue; the message gives the residual reached.
    """


class AsymptoticSeriesWarning(UserWarning):
    """A sequence of approximations stopped converging: the result is returned, but
    its error may be larger than the changes between approximations suggest.

    Warned by the Sonine solver when successive orders stop converging (the series is
    asymptotic there): by default when ``dist.error`` is first read (the check runs
    with the estimate), with ``check_series=True`` by the solve itself (then the
    result's ``info.extra['asymptotic_series']`` is True too); ``dist.error.asymptotic``
    says so either way.
    """


class ConvergenceError(RuntimeError):
    """An iteration (Newton, a continuation or a time integration) failed outright.

    Raised by the FEM solvers when no usable result exists; the message says what to
    change (a finer mesh, a longer cut-off, more iterations).
    """


class FileFormatError(ValueError):
    """A file cannot be read as what the loader expects: damaged, foreign or edited.

    Raised by every loader of the package (:func:`kinetic_fem.io.read_distribution`,
    :meth:`~kinetic_fem.VelocityDistribution.load`, :meth:`~kinetic_fem.Evolution.load`,
    the particle checkpoints) whatever the library underneath (numpy, zipfile, meshio);
    the message names the file and what was expected.  A missing file stays a
    ``FileNotFoundError``.
    """
