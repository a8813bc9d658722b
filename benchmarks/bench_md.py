"""Speed and accuracy of the event-driven MD (particles.md); prints tables.

1. Collisions per CPU second (one core): free cooling (alpha = 0.9 regularised,
   0.99) at N = 5000 and 1e5 over the homogeneous stage, cost per collision against
   log2 N; heated alpha = 0.9, N = 5000 with the kicks included at the default and
   other kick intervals, the cost of one kick per rod, and the split of the time
   into kicks and collisions.
2. Kick-interval convergence of the heated steady state (T/T_Sonine and a2, N = 5000,
   several seeds per interval, fitted order of the dt_k dependence) as
   dt_k -> 0, and the error of the default interval.
3. Threshold independence: heated (alpha = 0.9, 0.6) and freely cooling (alpha = 0.9)
   over more than a decade of thresholds.
4. Invariants over the longest run: rods ordered, momentum and energy balance.
5. Heated a2 against alpha: MD (N = 5000) vs DSMC vs first-order Sonine (``--part a2``).
6. The model space MD covers (``--part model``): T and a2 of MD (n sigma = 0.5) and FEM
   (at the Enskog density n/(1 - n sigma)) for alpha = 0.3 ... 0.99 and two laws, under
   white noise and a Fokker-Planck bath; the difference in MD standard errors (MD
   departs from the Boltzmann equation where the rods correlate and cluster).

Run ``python benchmarks/bench_md.py [--quick] [--part speed|kicks|a2|threshold|invariants]``.
Before/after speed comparisons: ``benchmarks/archive/bench_md_before_after.py``.
The machine may be shared: part 1 reports CPU time of the process (the event loop is
single-threaded), which does not count time spent descheduled but still feels the
other jobs in the caches; whole-run timings are wall-clock.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from kinetic_fem.model import ConstantRestitution
from kinetic_fem.sonine import a2_first_order, steady_temperature
from particles import _md_kernels as K
from particles import md

N_FREE = 2.0  # density on the reduced ring at n = 1, n sigma = 0.5


def _engine(alpha: float, n: int, seed: int, threshold: float | None,
            kick_fraction: float | None) -> md.MDEngine:
    temp, kicks = 1.0, md.Kicks()
    if kick_fraction is not None:
        temp = steady_temperature(alpha, N_FREE)
        kick_dt = kick_fraction * md.mean_free_time(temp, 1.0, 0.5)
        kicks = md.Kicks(kick_dt, 1.0, math.sqrt(2.0 * kick_dt))
    rng = np.random.default_rng(seed)
    y, v = md.initial_state(n, density=1.0, sigma=0.5, temperature=temp, rng=rng)
    opts = md.EngineOptions(n - 0.5 * n, 0.5, ConstantRestitution(alpha), threshold or 0.0,
                            kicks, 1e-12, 100 * n)
    return md.MDEngine(y, v, opts, rng)


def _event_rate(alpha: float, n: int, cpp: float, threshold: float | None, repeats: int,
                kick_fraction: float | None = None,
                min_collisions: int = 200_000) -> tuple[int, float, float, int]:
    """CPU time of the event loop alone (kicks included, no sampling), best of ``repeats``.

    Each measurement runs ``cpp`` collisions per particle from the initial state, on
    as many independent realisations as needed for ``min_collisions`` in total.
    Returns collisions, CPU seconds, the final temperature of the last realisation,
    and the kicks.
    """
    per_run = int(cpp * n / 2)
    runs = max(1, -(-min_collisions // per_run))
    best = np.inf
    for _ in range(repeats):
        cpu, kicks = 0.0, 0
        for seed in range(runs):
            eng = _engine(alpha, n, seed + 1, threshold, kick_fraction)
            start = time.process_time()
            eng.advance(per_run)
            cpu += time.process_time() - start
            kicks += int(eng.istate[K.I_NKICK])
        best = min(best, cpu)
    return runs * per_run, best, eng.temperature(), kicks


def _kick_cost(alpha: float, n: int, kick_fraction: float, repeats: int = 200) -> float:
    """CPU seconds of one kick alone (normals + sweep + heap), on a steady-state configuration.

    The kick is repeated in place on the same configuration with amplitude 0 (the
    configuration and the screened pairs stay those of the real kick).
    """
    eng = _engine(alpha, n, 1, 0.01 * math.sqrt(steady_temperature(alpha, N_FREE)),
                  kick_fraction)
    eng.advance(10 * n)
    tk, dt = eng.fstate[K.F_T_KICK], eng.kick_dt
    best = np.inf
    for _ in range(5):
        start = time.process_time()
        for _ in range(repeats):
            K.fill_normals(eng.xi, eng.rng_state)
            eng.head[:eng.istate[K.I_NB]] = -1  # (the previous sweep's buckets: empty)
            K.kick_sweep(tk, tk + dt, 1.0, 0.0, eng.xi, eng.x, eng.v, eng.tl, eng.free_length,
                         eng.heap, eng.hkey, eng.where, eng.ptime, eng.head, eng.nxt, eng.prv,
                         eng.bkt, eng.fstate, eng.istate)
        best = min(best, (time.process_time() - start) / repeats)
    return best


def speed(quick: bool) -> None:
    md.simulate_cooling(0.9, 100, seed=0, collisions_per_particle=10.0)  # compile / load cache
    md.simulate_heated(0.9, 100, seed=0, collisions_per_particle=10.0)
    print("\nCPU time of this process (one core; the machine may be shared, which slows "
          "memory access but does not count time spent descheduled)")
    print("\n== free cooling event loop, homogeneous stage, best of 3 "
          "(>= 2e5 collisions per measurement) ==")
    print(f"{'alpha':>6} {'threshold':>9} {'N':>7} {'cpp':>5} {'collisions':>11} {'cpu s':>7} "
          f"{'coll/s':>9} {'ns/coll':>8} {'ns/coll/log2N':>14} {'T_end':>6}")
    sizes = (5000, 20000) if quick else (5000, 100_000)
    for alpha, thr, cpp in ((0.9, 1e-4, 4.0), (0.99, None, 40.0)):
        for n in sizes:
            coll, cpu, t_end, _ = _event_rate(alpha, n, cpp / (4 if quick else 1), thr, 3)
            ns = 1e9 * cpu / coll
            print(f"{alpha:6.2f} {thr or 0:9.0e} {n:7d} {cpp:5.0f} {coll:11d} {cpu:7.3f} "
                  f"{coll / cpu:9.3g} {ns:8.1f} {ns / math.log2(n):14.2f} {t_end:6.3f}")
    n, cpp = 5000, (20.0 if quick else 100.0)
    thr = 0.01 * math.sqrt(steady_temperature(0.9, N_FREE))
    print(f"\n== heated alpha = 0.9, N = {n}, event loop with kicks (no sampling), {cpp:g} cpp "
          f"from the start, best of 3; default kick interval {md.KICK_FRACTION:g} tau ==")
    print(f"{'dt_k/tau':>8} {'kicks':>7} {'coll/kick':>9} {'cpu s':>7} {'coll/s':>9} "
          f"{'ns/coll':>8} {'us/interval':>11} {'kick alone: ns/rod':>18}")
    fracs = (0.05, 0.1, 0.25, 0.5, 1.0)
    rows = []
    for frac in fracs:
        coll, cpu, _, kicks = _event_rate(0.9, n, cpp, thr, 3, kick_fraction=frac)
        kick = _kick_cost(0.9, n, frac)
        rows.append((coll / kicks, 1e6 * cpu / kicks))
        mark = " (default)" if frac == md.KICK_FRACTION else ""
        print(f"{frac:8.2f} {kicks:7d} {coll / kicks:9.1f} {cpu:7.3f} {coll / cpu:9.3g} "
              f"{1e9 * cpu / coll:8.1f} {1e6 * cpu / kicks:11.1f} {1e9 * kick / n:18.2f}{mark}")
    c, t = np.array(rows).T
    slope, icpt = np.polyfit(1.0 / c, t / c, 1)  # time per collision against 1/(coll/kick)
    print(f"fit: time per collision = {1e3 * icpt:.0f} ns + (one kick in the run: "
          f"{slope:.1f} us = {1e3 * slope / n:.2f} ns per rod) / (collisions per kick);")
    print(f"a kick interval holds (dt_k/tau) N/2 collisions, so coll/s = 1 / ({1e3 * icpt:.0f} ns "
          f"+ {1e3 * slope / n:.2f} ns x 2 / (dt_k/tau)), at most {1e9 / (1e3 * icpt):.3g}/s")
    print(f"\n== heated alpha = 0.9, N = {n}, whole run (kicks, sampling every tau) ==")
    print(f"{'dt_k/tau':>8} {'kicks':>7} {'collisions':>11} {'s':>7} {'coll/s':>9} "
          f"{'coll/kick':>9}")
    for frac in fracs:
        tau = md.mean_free_time(steady_temperature(0.9, N_FREE), 1.0, 0.5)
        run = min((md.simulate_heated(0.9, n, seed=2, kick_interval=frac * tau,
                                      collisions_per_particle=cpp, n_records=5, box_counts=[2])
                   for _ in range(2)), key=lambda r: r.info.wall_time)
        print(f"{frac:8.2f} {run.n_kicks:7d} {run.n_collisions:11d} {run.info.wall_time:7.3f} "
              f"{run.n_collisions / run.info.wall_time:9.3g} "
              f"{run.n_collisions / max(run.n_kicks, 1):9.1f}")


KICK_FRACS = (0.025, 0.05, 0.1, 0.2, 0.4)


def _power_fit(f: np.ndarray, y: np.ndarray, err: np.ndarray) -> tuple:
    """Weighted fit ``y = y0 + c f^p``: (y0, c, p, error of p) by a scan over p.

    For each p the fit is linear in (y0, c); p minimises chi^2 and its error is the
    half width of chi^2 <= min + 1.  p is poorly determined when the bias is not
    resolved (then |c f^p| stays within the error bars for every p).
    """
    w = 1.0 / err**2
    ps = np.linspace(0.25, 3.0, 111)
    chi, coef = [], []
    for p in ps:
        a = np.stack([np.ones_like(f), f**p], axis=1)
        sol = np.linalg.lstsq(a * np.sqrt(w)[:, None], y * np.sqrt(w), rcond=None)[0]
        chi.append(float(np.sum(w * (y - a @ sol) ** 2)))
        coef.append(sol)
    chi = np.array(chi)
    k = int(np.argmin(chi))
    inside = ps[chi <= chi[k] + 1.0]
    return coef[k][0], coef[k][1], ps[k], 0.5 * (inside.max() - inside.min()), chi[k]


def _linear_fit(f: np.ndarray, y: np.ndarray, err: np.ndarray) -> tuple:
    """Weighted ``y = y0 + c f``: y0, c, error of c, chi^2."""
    w = 1.0 / err**2
    a = np.stack([np.ones_like(f), f], axis=1)
    cov = np.linalg.inv(a.T @ (a * w[:, None]))
    sol = cov @ (a.T @ (w * y))
    return sol[0], sol[1], math.sqrt(cov[1, 1]), float(np.sum(w * (y - a @ sol) ** 2))


def kicks(quick: bool, alphas: tuple = (0.9, 0.99, 0.6, 0.3)) -> None:
    """Kick-interval convergence: T/T_Sonine and a2 against dt_k/tau.

    alpha = 0.9 and 0.99 (the study of issue 6), and 0.6, 0.3, where clusters collapse
    between kicks and the heated threshold (0.01 thermal speeds) makes a large share of
    the collisions elastic, so that the kick interval and the threshold interact.

    Independent realisations (seeds) per interval; errors are the standard errors of
    the mean over the seeds (the spread of single runs gives the statistical error of
    one run of that length).  The bias of an interval is c (dt_k/tau)^p from a fit
    ``y0 + c (dt_k/tau)^p``; with p poorly determined, the linear fit (p = 1) is also
    printed.
    """
    n, cpp, warm = (1000, 600.0, 100.0) if quick else (5000, 2000.0, 300.0)
    seeds = ({0.9: 4, 0.99: 4, 0.6: 4, 0.3: 4} if quick
             else {0.9: 24, 0.99: 48, 0.6: 12, 0.3: 12})
    for alpha in alphas:
        t_ref = steady_temperature(alpha, N_FREE)
        tau = md.mean_free_time(t_ref, 1.0, 0.5)
        m = seeds[alpha]
        print(f"\n== kick-interval convergence, heated alpha = {alpha}, N = {n}, n sigma = 0.5, "
              f"{cpp:g} cpp (warm-up {warm:g}) x {m} seeds; T_ref = Sonine {t_ref:.4f}, "
              f"Sonine a2 = {a2_first_order(alpha):.4f} ==")
        print(f"{'dt_k/tau':>8} {'T/T_ref':>8} {'+-':>7} {'sd/run':>7} {'a2':>8} {'+-':>7} "
              f"{'sd/run':>7} {'elastic':>7} {'t/tau':>7} {'coll/s':>8} {'s':>6}")
        rows = []
        for frac in KICK_FRACS:
            temps, a2s, wall, coll, nel, span = [], [], 0.0, 0, 0, 0.0
            for s in range(m):
                r = md.simulate_heated(alpha, n, seed=1000 + s, kick_interval=frac * tau,
                                       collisions_per_particle=cpp, warmup=warm,
                                       n_records=10, box_counts=[2])
                temps.append(r.temperature / t_ref)
                a2s.append(r.a2)
                wall += r.info.wall_time
                coll += r.n_collisions
                nel += r.n_elastic
                t = r.series["t"]
                span += (t[-1] - np.interp(warm, r.series["collisions_per_particle"], t)) / tau
            temps, a2s = np.array(temps), np.array(a2s)
            row = (frac, temps.mean(), temps.std(ddof=1) / math.sqrt(m), temps.std(ddof=1),
                   a2s.mean(), a2s.std(ddof=1) / math.sqrt(m), a2s.std(ddof=1))
            rows.append(row)
            mark = " (default)" if frac == md.KICK_FRACTION else ""
            print(f"{frac:8.3f} {row[1]:8.4f} {row[2]:7.4f} {row[3]:7.4f} {row[4]:8.4f} "
                  f"{row[5]:7.4f} {row[6]:7.4f} {nel / coll:7.3f} {span / m:7.0f} "
                  f"{coll / wall:8.3g} {wall:6.1f}{mark}", flush=True)
        r = np.array(rows)
        f = r[:, 0]
        print("fits y = y0 + c (dt_k/tau)^p (chi^2 for 3 degrees of freedom) and "
              "y = y0 + c dt_k/tau:")
        for name, col in (("T/T_ref", 1), ("a2", 4)):
            y, err, sd = r[:, col], r[:, col + 1], r[:, col + 2]
            y0, c, p, dp, chi = _power_fit(f, y, err)
            l0, lc, lce, lchi = _linear_fit(f, y, err)
            print(f"  {name:7s}: power fit y0 = {y0:.4f}, c = {c:+.4f}, p = {p:.2f} +- {dp:.2f} "
                  f"(chi^2 {chi:.1f}); linear y0 = {l0:.4f}, slope = {lc:+.4f} +- {lce:.4f} "
                  f"({abs(lc) / lce:.1f} sigma, chi^2 {lchi:.1f})")
            sd_run = float(np.mean(sd))
            print(f"           bias against dt_k -> 0 (linear fit) and in units of the sd of "
                  f"one run ({sd_run:.4f}):")
            print("           " + ", ".join(
                f"{fr:g}: {lc * fr:+.4f} ({abs(lc * fr) / sd_run:.2f})" for fr in f))


A2_ALPHAS = (0.3, 0.6, 0.9, 0.95, 0.99, 0.999)


def a2_table(quick: bool) -> None:
    """Heated a2: MD (N = 5000, n sigma = 0.5) against DSMC and first-order Sonine.

    MD: independent seeds, each ``max(2000, 10/(1 - alpha^2))`` collisions per particle
    after a warm-up of ``max(300, 3/(1 - alpha^2))``, until ``budget`` seconds are spent
    (at least 3 seeds); the error is the standard error over the seeds.  DSMC
    (:func:`particles.dsmc.simulate_heated`, N = 25000, its default time step 0.05 mean
    free times): its own batch error bars.
    """
    from particles import dsmc

    n, n_dsmc = (1000, 5000) if quick else (5000, 25000)
    budget, max_seeds = (10.0, 4) if quick else (100.0, 16)
    print(f"\n== heated a2: MD (N = {n}, n sigma = 0.5) vs DSMC (N = {n_dsmc}) vs first-order "
          f"Sonine 16(1-2a^2)/(129+30a^2) ==")
    print(f"{'alpha':>6} {'MD a2':>8} {'+-':>7} {'seeds':>5} {'cpp':>6} {'MD s':>6} "
          f"{'DSMC a2':>8} {'+-':>7} {'DSMC s':>6} {'Sonine':>8} {'MD-DSMC':>8} {'/err':>6}")
    for alpha in A2_ALPHAS:
        relax = 1.0 / (1.0 - alpha**2)
        cpp, warm = max(2000.0, 10.0 * relax), max(300.0, 3.0 * relax)
        if quick:
            cpp, warm = cpp / 4, warm / 2
        a2s, wall = [], 0.0
        while len(a2s) < max_seeds and (len(a2s) < 3 or wall < budget):
            r = md.simulate_heated(alpha, n, seed=2000 + len(a2s), collisions_per_particle=cpp,
                                   warmup=warm, n_records=10, box_counts=[2])
            a2s.append(r.a2)
            wall += r.info.wall_time
        a2s = np.array(a2s)
        a2m, a2e = a2s.mean(), a2s.std(ddof=1) / math.sqrt(a2s.size)
        start = time.perf_counter()
        ds = dsmc.simulate_heated(alpha, n_dsmc, seed=3000,
                                  collisions_per_particle=max(1000.0, 20.0 * relax) / (
                                      4 if quick else 1))
        dwall = time.perf_counter() - start
        diff = a2m - ds.a2
        print(f"{alpha:6.3f} {a2m:8.4f} {a2e:7.4f} {a2s.size:5d} {cpp:6.0f} {wall:6.1f} "
              f"{ds.a2:8.4f} {ds.a2_error:7.4f} {dwall:6.1f} {a2_first_order(alpha):8.4f} "
              f"{diff:+8.4f} {abs(diff) / math.hypot(a2e, ds.a2_error):6.1f}", flush=True)


def threshold(quick: bool) -> None:
    n, cpp = (1000, 300.0) if quick else (5000, 400.0)
    for alpha in (0.9, 0.6):
        vth = math.sqrt(steady_temperature(alpha, N_FREE))
        print(f"\n== heated threshold independence, alpha = {alpha}, N = {n}, {cpp:g} cpp ==")
        print(f"{'thr/v_th':>8} {'T/T_sonine':>11} {'a2':>8} {'+-':>7} {'elastic':>8} "
              f"{'t_end':>8}")
        for rel in (1e-3, 3e-3, 1e-2, 3e-2, 1e-1):
            run = md.simulate_heated(alpha, n, seed=5, threshold=rel * vth,
                                     collisions_per_particle=cpp)
            print(f"{rel:8.0e} {run.temperature / vth**2:11.4f} {run.a2:8.4f} "
                  f"{run.a2_error:7.4f} {run.n_elastic / run.n_collisions:8.4f} "
                  f"{run.series['t'][-1]:8.2f}")
    n, cpp = (2000, 300.0) if quick else (10000, 1000.0)
    print(f"\n== free cooling threshold independence, alpha = 0.9, N = {n}: T at fixed times ==")
    times = np.geomspace(1.0, 60.0 if quick else 150.0, 6)
    print(f"{'threshold':>9} " + " ".join(f"{'T(' + format(t, '.3g') + ')':>10}" for t in times)
          + f" {'a2(late)':>9} {'elastic':>8}")
    for thr in (1e-5, 1e-4, 1e-3):
        run = md.simulate_cooling(0.9, n, seed=8, threshold=thr, collisions_per_particle=cpp,
                                  n_records=400)
        s = run.series
        temps = np.interp(times, s["t"], s["temperature"], right=np.nan)
        print(f"{thr:9.0e} " + " ".join(f"{x:10.4g}" for x in temps)
              + f" {run.a2:9.4f} {run.n_elastic / run.n_collisions:8.4f}")


def _gap_check(run: md.MDRun, length: float) -> tuple[float, float]:
    """Smallest gap between consecutive rod left ends over the snapshots (>= sigma if no
    overlap) and the largest |sum of gaps - L| (L if the rods keep their ring order:
    a rod that passed its neighbour would make one gap negative modulo L, i.e. ~ L)."""
    worst, order = np.inf, 0.0
    for s in run.snapshots:
        gaps = np.mod(np.diff(np.append(s.x, s.x[0])), length)
        worst = min(worst, float(gaps.min()))
        order = max(order, abs(float(gaps.sum()) - length))
    return worst, order


def invariants(quick: bool) -> None:
    n, cpp = (2000, 2000.0) if quick else (5000, 20000.0)
    start = time.perf_counter()
    run = md.simulate_cooling(0.9, n, seed=3, threshold=1e-4, collisions_per_particle=cpp,
                              snapshots_at=np.linspace(cpp / 20, cpp, 20))
    worst, order = _gap_check(run, float(n))
    p = run.series["momentum"]
    e = run.series["energy"]
    print(f"\n== invariants, cooling alpha = 0.9 threshold 1e-4, N = {n}, "
          f"{run.n_collisions:.3e} collisions ({time.perf_counter() - start:.1f} s), "
          f"E from {e[0]:.4g} to {e[-1]:.4g} ==")
    print(f"smallest gap between rod left ends over 20 snapshots: {worst:.15f} (sigma = 0.5; "
          f"positions up to L = {n}, spacing of doubles {np.spacing(float(n)):.1e}); "
          f"max |sum of gaps - L| = {order:.2e}")
    print(f"max |P(t) - P(0)| over {p.size} records: {np.max(np.abs(p - p[0])):.3e} "
          f"(sqrt(N sum v_i(0)^2) = {math.sqrt(2 * e[0] * n):.3g} sets the round-off scale)")
    print(f"energy balance: max|E - E0 + dissipated| / E0 = {run.energy_balance_error:.3e}")
    start = time.perf_counter()
    heated = md.simulate_heated(0.9, n, seed=3, collisions_per_particle=cpp,
                                snapshots_at=np.linspace(cpp / 20, cpp, 20))
    worst, order = _gap_check(heated, float(n))
    s = heated.series
    print(f"heated alpha = 0.9 (default kicks and threshold), N = {n}, "
          f"{heated.n_collisions:.3e} collisions, {heated.n_kicks} kicks "
          f"({time.perf_counter() - start:.1f} s): injected {s['energy_injected'][-1]:.4g}, "
          f"dissipated {s['energy_dissipated'][-1]:.4g}, E - E0 = "
          f"{s['energy'][-1] - s['energy'][0]:+.4g} (of which the centre of mass, whose momentum "
          f"the independent kicks make a random walk: P^2/2N = {s['momentum'][-1]**2 / (2 * n):.4g}"
          f" against D t = {s['t'][-1]:.4g} on average: P / sqrt(2 N D t) = "
          f"{s['momentum'][-1] / math.sqrt(2 * n * s['t'][-1]):+.2f}, a standard normal)")
    print(f"  max |E - E0 - (injected - dissipated)| / max E over {s['t'].size} records = "
          f"{heated.energy_balance_error:.3e}; relative to the injected energy "
          f"{heated.energy_balance_error * np.max(s['energy']) / s['energy_injected'][-1]:.3e}")
    print(f"  smallest gap over 20 snapshots: {worst:.15f}; max |sum of gaps - L| = "
          f"{order:.2e}")


def model_table(quick: bool) -> None:
    """MD against FEM over alpha, two restitution laws and both thermostats (hard rods)."""
    import kinetic_fem as kf
    from kinetic_fem.model import ThresholdRestitution, ViscoelasticRestitution

    n, seeds = (1000, 3) if quick else (2000, 4)
    laws = (0.3, 0.6, 0.9, 0.99, ViscoelasticRestitution(0.1),
            ThresholdRestitution(0.6, threshold=1.0))
    print(f"\n== MD (N = {n}, n sigma = 0.5, {seeds} seeds) vs FEM (density 2): T and a2, "
          f"D = 1; bath xi = 1 (T_b = 1) ==")
    print(f"{'law':46s} {'xi':>3} {'T FEM':>8} {'T MD':>8} {'+-':>6} {'dT/err':>7} "
          f"{'a2 FEM':>8} {'a2 MD':>8} {'+-':>6} {'da2/err':>7} {'elastic':>7} {'s':>5}")
    for law in laws:
        alpha = law if isinstance(law, float) else law.min_alpha
        cpp = max(400.0, 8.0 / (1.0 - alpha**2)) / (4 if quick else 1)
        for xi in (0.0, 1.0):
            fem = kf.solve_heated(law, density=N_FREE, diffusion=1.0, friction=xi)
            start = time.perf_counter()
            runs = [md.simulate_heated(law, n, friction=xi, seed=500 + s, n_records=10,
                                       collisions_per_particle=cpp, box_counts=[2])
                    for s in range(seeds)]
            wall = time.perf_counter() - start
            t = np.array([r.temperature for r in runs])
            a2 = np.array([r.a2 for r in runs])
            te, ae = t.std(ddof=1) / math.sqrt(seeds), a2.std(ddof=1) / math.sqrt(seeds)
            el = sum(r.n_elastic for r in runs) / sum(r.n_collisions for r in runs)
            print(f"{law!r:46s} {xi:3g} {fem.temperature:8.4f} {t.mean():8.4f} {te:6.4f} "
                  f"{(t.mean() - fem.temperature) / te:7.1f} {fem.a2:8.4f} {a2.mean():8.4f} "
                  f"{ae:6.4f} {(a2.mean() - fem.a2) / ae:7.1f} {el:7.3f} {wall:5.1f}",
                  flush=True)


PARTS = {"speed": speed, "kicks": kicks, "a2": a2_table, "threshold": threshold,
         "invariants": invariants, "model": model_table}

if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--part", choices=sorted(PARTS), action="append")
    args = parser.parse_args()
    for name in args.part or list(PARTS):
        PARTS[name](args.quick)
