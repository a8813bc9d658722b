"""The FEM cooling states against the quasi-elastic limit (issue 10, part 3).

Along the continuation of :func:`kinetic_fem.solvers.fem.cooling.cooling_state`
(eps = 0.1 / 2^k, 0.07 hump widths, which gives zeta to ~1e-10), print (CPU seconds)

* ``zeta/eps - 1`` and ``(zeta/eps - 1)/eps``: the energy identity
  :math:`\\zeta = (1-\\alpha^2)\\langle|g|^3\\rangle/8` with two humps at
  :math:`c = \\pm m(1 - w y)`, :math:`w = \\varepsilon^{1/3}`, :math:`m^2(1 + w^2\\langle
  y^2\\rangle) = 1`, gives :math:`\\langle|g|^3\\rangle/4 = 1 + O(w^3)` (the
  :math:`w` and :math:`w^2` terms cancel, the latter through the unit temperature), so
  :math:`\\zeta/\\varepsilon = 1 + O(\\varepsilon)`; the fit of
  :math:`(\\zeta/\\varepsilon - 1)/\\varepsilon = C_0 + C_1 w + C_2 w^2` measures the
  constants and the rate;
* the hump moments on the psi variable :math:`y = (1 - c/\\langle|c|\\rangle)/w`
  (:func:`kinetic_fem.analysis.humps.psi_profile`): :math:`\\langle y\\rangle`,
  :math:`\\langle y^2\\rangle`, :math:`\\langle y^3\\rangle` against those of
  :math:`\\psi` (:func:`kinetic_fem.scaling.solve_psi`), and the largest difference of
  the rescaled hump from :math:`\\psi` on :math:`-3 \\le y \\le 6`, with the observed
  rate of each difference (theory: :math:`O(w) = O(\\varepsilon^{1/3})`).

    python benchmarks/quasi_elastic_cooling.py [--eps-min 1e-4]
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import math  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

import kinetic_fem as kf  # noqa: E402
from kinetic_fem.analysis.humps import psi_profile  # noqa: E402
from kinetic_fem.solvers.fem import cooling as fc  # noqa: E402


def hump_moments(state: fc.CoolingState, eps: float) -> tuple[dict[str, float], float]:
    """Moments of the right hump on the psi variable and max |psi_hcs - psi| on [-3, 6]."""
    xq, wq, _ = state.disc.points
    fq = state.disc.values(state.u)
    right = xq > 0
    prof = psi_profile(xq[right], fq[right], 2.0 * wq[right], eps)
    # the weights in y: dy = dc / (eps^(1/3) <|c|>), and psi dy = 2 f dc
    order = np.argsort((1.0 - xq[right] / prof.mean_abs) / eps ** (1 / 3))
    w = (2.0 * wq[right])[order] / (2.0 * eps ** (1 / 3) * prof.mean_abs)
    mom = {f"y{k}": float(np.sum(w * prof.y**k * prof.psi)) for k in (0, 1, 2, 3)}
    return mom, prof


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--eps-min", type=float, default=1e-4)
    args = parser.parse_args()
    psi = kf.scaling.solve_psi(estimate_errors=False)
    print(f"psi: <y^2> = {psi.y2:.10f}, <y^3> = {psi.y3:.10f}")
    prev, eps_prev = fc.hump_start(2, None), fc.HUMP_EPS
    rows = []
    for eps in fc.hump_chain(args.eps_min):
        t0 = time.process_time()
        st = fc.continued_state(prev, eps_prev, eps, resolution=fc.HUMP_STEP_RESOLUTION,
                                tol=1e-11)
        wall = time.process_time() - t0
        if not st.info.converged:
            print(f"eps = {eps:.3g}: not converged ({st.info.message}); stopping")
            break
        mom, prof = hump_moments(st, eps)
        core = (prof.y >= -3.0) & (prof.y <= 6.0)
        dpsi = float(np.max(np.abs(prof.psi[core] - psi(prof.y[core]))))
        rows.append((eps, st.zeta / eps - 1.0, mom, dpsi, wall, st.u.size))
        ident = st.energy_identity() / eps - 1.0
        print(f"eps {eps:9.3e} dofs {st.u.size:5d} {wall:6.1f} s  zeta/eps-1 "
              f"{st.zeta / eps - 1:.10e} (identity {ident:.10e})  /eps^(4/3) "
              f"{(st.zeta / eps - 1) / eps ** (4 / 3):.6f}  "
              f"<y> {mom['y1']:+.6f} <y2>-psi {mom['y2'] - psi.y2:+.6f} "
              f"<y3>-psi {mom['y3'] - psi.y3:+.6f} max|dpsi| {dpsi:.3e}", flush=True)
        prev, eps_prev = st, eps
    eps = np.array([r[0] for r in rows])
    ratio = np.array([r[1] for r in rows]) / eps
    w = eps ** (1 / 3)
    tail = eps <= 0.02
    if tail.sum() >= 4:
        a = np.stack([np.ones(tail.sum()), w[tail], w[tail] ** 2], axis=1)
        coef, *_ = np.linalg.lstsq(a, ratio[tail], rcond=None)
        fit = a @ coef
        print(f"\n(zeta/eps - 1)/eps = C0 + C1 eps^(1/3) + C2 eps^(2/3) on eps <= 0.02: "
              f"C0 = {coef[0]:.6f}, C1 = {coef[1]:.6f}, C2 = {coef[2]:.6f}, "
              f"max misfit {np.abs(fit - ratio[tail]).max():.1e}")
    for lo in (2e-3, 4e-4):
        sel = eps <= lo
        if sel.sum() >= 3:
            a = np.stack([w[sel], w[sel] ** 2], axis=1)
            coef, *_ = np.linalg.lstsq(a, ratio[sel], rcond=None)
            print(f"(zeta/eps - 1)/eps = C1 eps^(1/3) + C2 eps^(2/3) on eps <= {lo:g}: "
                  f"C1 = {coef[0]:.5f}, C2 = {coef[1]:.4f}, max misfit "
                  f"{np.abs(a @ coef - ratio[sel]).max():.1e}")
    dz = np.array([r[1] for r in rows])
    print("local exponents of zeta/eps - 1: " + " ".join(
        f"{math.log(dz[i] / dz[i + 1]) / math.log(eps[i] / eps[i + 1]):.3f}"
        for i in range(len(dz) - 1)))
    print("\nobserved rates (log ratio of successive differences / log ratio of eps):")
    for name, vals in (("<y2> - psi", [r[2]["y2"] - psi.y2 for r in rows]),
                       ("<y3> - psi", [r[2]["y3"] - psi.y3 for r in rows]),
                       ("<y>", [r[2]["y1"] for r in rows]),
                       ("max|psi_hcs - psi|", [r[3] for r in rows])):
        v = np.abs(np.array(vals))
        rates = [math.log(v[i] / v[i + 1]) / math.log(eps[i] / eps[i + 1])
                 for i in range(len(v) - 1) if v[i + 1] > 0]
        print(f"  {name:>20}: " + " ".join(f"{r:5.2f}" for r in rates))


if __name__ == "__main__":
    main()
