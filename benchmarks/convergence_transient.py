"""Convergence of the adaptive transient in its tolerance ``rtol``, and the Maxwell check.

Part ``hard-rods``: heated hard rods (alpha = 0.5, n = D = 1) from a Gaussian at T = 0.5,
a step of the noise strength D: 1 -> 2 at t = 1, output at t = 0.5, 1, 1.5, 2, 3; fixed
coarse mesh (spacing 0.5, cut-off 12), so the time error is isolated.  The reference is
the same run at a tight rtol.  Prints, per rtol, the maximum over the output times of the
relative error of T and the absolute error of a2, both divided by rtol, the steps taken
(rejected, Newton failures), Newton iterations and the CPU time (on a shared machine:
compare within one run).

Part ``quench``: the same table for the protocol of the DSMC transient tests (hard rods
alpha = 0.5 from a Gaussian at T = 1, D: 1 -> 0.3 at t = 1.5, alpha -> 0.8 at t = 2.5,
outputs every 0.25 to t = 4, spacing 0.5, default cut-off): a quench, after which the
global error is several rtol (the estimate misses part of the local error there).

Part ``maxwell``: the Maxwell model (kernel gamma = 0, alpha = 0.5) from a Gaussian at
T = 1 against its closed moment equations (:func:`kinetic_fem.solvers.maxwell.
evolve_moments`): maximum relative error of T and <v^4> over the output times, per
spacing and rtol, under white noise D = 1 and under a protocol with a step of D and of
the bath friction.

    python benchmarks/convergence_transient.py [--quick] [--part hard-rods|quench|maxwell]
"""

import argparse
import time

import numpy as np

import kinetic_fem as kf
from kinetic_fem.model.protocol import Protocol, steps
from kinetic_fem.solvers.maxwell import evolve_moments

TIMES = [0.0, 0.5, 1.0, 1.5, 2.0, 3.0]
MESH = {"spacing": 0.5, "cutoff": 12.0}


def run(rtol: float, part: str = "hard-rods"):
    start = time.process_time()
    if part == "quench":
        ev = kf.evolve_heated(0.5, times=np.linspace(0.0, 4.0, 17), initial_temperature=1.0,
                              protocol=Protocol(diffusion=steps([1.5], [1.0, 0.3]),
                                                restitution=[(2.5, 0.8)]),
                              rtol=rtol, spacing=0.5, max_steps=10**6)
    else:
        ev = kf.evolve_heated(0.5, times=TIMES, initial_temperature=0.5,
                              protocol=Protocol(diffusion=steps([1.0], [1.0, 2.0])), rtol=rtol,
                              max_steps=10**6, **MESH)
    return ev, time.process_time() - start


def hard_rods(quick: bool = False, part: str = "hard-rods") -> list[tuple]:
    rtols = [1e-2, 1e-3, 1e-4, 1e-5] if quick else [1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 1e-5,
                                                      1e-6]
    ref_tol = 1e-6 if quick else 1e-7
    ref, _ = run(ref_tol, part)
    rows = []
    print(f"reference rtol={ref_tol:g}: {ref.info.message}")
    print(f"{'rtol':>8} {'max dT/T':>10} {'/rtol':>6} {'max |da2|':>10} {'/rtol':>6} "
          f"{'steps':>6} {'rej':>4} {'fail':>4} {'Newton':>7} {'CPU s':>7}")
    for rtol in rtols:
        ev, cpu = run(rtol, part)
        e_t = float(np.max(np.abs(ev.temperature / ref.temperature - 1.0)))
        e_a = float(np.max(np.abs(ev.a2 - ref.a2)))
        x = ev.info.extra
        rows.append((rtol, e_t, e_a, x["accepted"], x["rejected"], x["newton_failures"],
                     x["newton_iterations"], cpu))
        print(f"{rtol:8.0e} {e_t:10.2e} {e_t / rtol:6.2f} {e_a:10.2e} {e_a / rtol:6.2f} "
              f"{x['accepted']:6d} {x['rejected']:4d} {x['newton_failures']:4d} "
              f"{x['newton_iterations']:7d} {cpu:7.1f}")
    return rows


def maxwell_errors(rtol: float, spacing: float, protocol: Protocol, t_end: float,
                   cutoff: float = 12.0) -> tuple[float, float, float, int]:
    """Max relative errors of T and <v^4> against the moment equations, CPU s, steps."""
    times = np.linspace(0.0, t_end, 5)
    start = time.process_time()
    ev = kf.evolve_heated(0.5, kernel=0.0, times=times, initial_temperature=1.0,
                          protocol=protocol, rtol=rtol, spacing=spacing, cutoff=cutoff,
                          max_steps=10**6)
    cpu = time.process_time() - start
    ex = evolve_moments(0.5, times, initial_temperature=1.0,
                        diffusion=lambda t: protocol.diffusion_at(t, 1.0),
                        friction=lambda t: protocol.friction_at(t, 0.0),
                        breakpoints=protocol.breakpoints(t_end))
    m4 = 3.0 * ev.temperature**2 * (1.0 + ev.a2)
    m4_ex = 3.0 * ex.temperature**2 * (1.0 + ex.a2)
    return (float(np.max(np.abs(ev.temperature / ex.temperature - 1.0))),
            float(np.max(np.abs(m4 / m4_ex - 1.0))), cpu, int(ev.info.extra["accepted"]))


def maxwell(quick: bool = False) -> list[tuple]:
    cases = [("white noise D = 1", Protocol(), 0.5)]
    if not quick:
        cases.append(("D 1 -> 0.5 at t = 0.5, friction 0 -> 0.5 at t = 1",
                      Protocol(diffusion=steps([0.5], [1.0, 0.5]),
                               friction=steps([1.0], [0.0, 0.5])), 2.0))
    grid = [(0.5, 1e-5), (0.25, 1e-5), (0.25, 1e-6)] if quick else [
        (0.5, 1e-5), (0.5, 1e-6), (0.25, 1e-5), (0.25, 1e-6), (0.25, 1e-7)]
    rows = []
    print(f"{'protocol':>52} {'spacing':>7} {'rtol':>6} {'dT/T':>9} {'d<v4>':>9} "
          f"{'steps':>6} {'CPU s':>7}")
    for name, protocol, t_end in cases:
        for spacing, rtol in grid:
            e_t, e_4, cpu, n = maxwell_errors(rtol, spacing, protocol, t_end)
            rows.append((name, spacing, rtol, e_t, e_4, n, cpu))
            print(f"{name:>52} {spacing:7.2f} {rtol:6.0e} {e_t:9.2e} {e_4:9.2e} {n:6d} "
                  f"{cpu:7.1f}", flush=True)
    return rows


def main(quick: bool = False, part: str = "all") -> dict:
    out = {}
    for name in ("hard-rods", "quench"):
        if part in ("all", name):
            out[name] = hard_rods(quick, name)
    if part in ("all", "maxwell"):
        out["maxwell"] = maxwell(quick)
    return out


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--part", default="all", choices=["all", "hard-rods", "quench", "maxwell"])
    args = parser.parse_args()
    main(quick=args.quick, part=args.part)
