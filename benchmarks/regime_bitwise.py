"""Bit-for-bit check of the FEM cooling state over every path of its dispatch (issue 26).

Solves 19 problems that together take every regime of
:data:`kinetic_fem.solvers.fem.regimes.REGIMES` and the fallbacks inside them (the
Maxwell short mesh, the gamma = 2 anchors on both of their meshes and their failure, the
near-elastic hard-kernel chain, the hump band and chain with and without ``initial``,
``resolution``, ``order``, ``spacing``, ``cutoff``, ``vertices``, the strong-alpha
continuation, the hard-kernel alpha chain, mesh sequencing, refused options) at cheap
sizes, and stores zeta, a2, the temperature, the node values of ln f and the error
message of each (or compares them with a stored run, bit for bit).

    python benchmarks/regime_bitwise.py --save before.npz     # e.g. on main
    python benchmarks/regime_bitwise.py --compare before.npz  # after the change
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from kinetic_fem.model import CoolingProblem  # noqa: E402
from kinetic_fem.solvers.fem import cooling as fc  # noqa: E402


def _vertices(c_max: float, h: float) -> np.ndarray:
    half = np.linspace(0.0, c_max, round(c_max / h) + 1)
    return np.concatenate([-half[:0:-1], half])


# name, kernel exponent, alpha, options (``initial``: the name of an earlier case)
CASES: tuple[tuple[str, float, float, dict], ...] = (
    ("maxwell_tail", 0.0, 0.7, {}),
    ("maxwell_tail_p2", 0.0, 0.3, {"order": 2}),
    ("maxwell_truncated", 0.0, 0.5, {"spacing": 0.16, "cutoff": 50.0}),
    ("gamma2_anchored", 2.0, 0.9, {}),
    ("gamma2_anchored_efold", 2.0, 0.999, {}),
    ("gamma2_anchor_fails", 2.0, 0.6, {"max_iter": 1}),
    ("gamma2_alpha_chain", 2.0, 0.9, {"spacing": 0.2}),
    ("gamma2_strong", 2.0, 0.3, {"spacing": 0.2}),
    ("gamma1.5_near_elastic", 1.5, 0.998, {}),
    ("rods_p3_strong", 1.0, 0.0, {}),
    ("rods_p2_sequenced", 1.0, 0.6, {"order": 2}),
    ("rods_vertices", 0.5, 0.3, {"vertices": _vertices(8.0, 0.25)}),
    ("rods_band", 1.0, 0.95, {}),
    ("rods_hump", 1.0, 0.97, {}),
    ("rods_hump_resolution", 1.0, 0.99, {"resolution": 0.14}),
    ("rods_hump_initial", 1.0, 0.99, {"initial": "rods_hump"}),
    ("rods_hump_p3", 1.0, 0.999, {}),
    ("rods_resolution_refused", 1.0, 0.5, {"resolution": 0.1}),
    ("rods_hump_order3_refused", 1.0, 0.99, {"order": 3}),
)


def run() -> dict[str, np.ndarray]:
    """Solve every case; arrays per case (``<name>/zeta`` ...), errors as strings."""
    out: dict[str, np.ndarray] = {}
    states: dict[str, object] = {}
    for name, gamma, alpha, options in CASES:
        opts = dict(options)
        if "initial" in opts:
            opts["initial"] = states[opts["initial"]]
        problem = CoolingProblem.from_parameters(alpha, kernel=gamma)
        t0 = time.process_time()
        try:
            state = fc.cooling_state(problem, **opts)
        except Exception as exc:  # noqa: BLE001 (the error is the result)
            out[f"{name}/error"] = np.array(f"{type(exc).__name__}: {exc}")
            print(f"{name:26s} {type(exc).__name__} {time.process_time() - t0:6.2f} CPU s")
            continue
        states[name] = state
        dist = fc.cooling_distribution(problem, state)
        out[f"{name}/zeta"] = np.array(state.zeta)
        out[f"{name}/a2"] = np.array(dist.a2)
        out[f"{name}/T"] = np.array(dist.temperature)
        out[f"{name}/u"] = np.asarray(state.u)
        out[f"{name}/vertices"] = np.asarray(state.disc.vertices)
        print(f"{name:26s} zeta {state.zeta:.15g} a2 {dist.a2:.6g} dofs {state.u.size} "
              f"{time.process_time() - t0:6.2f} CPU s", flush=True)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    group = parser.add_mutually_exclusive_group(required=True)
    group.add_argument("--save", help="write the results to this .npz")
    group.add_argument("--compare", help="compare with this .npz, bit for bit")
    args = parser.parse_args()
    out = run()
    if args.save:
        np.savez(args.save, **out)
        return
    ref = np.load(args.compare)
    keys = sorted(set(ref.files) | set(out))
    bad = [k for k in keys if k not in ref.files or k not in out
           or ref[k].shape != out[k].shape or ref[k].tobytes() != out[k].tobytes()]
    print(f"{len(keys) - len(bad)} of {len(keys)} arrays bit-identical")
    for k in bad:
        print("DIFFERS:", k)
    raise SystemExit(1 if bad else 0)


if __name__ == "__main__":
    main()
