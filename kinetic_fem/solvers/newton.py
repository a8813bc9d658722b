"""One damped Newton driver for every deterministic solver.

Solves :math:`r(x) = 0` for :math:`x \\in \\mathbb R^m` by Newton's method with Armijo
backtracking.  Each iteration

1. linearises: :math:`J(x_k)\\,\\delta = -r(x_k)` (dense LU, sparse LU, GMRES for a
   matrix-free Jacobian, or a solver the caller passes), optionally equilibrated by row
   scales :math:`s_i(x_k)` and column scales :math:`t_j(x_k)`:
   :math:`(S^{-1} J T)\\,\\tilde\\delta = -S^{-1} r`, :math:`\\delta = T\\tilde\\delta`;
2. backtracks: the damping :math:`\\theta = 1, 1/2, 1/4, \\ldots` is accepted at the first
   trial :math:`x_k \\oplus \\theta\\delta` whose residual norm, with the row scales of
   :math:`x_k` frozen, satisfies the Armijo condition

   .. math:: \\|S_k^{-1} r(x_k \\oplus \\theta\\delta)\\| \\le (1 - c\\,\\theta)
             \\|S_k^{-1} r(x_k)\\|

   (``armijo`` is :math:`c`); below ``min_damping`` the search gives up and either takes
   the smallest step (``on_failure="accept"``, as a globalised Newton must to leave a
   local minimum of the norm) or stops (``on_failure="stop"``);
3. stops on the residual norm (``criterion="residual"``) or on the size of the full
   Newton step (``criterion="step"``), whichever the caller names, below ``tol``.

:math:`x \\oplus \\delta` is ``x + delta`` unless an ``update`` map is given (a relative
update :math:`P \\to P(1 + \\delta)` that keeps a density positive, a step in the
logarithm, a projection onto constraints).

**Stall at round-off.**  Quadratic convergence ends at the round-off floor of the
residual, which can lie above a tolerance chosen for the well-conditioned case.  When the
stopping measure is below ``stall_level`` and stopped decreasing (it exceeds a quarter of
the smaller of the previous two), or the step is below round-off relative to ``x``, the
iteration stops and reports *converged* with the measure it reached, saying so in the
message.  ``stall_level = 0`` (the default) disables the rule.

A non-finite residual at the start raises :class:`ValueError`; a non-finite trial
residual counts as no decrease (the step is halved), and a non-finite step (singular
system) stops the iteration, not converged.  :func:`run_info` turns the result into the
fields of :class:`~kinetic_fem.run_info.RunInfo` that a solver attaches to its result.
"""

from __future__ import annotations

import logging
import math
import time
import warnings
from dataclasses import dataclass, replace
from typing import Any, Callable, Literal, Mapping, Union

import numpy as np
import scipy.linalg
import scipy.sparse
import scipy.sparse.linalg
from numpy.typing import ArrayLike, NDArray

from ..options import option_group
from ..run_info import RunInfo

__all__ = ["NewtonResult", "NewtonReport", "NewtonOptions", "PseudoTransient", "newton",
           "run_info", "Jacobian"]

logger = logging.getLogger(__name__)

Array = NDArray[np.float64]
Jacobian = Union[Array, scipy.sparse.spmatrix, scipy.sparse.sparray,
                 scipy.sparse.linalg.LinearOperator, Callable[[Array], Array]]
"""A dense matrix, a scipy sparse matrix, a ``LinearOperator`` or a callable ``v -> J v``."""

System = Callable[[Array, bool], tuple[Array, Union[Jacobian, None]]]


@dataclass(frozen=True)
class NewtonResult:
    """Outcome of :func:`newton`.

    Parameters
    ----------
    x : ndarray, shape (m,)
        The last accepted iterate.
    converged : bool
        The stopping criterion was met, or the iteration stalled at round-off below
        ``stall_level``.
    iterations : int
        Newton steps taken (linear solves).
    residual : float
        Norm of the residual at ``x`` (with the row scales of ``x``).
    step : float
        Size ``step_norm(delta, x)`` of the last full Newton step (NaN before the first).
    history : tuple of float
        The stopping measure (residual norm or step size, as ``criterion`` says) after
        each iteration; for ``criterion="residual"`` it starts with the initial residual.
    message : str
        Human-readable status.
    """

    x: Array
    converged: bool
    iterations: int
    residual: float
    step: float
    history: tuple[float, ...]
    message: str


class NewtonReport:
    """Mixin of solver results that carry a :class:`NewtonResult` as ``newton``.

    Gives them the convergence report under the names every result uses:
    ``converged``, ``iterations``, ``residual`` and ``message`` (read from ``newton``).
    """

    newton: NewtonResult

    @property
    def converged(self) -> bool:
        """Newton's stopping criterion was met (or it stalled at round-off)."""
        return self.newton.converged

    @property
    def iterations(self) -> int:
        """Newton iterations."""
        return self.newton.iterations

    @property
    def residual(self) -> float:
        """The residual reached, in the solver's own (scaled) norm."""
        return self.newton.residual

    @property
    def message(self) -> str:
        """Newton's status message."""
        return self.newton.message


def _max_norm(r: Array, x: Array) -> float:
    return float(np.max(np.abs(r))) if r.size else 0.0


def _step_max(dx: Array, x: Array) -> float:
    return float(np.max(np.abs(dx))) if dx.size else 0.0


def _add(x: Array, dx: Array) -> Array:
    return x + dx


def _prediction(step: float, last_step: float, chord_rate: float) -> float:
    """The next step a chord iteration predicts after ``step``: ``step**2 / last_step``,
    or inf when ``step`` contracts ``last_step`` by less than ``chord_rate``."""
    return step * step / last_step if step <= chord_rate * last_step else math.inf


def _solve_default(jac: Jacobian, rhs: Array) -> Array:
    """``J^{-1} rhs`` by the solver that fits the Jacobian's type."""
    if isinstance(jac, np.ndarray):
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", scipy.linalg.LinAlgWarning)
                lu = scipy.linalg.lu_factor(jac, check_finite=False)
            return np.asarray(scipy.linalg.lu_solve(lu, rhs, check_finite=False))
        except (np.linalg.LinAlgError, ValueError):
            return np.full_like(rhs, np.nan)
    if scipy.sparse.issparse(jac):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", scipy.sparse.linalg.MatrixRankWarning)
            return np.asarray(scipy.sparse.linalg.spsolve(scipy.sparse.csc_matrix(jac), rhs))
    op = scipy.sparse.linalg.aslinearoperator(jac) if not callable(jac) or isinstance(
        jac, scipy.sparse.linalg.LinearOperator) else scipy.sparse.linalg.LinearOperator(
        (rhs.size, rhs.size), matvec=jac, dtype=float)
    step, _ = scipy.sparse.linalg.gmres(op, rhs, rtol=1e-14, atol=0.0, restart=80, maxiter=4)
    return np.asarray(step)


def _equilibrated(jac: Jacobian, rows: Array | None, cols: Array | None) -> Jacobian:
    """:math:`S^{-1} J T` for dense, sparse and matrix-free Jacobians."""
    if rows is None and cols is None:
        return jac
    r = np.ones(1) if rows is None else rows
    c = np.ones(1) if cols is None else cols
    if isinstance(jac, np.ndarray):
        return np.asarray(jac * c[None, :] / r[:, None])
    if scipy.sparse.issparse(jac):
        n_r, n_c = jac.shape  # type: ignore[union-attr]
        rs = scipy.sparse.diags(np.broadcast_to(1.0 / r, (n_r,)))
        cs = scipy.sparse.diags(np.broadcast_to(c, (n_c,)))
        return scipy.sparse.csr_matrix(rs @ jac @ cs)
    op = scipy.sparse.linalg.aslinearoperator(jac) if isinstance(
        jac, scipy.sparse.linalg.LinearOperator) else None
    apply = op.matvec if op is not None else jac
    assert callable(apply)
    return lambda v: np.asarray(apply(v * c)) / r


def _check_options(tol: float, max_iter: int, criterion: str, armijo: float,
                   min_damping: float, on_failure: str, stall_level: float) -> None:
    if not (isinstance(tol, (int, float)) and math.isfinite(tol) and tol > 0):
        raise ValueError(f"tol={tol!r} is not allowed; tol must be a finite number > 0")
    if isinstance(max_iter, bool) or not isinstance(max_iter, (int, np.integer)) \
            or max_iter < 0:
        raise ValueError(f"max_iter={max_iter!r} is not allowed; it must be an integer >= 0")
    if criterion not in ("residual", "step"):
        raise ValueError(f"criterion={criterion!r} is not allowed; use 'residual' or 'step'")
    if not 0.0 <= armijo < 1.0:
        raise ValueError(f"armijo={armijo!r} is not allowed; it must be in [0, 1)")
    if not 0.0 < min_damping <= 1.0:
        raise ValueError(f"min_damping={min_damping!r} is not allowed; it must be in (0, 1]")
    if on_failure not in ("accept", "stop"):
        raise ValueError(f"on_failure={on_failure!r} is not allowed; use 'accept' or 'stop'")
    if not stall_level >= 0.0:
        raise ValueError(f"stall_level={stall_level!r} is not allowed; it must be >= 0")


@dataclass(frozen=True)
class PseudoTransient:
    """Pseudo-transient globalisation of :func:`newton` (option ``pseudo_time``).

    Implicit Euler steps in a pseudo-time :math:`\\tau` of :math:`M\\,dx/d\\tau = r(x)`,
    whose attractor is the root: each iteration solves
    :math:`(J - M/\\Delta\\tau)\\,\\delta = -r` and takes the full step; the pseudo-time
    step grows by switched evolution relaxation (by the ratio of the last two step sizes,
    at least ``min_growth`` once that ratio exceeds ``stall_ratio``, clipped to
    ``growth_range``) and becomes infinite, Newton's method, once a step is below
    ``newton_below``.  The iteration stops when a Newton step (infinite
    :math:`\\Delta\\tau`) is below ``tol`` or ``stalled(history)`` says round-off is
    reached; converged if the last step is below ``tol`` or stalled.  ``step_norm``,
    ``update``, ``factorize`` (or ``linear_solver``), ``tol`` and ``max_iter`` of the
    :class:`NewtonOptions` apply; no line search.

    Parameters
    ----------
    first_step : float
        The first :math:`\\Delta\\tau` (> 0; ``inf``: Newton's method, full steps).
    mass : callable
        ``mass(x) -> M``, a dense (k, k) array: the leading k x k block of the Jacobian
        is shifted by :math:`-M/\\Delta\\tau`.
    stall_ratio, min_growth : float
        The growth floor of the switched evolution relaxation.
    newton_below : float
        Step size below which :math:`\\Delta\\tau = \\infty`.
    growth_range : tuple of float
        Smallest and largest growth factor of :math:`\\Delta\\tau` per step.
    stalled : callable, optional
        ``stalled(history) -> bool`` over the step sizes so far.
    """

    first_step: float
    mass: Callable[[Array], Array]
    stall_ratio: float = 0.9
    min_growth: float = 1.3
    newton_below: float = 1e-2
    growth_range: tuple[float, float] = (0.5, 3.0)
    stalled: Callable[[list[float]], bool] | None = None


@option_group
@dataclass(frozen=True)
class NewtonOptions:
    """The options of :func:`newton` that travel together.

    Parameters
    ----------
    tol, max_iter, criterion, norm, step_norm, update, linear_solver, row_scale, \
column_scale, line_search, armijo, min_damping, on_failure, stall_level, factorize, \
chord, chord_rate, chord_contracted, predict, predict_newton, pseudo_time, name
        As in :func:`newton` (``tol`` required).

    Examples
    --------
    >>> opts = NewtonOptions(tol=1e-12, max_iter=20, criterion="step")
    >>> replace(opts, max_iter=5).max_iter
    5
    """

    tol: float
    max_iter: int = 50
    criterion: Literal["residual", "step"] = "residual"
    norm: Callable[[Array, Array], float] | None = None
    step_norm: Callable[[Array, Array], float] | None = None
    update: Callable[[Array, Array], Array] | None = None
    linear_solver: Callable[[Any, Array], Array] | None = None
    row_scale: Callable[[Array], Array] | None = None
    column_scale: Callable[[Array], Array] | None = None
    line_search: bool = True
    armijo: float = 1e-4
    min_damping: float = 1e-3
    on_failure: Literal["accept", "stop"] = "accept"
    stall_level: float = 0.0
    factorize: Callable[[Any], Callable[[Array], Array]] | None = None
    chord: float = 0.0
    chord_rate: float = 0.1
    chord_contracted: float = 0.0
    predict: float = 0.0
    predict_newton: bool = False
    pseudo_time: PseudoTransient | None = None
    name: str = "Newton"


def newton(fun: System, x0: ArrayLike, options: NewtonOptions | None = None,
           **overrides: Any) -> NewtonResult:
    """Solve ``r(x) = 0`` by Newton's method with Armijo backtracking.

    Parameters
    ----------
    fun : callable
        ``fun(x, jacobian) -> (r, J)``: the residual, shape (n,), at ``x`` and, when
        ``jacobian`` is true, its Jacobian ``dr/dx`` (a dense array, a scipy sparse matrix,
        a ``LinearOperator`` or a callable ``v -> J v``); with ``jacobian`` false the
        second item is ignored (trial points of the line search need only ``r``).
        ``n`` may differ from ``x.size`` when ``update`` maps a reduced step (e.g. on the
        active nodes) to ``x``.  The residual of an accepted trial point is reused and its
        Jacobian requested only if another step is needed (``fun(x, True)`` at the same
        ``x`` again, so a ``fun`` that caches its last residual evaluates it once).
    x0 : array_like, shape (m,)
        Initial iterate.
    options : NewtonOptions, optional
        The options below as one object (``tol`` required, here or in ``overrides``).
    **overrides
        Any option below by keyword, over ``options`` (an unknown name raises
        :class:`TypeError`).
    tol : float
        Tolerance on the stopping measure named by ``criterion``.
    max_iter : int
        Newton steps allowed.
    criterion : {"residual", "step"}
        Stop when ``norm(r, x) < tol`` (checked before the first step too), or when the
        Newton step ``step_norm(delta, x) < tol`` (the full step is then taken).
    norm : callable, optional
        ``norm(r, x) -> float`` of a (row-scaled) residual; default the max norm.
    step_norm : callable, optional
        ``step_norm(dx, x) -> float`` of the damped step ``dx`` taken from ``x``; default
        the max norm.  ``criterion="step"`` measures the full (undamped) Newton step, so
        a step shortened by the line search never counts as convergence.
    update : callable, optional
        ``update(x, dx) -> x_new``; default ``x + dx``.  Use it for positivity-keeping
        relative updates, steps in the logarithm, or projections onto constraints.
    linear_solver : callable, optional
        ``linear_solver(J, b) -> J^{-1} b`` for the (equilibrated) Jacobian; default:
        dense LU, sparse LU (``spsolve``) or GMRES (relative accuracy 1e-14) by type.
    row_scale, column_scale : callable, optional
        ``x -> s`` (shape (n,)) and ``x -> t`` (shape (m,)), positive: the linear solve
        uses :math:`S^{-1}JT` and the line search compares :math:`\\|S^{-1}r\\|` with the
        row scales of the current iterate frozen.
    line_search : bool
        Backtrack (``True``) or always take the full step.
    armijo : float
        Sufficient-decrease constant :math:`c \\in [0, 1)` (0: any decrease).
    min_damping : float
        Smallest damping tried; below it the search fails.
    on_failure : {"accept", "stop"}
        When the search fails: take the smallest step anyway, or stop (converged only if
        the stall rule applies).
    stall_level : float
        Stall rule threshold (module docstring); 0 disables it.
    factorize : callable, optional
        ``factorize(J) -> solve`` with ``solve(b) = J^{-1} b`` for the (equilibrated)
        Jacobian, in place of ``linear_solver``; it lets chord steps reuse the factors.
    chord : float
        With ``factorize``: once a full Newton step is below ``chord`` (``step_norm``),
        the next steps reuse the last factorisation (residual only, no Jacobian) while
        each shrinks the step by ``chord_rate`` or more and decreases the residual;
        otherwise the Jacobian is refreshed.  0 (the default): plain Newton.
    chord_rate : float
        Contraction a chord step must reach, in (0, 1).  Without a line search the
        Jacobian of an iterate that will take a chord step is not evaluated.
    chord_contracted : float
        With ``chord``: a full Newton step below this (and above ``chord``) that
        contracts the previous full step by ``chord_rate**2`` or more (the quadratic
        regime: the chord iteration then contracts by about the square of that) is
        followed by chord steps too.  0 (the default): off.
    predict : float
        With ``criterion="step"``: take a chord step whose size times its contraction
        rate (the next step a chord iteration predicts) is below ``predict * tol`` and
        stop, converged, without the residual that would confirm it (the result's
        ``residual`` is then the previous iterate's); likewise a final Newton step below
        ``tol`` without a line search.  0 (the default): off.
    predict_newton : bool
        With ``predict``, ``stall_level`` and ``criterion="step"``: a Newton step below
        ``stall_level`` that contracts the previous full step by ``chord_rate`` or more
        and whose size times that contraction (``step**2 / previous``, the chord
        prediction) is below ``predict * tol`` is taken in full without line search or
        residual, and the iteration stops, converged.  A line search cannot judge such a
        step once the residual is at round-off (it backtracks on noise).  False (the
        default): off.
    pseudo_time : PseudoTransient, optional
        Pseudo-transient globalisation in place of the line search (its docstring); the
        other options but ``step_norm``, ``update``, ``factorize``/``linear_solver``,
        ``tol``, ``max_iter`` and ``name`` are then not used.
    name : str
        Prefix of log messages and of the result message.

    Returns
    -------
    NewtonResult

    Raises
    ------
    ValueError
        An option is out of range, or the residual at ``x0`` is not finite.

    Examples
    --------
    Newton converges quadratically on :math:`x^2 = 2`:

    >>> res = newton(lambda x, jac: (x**2 - 2.0, np.diag(2.0 * x)), [1.0], tol=1e-14)
    >>> res.converged, float(res.x[0]) == math.sqrt(2.0), res.iterations
    (True, True, 5)
    >>> ["%.0e" % h for h in res.history]
    ['1e+00', '2e-01', '7e-03', '6e-06', '5e-12', '0e+00']
    """
    o = NewtonOptions(**overrides) if options is None else replace(options, **overrides)
    tol, max_iter, criterion, name = o.tol, o.max_iter, o.criterion, o.name
    norm, step_norm, update, linear_solver = o.norm, o.step_norm, o.update, o.linear_solver
    row_scale, column_scale, line_search = o.row_scale, o.column_scale, o.line_search
    armijo, min_damping, on_failure = o.armijo, o.min_damping, o.on_failure
    stall_level, factorize, chord = o.stall_level, o.factorize, o.chord
    chord_rate, predict, predict_newton = o.chord_rate, o.predict, o.predict_newton
    chord_contracted = o.chord_contracted
    if o.pseudo_time is not None:
        return _pseudo_transient(fun, x0, o)
    _check_options(tol, max_iter, criterion, armijo, min_damping, on_failure, stall_level)
    if chord < 0.0 or not 0.0 < chord_rate < 1.0 or (chord > 0.0 and factorize is None):
        raise ValueError(f"chord steps need chord >= 0, 0 < chord_rate < 1 and a factorize "
                         f"callable; got chord={chord!r}, chord_rate={chord_rate!r}, "
                         f"factorize={factorize!r}")
    norm_ = norm or _max_norm
    step_norm_ = step_norm or _step_max
    update_ = update or _add
    solve = linear_solver or _solve_default
    x = np.array(x0, dtype=float, ndmin=1)

    def scaled_norm(r: Array, rows: Array | None, at: Array) -> float:
        return norm_(r if rows is None else r / rows, at)

    r, jac = fun(x, True)
    r = np.asarray(r, dtype=float)
    if not np.all(np.isfinite(r)):
        bad = np.flatnonzero(~np.isfinite(r))
        raise ValueError(f"{name}: the residual at the initial iterate is not finite "
                         f"(at {bad.size} of {r.size} equations, first index {bad[0]}); "
                         "start from a point where the equations can be evaluated")
    rows = row_scale(x) if row_scale is not None else None
    res = scaled_norm(r, rows, x)
    history: list[float] = [res] if criterion == "residual" else []
    step_size = math.nan
    it = 0
    message = ""
    converged = False
    # chord steps: the last factorisation, the scales it was made with, the last step
    factors: tuple[Callable[[Array], Array], Array | None, Array | None] | None = None
    use_chord, last_step, last_full = False, math.inf, False
    while True:
        if criterion == "residual" and res < tol:
            converged = True
            message = f"{name} converged: residual {res:.2e} < tol {tol:.1e}"
            break
        if it >= max_iter:
            message = (f"{name} not converged: {max_iter} iterations reached, residual "
                       f"{res:.2e}, last step {step_size:.2e} (tol {tol:.1e})")
            break
        it += 1
        if use_chord and factors is not None:
            solve_f, rows_f, cols_f = factors
            delta = np.asarray(solve_f(-(r if rows_f is None else r / rows_f)), dtype=float)
            if cols_f is not None:
                delta = delta * cols_f
            chord_step = step_norm_(delta, x)
            x_try = update_(x, delta)
            predicted = _prediction(chord_step, last_step, chord_rate)
            if (criterion == "step" and predicted < predict * tol
                    and bool(np.all(np.isfinite(x_try)))):
                # the chord iteration contracts at a nearly constant rate: the step still
                # to come is about `predicted`, far below tol; no residual to confirm it
                x, jac, step_size = x_try, None, chord_step
                history.append(step_size)
                converged = True
                message = (f"{name} converged: chord-predicted step {predicted:.2e} < "
                           f"{predict:g} tol")
                break
            r_try = np.asarray(fun(x_try, False)[0], dtype=float)
            rows_try = row_scale(x_try) if row_scale is not None else None
            res_try = scaled_norm(r_try, rows_try, x_try)
            if (math.isfinite(res_try) and bool(np.all(np.isfinite(x_try)))
                    and res_try < res):
                x, r, jac, rows, res = x_try, r_try, None, rows_try, res_try
                use_chord = chord_step <= chord_rate * last_step
                step_size, last_step, last_full = chord_step, chord_step, True
                measure = res if criterion == "residual" else step_size
                history.append(measure)
                logger.debug("%s %d: residual %.3e, chord step %.3e", name, it, res,
                             step_size)
                if criterion == "step" and step_size < tol:
                    converged = True
                    message = f"{name} converged: step {step_size:.2e} < tol {tol:.1e}"
                    break
                continue
            use_chord = False   # a failed chord step: refresh the Jacobian at x
        if jac is None:   # the accepted trial point was evaluated without its Jacobian
            r, jac = fun(x, True)
            r = np.asarray(r, dtype=float)
        if jac is None:
            raise TypeError(f"{name}: fun(x, True) returned no Jacobian")
        cols = column_scale(x) if column_scale is not None else None
        rhs = -(r if rows is None else r / rows)
        if factorize is not None:
            solve_f = factorize(_equilibrated(jac, rows, cols))
            factors = (solve_f, rows, cols)
            delta = np.asarray(solve_f(rhs), dtype=float)
        else:
            delta = np.asarray(solve(_equilibrated(jac, rows, cols), rhs), dtype=float)
        if cols is not None:
            delta = delta * cols
        if not np.all(np.isfinite(delta)):
            message = f"{name} stopped: singular Newton system at iteration {it}"
            break
        # backtracking with the row scales of x frozen
        newton_step = step_norm_(delta, x)
        small = criterion == "step" and newton_step < tol
        predicted = _prediction(newton_step, last_step, chord_rate)
        if (predict_newton and predict > 0.0 and criterion == "step" and last_full
                and newton_step < stall_level and predicted < predict * tol):
            x_try = update_(x, delta)
            if bool(np.all(np.isfinite(x_try))):
                # the residual may be at round-off: no line search on it, no residual
                x, jac, step_size, converged = x_try, None, newton_step, True
                history.append(step_size)
                message = f"{name} converged: Newton-predicted step {predicted:.2e}"
                break
        theta, accepted = 1.0, False
        x_t, r_t, jac_t = x, r, None
        while True:
            x_try = update_(x, theta * delta)
            if small and predict > 0.0 and not line_search and np.all(np.isfinite(x_try)):
                # converged on the step: the residual at the last iterate is not needed
                x_t, r_t, jac_t, accepted = x_try, r, None, True
                break
            # without a line search the trial is the next iterate: take its Jacobian now,
            # unless the next step will be a chord step
            r_try, jac_try = fun(x_try, not line_search and not (
                chord > 0.0 and newton_step < chord))
            r_try = np.asarray(r_try, dtype=float)
            res_try = scaled_norm(r_try, rows, x_try)
            finite = math.isfinite(res_try) and bool(np.all(np.isfinite(x_try)))
            if finite:
                x_t, r_t, jac_t = x_try, r_try, jac_try if not line_search else None
            if finite and (not line_search or small
                           or res_try <= (1.0 - armijo * theta) * res):
                accepted = True
                break
            if theta * 0.5 < min_damping:
                break
            theta *= 0.5
        if not accepted and (on_failure == "stop" or x_t is x):
            why = ("no finite residual along the step" if x_t is x
                   else f"no decrease of the residual down to damping {theta:.1e}")
            converged = res < stall_level
            message = (f"{name} stalled at round-off: {why}, residual {res:.2e} "
                       f"(tol {tol:.1e})" if converged else
                       f"{name} stopped: {why}, residual {res:.2e} (tol {tol:.1e})")
            break
        step_size = newton_step
        use_chord = chord > 0.0 and theta == 1.0 and (newton_step < chord or (
            newton_step < chord_contracted and last_full
            and newton_step <= chord_rate * chord_rate * last_step))
        last_step, last_full = newton_step, theta == 1.0
        x_old = x
        x, r, jac = x_t, r_t, jac_t
        rows = row_scale(x) if row_scale is not None else None
        res = scaled_norm(r, rows, x)
        measure = res if criterion == "residual" else step_size
        history.append(measure)
        logger.debug("%s %d: residual %.3e, step %.3e, damping %.3g", name, it, res,
                     step_size, theta)
        if criterion == "step" and step_size < tol:
            converged = True
            message = f"{name} converged: step {step_size:.2e} < tol {tol:.1e}"
            break
        roundoff = bool(np.all(np.abs(x - x_old) <= 4 * np.finfo(float).eps * np.abs(x_old)))
        flat = len(history) >= 3 and measure > 0.25 * min(history[-3:-1])
        if stall_level > 0 and measure < stall_level and (flat or roundoff):
            converged = True
            message = (f"{name} stalled at round-off: {criterion} {measure:.2e} "
                       f"(tol {tol:.1e})")
            logger.info("%s", message)
            break
        if roundoff and criterion == "residual" and res >= tol:
            message = f"{name} stopped: step below round-off, residual {res:.2e}"
            break
    if not converged:
        logger.info("%s", message)
    return NewtonResult(x, converged, it, res, step_size, tuple(history), message)


def _pseudo_transient(fun: System, x0: ArrayLike, o: NewtonOptions) -> NewtonResult:
    """:func:`newton` with the :class:`PseudoTransient` option (its docstring)."""
    pt = o.pseudo_time
    assert pt is not None
    step_norm = o.step_norm or _step_max
    update = o.update or _add
    x = np.array(x0, dtype=float, ndmin=1)
    history: list[float] = []
    dtau = pt.first_step
    it = 0
    for it in range(1, o.max_iter + 1):
        r, j = fun(x, True)
        assert isinstance(j, np.ndarray)
        if dtau < np.inf:
            shift = pt.mass(x) / dtau
            k = shift.shape[0]
            j[:k, :k] -= shift
        delta = (o.factorize(j)(-r) if o.factorize is not None
                 else (o.linear_solver or _solve_default)(j, -r))
        step = step_norm(delta, x)
        history.append(step)
        logger.debug("%s %d: step %.3e, dtau = %.3g", o.name, it, step, dtau)
        if not np.isfinite(step):
            break
        x = update(x, delta)
        if dtau == np.inf and (step < o.tol or (pt.stalled is not None
                                                and pt.stalled(history))):
            break
        # switched evolution relaxation: grow the step while the updates shrink
        ratio = history[-2] / step if len(history) > 1 else 2.0
        if ratio > pt.stall_ratio:  # not growing: the step creeps (a tail relaxing)
            ratio = max(ratio, pt.min_growth)
        low, high = pt.growth_range
        dtau = np.inf if step < pt.newton_below else dtau * min(max(ratio, low), high)
    last = history[-1] if history else math.nan
    stall = pt.stalled is not None and pt.stalled(history)
    converged = last < o.tol or stall
    message = (f"{o.name} {'converged' if converged else 'not converged'}: last step "
               f"{last:.1e} (tol {o.tol:.1e}){', stalled at round-off' if stall else ''}")
    return NewtonResult(x, converged, it, math.nan, last, tuple(history), message)


def run_info(result: NewtonResult, *, start: float | None = None,
             wall_time: float | None = None,
             extra: Mapping[str, Any] | None = None) -> RunInfo:
    """The :class:`~kinetic_fem.run_info.RunInfo` fields of a Newton solve.

    Parameters
    ----------
    result : NewtonResult
    start : float, optional
        ``time.perf_counter()`` when the solver started; the wall time is measured to now.
    wall_time : float, optional
        Seconds spent, when known otherwise (``start`` wins if both are given).
    extra : mapping, optional
        Method-specific figures for ``RunInfo.extra``.

    Returns
    -------
    RunInfo
        ``converged``, ``iterations``, ``residual``, ``message`` from ``result``.

    Examples
    --------
    >>> res = newton(lambda x, jac: (x - 1.0, np.eye(1)), [0.0], tol=1e-12)
    >>> info = run_info(res, wall_time=0.5)
    >>> info.converged, info.iterations, info.residual, info.wall_time
    (True, 1, 0.0, 0.5)
    """
    seconds = (time.perf_counter() - start if start is not None
               else math.nan if wall_time is None else wall_time)
    return RunInfo(converged=result.converged, iterations=result.iterations,
                   residual=result.residual, wall_time=seconds, message=result.message,
                   extra=dict(extra or {}))
