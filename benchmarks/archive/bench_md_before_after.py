"""Before/after speed of the event-driven MD (particles.md) against another version.

``DIR`` holds the other (older) ``particles`` package, e.g. made by
``mkdir DIR && git archive <rev> particles | tar -x -C DIR``.

1. ``--part compare``: whole calls with default options (the MD rows of issue 13, and a
   bath and a viscoelastic run, new in the model layer), each timed in a fresh process
   with this tree's ``particles`` and with ``DIR``'s, alternately, best CPU time of
   three, so both feel the same load.
2. ``--part paired``: the event loop alone, old and new engines imported side by side
   (``DIR/particles`` copied as ``particles_before``) on the same initial state,
   alternating in one process; the median of the paired ratios, and whether the final
   velocities are bit-identical.  Short, many pairs: at N = 1e5 the memory-bound loop
   feels the other jobs on a shared machine (single pairs of 0.5e6 collisions ranged
   over 0.55-1.27 under a load of 10), and only fine interleaving cancels that.

Run ``python benchmarks/bench_md_before_after.py --against DIR [--part compare|paired]
[--quick]``.  CPU time of the process: on a shared machine it does not count time
spent descheduled but still feels the other jobs in the caches; ratios within one run
are what count.
"""

from __future__ import annotations

import argparse
import math
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from kinetic_fem.model import ConstantRestitution
from particles import md

WHOLE_CALLS = (
    ("cooling 0.9 N=5000 1000 cpp thr 1e-6",
     "simulate_cooling(0.9, 5000, collisions_per_particle=1000.0, threshold=1e-6, seed=1)"),
    ("heated 0.9 N=5000 2000 cpp",
     "simulate_heated(0.9, 5000, collisions_per_particle=2000.0, seed=1)"),
    ("cooling 0.99 N=1e5 200 cpp",
     "simulate_cooling(0.99, 100000, collisions_per_particle=200.0, seed=1)"),
)
NEW_CALLS = (  # the model layer only: no "before"
    ("heated 0.9 N=5000 2000 cpp, bath xi=1",
     "simulate_heated(0.9, 5000, collisions_per_particle=2000.0, seed=1, friction=1.0)"),
    ("heated visco 0.1 N=5000 2000 cpp",
     "simulate_heated(ViscoelasticRestitution(0.1), 5000, collisions_per_particle=2000.0, "
     "seed=1)"),
)
_TIMER = ("import time, sys; from particles import md; "
          "from particles.md import simulate_cooling, simulate_heated; {extra}"
          "{call}; t = time.process_time(); w = time.perf_counter(); r = {call}; "
          "print(r.n_collisions, time.process_time() - t, time.perf_counter() - w)")


def _timed(call: str, package_dir: Path | None, quick: bool) -> tuple[int, float, float]:
    """Collisions, CPU and wall seconds of one whole call in a fresh process.

    The call runs twice; the second is timed (the first loads the numba cache).  The
    process starts in a temporary directory so that ``PYTHONPATH`` decides which
    ``particles`` is imported.
    """
    if quick:
        call = call.replace("collisions_per_particle=", "collisions_per_particle=0.25*")
    extra = ("" if package_dir is not None else
             "from kinetic_fem.model import ViscoelasticRestitution; ")
    env = dict(os.environ)
    if package_dir is not None:
        env["PYTHONPATH"] = str(package_dir)
    else:
        env["PYTHONPATH"] = str(Path(__file__).resolve().parents[2])
    out = subprocess.run([sys.executable, "-c", _TIMER.format(call=call, extra=extra)],
                         env=env, cwd="/", capture_output=True, text=True, check=True)
    coll, cpu, wall = out.stdout.split()[-3:]
    return int(coll), float(cpu), float(wall)


def compare(quick: bool, against: Path | None, repeats: int = 3) -> None:
    """Whole calls before (``against``) and after (this tree), alternately, best of ``repeats``."""
    print(f"\n== whole calls with default options, fresh process each, CPU time, best of "
          f"{repeats} alternating before/after; before = {against} ==")
    print(f"{'call':40s} {'collisions':>11} {'before coll/s':>14} {'after coll/s':>13} "
          f"{'after/before':>12}")
    for name, call in WHOLE_CALLS:
        best = {"before": math.inf, "after": math.inf}
        coll = 0
        for _ in range(repeats):
            for key, where in (("before", against), ("after", None)):
                coll, cpu, _ = _timed(call, where, quick)
                best[key] = min(best[key], cpu)
        b, a = coll / best["before"], coll / best["after"]
        print(f"{name:40s} {coll:11d} {b:14.3g} {a:13.3g} {a / b:12.3f}", flush=True)
    for name, call in NEW_CALLS:
        cpu = min(_timed(call, None, quick)[1] for _ in range(repeats))
        coll = _timed(call, None, quick)[0]
        print(f"{name:40s} {coll:11d} {'-':>14} {coll / cpu:13.3g}", flush=True)


PAIRED_CASES = (  # name, alpha, N, threshold, kick interval, collisions per particle
    ("cooling 0.99 N=1e5", 0.99, 100_000, 0.0, math.inf, 4.0),
    ("cooling 0.9 thr 1e-4 N=5000", 0.9, 5000, 1e-4, math.inf, 100.0),
    ("kicked 0.9 dt_k=0.03 N=5000", 0.9, 5000, 0.01, 0.03, 100.0),
)


def paired(against: Path | None, repeats: int = 15) -> None:
    """Event loop of the old engine (``against``) and this one, alternating in one process."""
    import shutil
    import tempfile

    tmp = Path(tempfile.mkdtemp())
    shutil.copytree(against / "particles", tmp / "particles_before",
                    ignore=shutil.ignore_patterns("__pycache__"))
    sys.path.insert(0, str(tmp))
    from particles_before._md_engine import _Engine as Before  # relative imports only

    def make(new: bool, alpha, n, thr, kick_dt):
        rng = np.random.default_rng(1)
        y, v = md.initial_state(n, density=1.0, sigma=0.5, temperature=1.0, rng=rng)
        amp = math.sqrt(2.0 * kick_dt) if math.isfinite(kick_dt) else 0.0
        if not new:
            return Before(y, v, free_length=0.5 * n, sigma=0.5, alpha=alpha, threshold=thr,
                          kick_dt=kick_dt, kick_amp=amp, rng=rng, collapse_tol=1e-12,
                          max_stall=100 * n)
        kicks = md.Kicks(kick_dt, 1.0, amp) if math.isfinite(kick_dt) else md.Kicks()
        return md.MDEngine(y, v, md.EngineOptions(0.5 * n, 0.5, ConstantRestitution(alpha),
                                                  thr, kicks, 1e-12, 100 * n), rng)

    print(f"\n== event loop alone, before ({against}) and after alternating in one process, "
          f"CPU time, {repeats} pairs (first pair also compiles) ==")
    print(f"{'case':28s} {'before coll/s':>13} {'after coll/s':>12} {'paired ratio':>12} "
          f"{'(min, max)':>14} {'same v':>6}")
    for name, alpha, n, thr, kick_dt, cpp in PAIRED_CASES:
        target = int(cpp * n / 2)
        rates: dict[bool, list[float]] = {False: [], True: []}
        final = {}
        for r in range(repeats + 1):
            for new in ((False, True) if r % 2 else (True, False)):
                eng = make(new, alpha, n, thr, kick_dt)
                start = time.process_time()
                eng.advance(target)
                if r:
                    rates[new].append(target / (time.process_time() - start))
                final[new] = eng.v.copy()
        b, a = np.array(rates[False]), np.array(rates[True])
        ratio = a / b
        same = np.array_equal(final[False], final[True])
        print(f"{name:28s} {np.median(b):13.3g} {np.median(a):12.3g} {np.median(ratio):12.3f} "
              f"({ratio.min():.3f}, {ratio.max():.3f}) {same!s:>6}", flush=True)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--against", type=Path, required=True,
                        help="directory holding the 'before' particles package")
    parser.add_argument("--part", choices=["compare", "paired"], action="append")
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args()
    for name in args.part or ["compare", "paired"]:
        if name == "compare":
            compare(args.quick, args.against)
        else:
            paired(args.against)
