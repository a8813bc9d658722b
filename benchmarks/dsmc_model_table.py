"""DSMC table of the heated steady state over the model space: T and a2 with error bars.

Run: ``python benchmarks/dsmc_model_table.py OUT.csv [--quick] [--workers K]``.

Rows: kernels :math:`|g|^\\gamma` with gamma in {0, 0.5, 1, 2}, both thermostats
(white noise ``D = 1``; Fokker-Planck bath ``xi = 1, D = 1``), alpha in
{0.3, 0.6, 0.9, 0.99}, and two velocity-dependent restitution laws (viscoelastic
``delta = 0.2`` and threshold ``alpha = 0.6`` below ``|g| = 1`` elastic) for hard
rods under both thermostats; density 1.  Each row is one run of
:func:`particles.dsmc.simulate_heated` with ``N = 20000`` (``--quick``: 2000),
automatic relaxation detection, and ``collisions_per_particle = max(2000, 20 W)`` of
averaging (``--quick``: ``max(100, 20 W)`` with ``N = 2000``) in 20 batches, ``W =
12/((2+gamma)(1+gamma)(1-alpha^2))`` the relaxation window of the white-noise gas
(three relaxation times of T, in collisions per particle; 2/(1-alpha^2) for hard
rods), so that each batch is longer than the correlation time and the batch errors are
honest; error bars are the batch standard errors (about 1e-3 in a2).  For the Maxwell
kernel the exact steady state is added (``T = 4D/(n(1-alpha^2) + 4 xi)``, ``a2`` from the closed
fourth-moment equation, see ``tests/particles/test_dsmc_models.py``) with the
deviation in standard errors.  The CSV is what the lead merges with the FEM and
Sonine tables; its columns are those of :data:`COLUMNS`.  CPU seconds per row are
recorded (``time.process_time`` of the worker).
"""

from __future__ import annotations

import argparse
import csv
import math
import time
from concurrent.futures import ProcessPoolExecutor
from typing import Any

import numpy as np

from kinetic_fem.model import ThresholdRestitution, ViscoelasticRestitution
from particles import dsmc

GAMMAS = (0.0, 0.5, 1.0, 2.0)
ALPHAS = (0.3, 0.6, 0.9, 0.99)
THERMOSTATS = {"white noise": dict(diffusion=1.0, friction=0.0),
               "bath": dict(diffusion=1.0, friction=1.0)}
LAWS = (ViscoelasticRestitution(0.2), ThresholdRestitution(0.6, 1.0))
COLUMNS = ("method", "gamma", "thermostat", "diffusion", "friction", "restitution", "alpha",
           "n_particles", "collisions_per_particle", "T", "T_err", "a2", "a2_err",
           "T_exact", "a2_exact", "z_T", "z_a2", "converged", "relaxed_at", "n_collisions",
           "dt", "cpu_s")


def maxwell_exact(alpha: float, diffusion: float, friction: float) -> tuple[float, float]:
    """Exact steady (T, a2) of the heated inelastic Maxwell gas at density 1."""
    p = 0.5 * (1.0 + alpha)
    q = 1.0 - p
    t = 4.0 * diffusion / ((1.0 - alpha**2) + 4.0 * friction)
    m4 = (6 * p**2 * q**2 * t**2 + 12 * diffusion * t) / ((1 - p**4 - q**4) + 4 * friction)
    return t, m4 / (3 * t**2) - 1.0


def rows(quick: bool) -> list[dict[str, Any]]:
    """The parameter sets of the table (one run each)."""
    out = []
    for gamma in GAMMAS:
        for name, thermostat in THERMOSTATS.items():
            for alpha in ALPHAS:
                out.append(dict(gamma=gamma, thermostat=name, alpha=alpha, law=None,
                                **thermostat))
    for law in LAWS:
        for name, thermostat in THERMOSTATS.items():
            out.append(dict(gamma=1.0, thermostat=name, alpha=getattr(law, "alpha", math.nan),
                            law=law, **thermostat))
    n, base = (2000, 100.0) if quick else (20_000, 2000.0)
    for k, row in enumerate(out):
        alpha = row["alpha"] if row["law"] is None else 0.6
        gamma = row["gamma"]
        window = 12.0 / ((2.0 + gamma) * (1.0 + gamma) * (1.0 - alpha**2))
        row.update(n=n, cpp=max(base, 20.0 * window),
                   seed=np.random.SeedSequence(2026, spawn_key=(k,)))
    return out


def run_row(row: dict[str, Any]) -> dict[str, Any]:
    """One DSMC run and its table row."""
    c0 = time.process_time()
    model = row["law"] if row["law"] is not None else row["alpha"]
    run = dsmc.simulate_heated(model, row["n"], kernel=row["gamma"],
                               diffusion=row["diffusion"], friction=row["friction"],
                               seed=row["seed"], collisions_per_particle=row["cpp"])
    cpu = time.process_time() - c0
    d = run.distribution
    t_err = d.observable_error(lambda x: x.temperature)
    t_ex = a2_ex = math.nan
    if row["gamma"] == 0.0 and row["law"] is None:
        t_ex, a2_ex = maxwell_exact(row["alpha"], row["diffusion"], row["friction"])
    return {"method": "dsmc", "gamma": row["gamma"], "thermostat": row["thermostat"],
            "diffusion": row["diffusion"], "friction": row["friction"],
            "restitution": "constant" if row["law"] is None else repr(row["law"]),
            "alpha": row["alpha"], "n_particles": row["n"],
            "collisions_per_particle": row["cpp"], "T": run.temperature, "T_err": t_err,
            "a2": run.a2, "a2_err": run.a2_error, "T_exact": t_ex, "a2_exact": a2_ex,
            "z_T": (run.temperature - t_ex) / t_err, "z_a2": (run.a2 - a2_ex) / run.a2_error,
            "converged": run.info.converged, "relaxed_at": run.relaxed_at,
            "n_collisions": run.n_collisions, "dt": d.params["dt"], "cpu_s": cpu}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", help="CSV file to write")
    parser.add_argument("--quick", action="store_true", help="N = 2000, short runs")
    parser.add_argument("--workers", type=int, default=1, help="processes (default 1)")
    args = parser.parse_args()
    todo = rows(args.quick)
    t0 = time.perf_counter()
    if args.workers > 1:
        with ProcessPoolExecutor(args.workers) as pool:
            results = list(pool.map(run_row, todo))
    else:
        results = [run_row(r) for r in todo]
    with open(args.out, "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=COLUMNS)
        writer.writeheader()
        writer.writerows(results)
    print(f"{'gamma':>5} {'thermostat':<11} {'restitution':<40}{'T':>10}{'+-':>9}"
          f"{'a2':>10}{'+-':>9}{'z_T':>7}{'z_a2':>7}{'cpu s':>7}")
    for r in results:
        law = f"alpha={r['alpha']}" if r["restitution"] == "constant" else r["restitution"]
        print(f"{r['gamma']:>5} {r['thermostat']:<11} {law:<40}{r['T']:>10.5f}"
              f"{r['T_err']:>9.1e}{r['a2']:>+10.5f}{r['a2_err']:>9.1e}{r['z_T']:>7.2f}"
              f"{r['z_a2']:>7.2f}{r['cpu_s']:>7.1f}")
    cpu = sum(r["cpu_s"] for r in results)
    print(f"{len(results)} runs, {cpu:.0f} CPU s in the runs, {time.perf_counter() - t0:.0f} s "
          f"wall; CSV written to {args.out}")


if __name__ == "__main__":
    main()
