"""Planned vs Newton-controlled step of the continuation in alpha (issue 26).

The hard-kernel chain (``fem_cooling_alpha.alpha_chain``) runs on the target's mesh, so
every path ends at the same discrete state: only Newton's work differs.  Planned: the
chain of ratio 1.6 in eps; controlled: ``StepRule(target_iterations=k)`` from a first
ratio 1.6.  CPU seconds (process time) and the summed Newton iterations.

    PYTHONPATH=. python benchmarks/archive/continuation_step.py
"""
import math, os, time
for v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[v] = "1"
from kinetic_fem.model import CoolingProblem
from kinetic_fem.solvers.fem_regimes import CoolingOptions, Run, GenericNewton
from kinetic_fem.solvers import fem_cooling_alpha as fa
from kinetic_fem.solvers.continuation import StepRule, continuation, geometric_path
from kinetic_fem.solvers.fem import FEMDiscretisation
from kinetic_fem.solvers.fem_cooling_newton import newton_cooling

for gamma, alpha, spacing in ((2.0, 0.9, 0.2), (1.5, 0.97, 0.1)):
    problem = CoolingProblem.from_parameters(alpha, kernel=gamma)
    opts = CoolingOptions(spacing=spacing)
    mesh = GenericNewton.mesh(problem, opts)
    run = Run()
    base = run.solve(CoolingProblem.from_parameters(0.5, kernel=gamma),
                     CoolingOptions(order=mesh.order, vertices=mesh.disc.vertices, tol=1e-7))
    disc, eps = mesh.disc, 1.0 - alpha
    its = []

    def solve(prev, eps_prev, step):
        final = step == eps
        d = disc if final else FEMDiscretisation(1.0 - step, disc.vertices, disc.order,
                                                 disc.intorder, gamma=disc.gamma)
        zeta0 = prev.zeta * (1.0 - (1.0 - step) ** 2) / (1.0 - (1.0 - eps_prev) ** 2)
        st = newton_cooling(d, prev.u, zeta0, tol=1e-11 if final else fa.ALPHA_CHAIN_TOL,
                            max_iter=40, pseudo_time=math.inf)
        its.append(st.info.iterations)
        return st

    for label, rule, path in (
            ("planned ratio 1.6", StepRule(min_ratio=fa.MIN_RATIO),
             geometric_path(0.5, eps, fa.ALPHA_CHAIN_RATIO)),
            ("Newton-controlled, 4 its", StepRule(min_ratio=fa.MIN_RATIO, target_iterations=4,
                                                  first_step=1.6), [eps]),
            ("Newton-controlled, 6 its", StepRule(min_ratio=fa.MIN_RATIO, target_iterations=6,
                                                  first_step=1.6), [eps])):
        its.clear()
        t0 = time.process_time()
        walk = continuation(base, 0.5, path, solve, rule=rule)
        cpu = time.process_time() - t0
        print(f"gamma {gamma} alpha {alpha}: {label:26s} converged {walk.converged} steps "
              f"{walk.steps} retries {walk.retries} Newton its {sum(its)} CPU {cpu:.2f} s "
              f"zeta {walk.state.zeta:.15g}", flush=True)
