"""``kinetic-fem dsmc`` and ``kinetic-fem md``: one particle simulation.

``particles`` is imported inside the commands only (kinetic_fem never imports it at
module level); model options the installed simulation does not take are refused with
the list of what it does take.
"""

from __future__ import annotations

import argparse
import importlib
import inspect
import time
from pathlib import Path
from typing import Any

from ..files import npz_path
from . import COMMANDS
from .parser import (
    add_model_arguments,
    check_options,
    check_out,
    key_value,
    restitution_of,
    save,
)

__all__ = ["add_parsers", "run", "interrupt_note"]

EPILOG = """\
examples:
  kinetic-fem {cmd} 0.9 -N 10000 --collisions 400 --seed 1 --out run.npz
  kinetic-fem {cmd} 0.6 -N 100000 --progress --checkpoint run.ckpt --seed 1   (Ctrl-C, then:)
  kinetic-fem {cmd} 0.6 -N 100000 --progress --checkpoint run.ckpt --seed 1 --resume
  kinetic-fem {cmd} {cooling} --cooling --collisions 50 -o n_batches=4
  kinetic-fem {cmd} 0.9 -N 5000 -o n_batches=5{extra}

One line summarises the run: T, a2 with its batch error, collisions, wall time and
collisions per second.  Any keyword of particles.{cmd}.simulate_heated/_cooling can
be given with -o; an unknown one lists the valid names.
"""

_DESCRIPTION = {
    "dsmc": "Direct Simulation Monte Carlo of the homogeneous Boltzmann equation "
            "(velocities only): heated steady state or free cooling.",
    "md": "Event-driven molecular dynamics of inelastic rods on a ring: heated steady "
          "state or free cooling.",
}


def add_parsers(sub: argparse._SubParsersAction) -> list[argparse.ArgumentParser]:
    """The ``dsmc`` and ``md`` sub-commands, added to ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The sub-parsers of the ``kinetic-fem`` parser.

    Returns
    -------
    list of argparse.ArgumentParser
    """
    parsers = []
    for cmd in ("dsmc", "md"):
        extra = "\n  kinetic-fem md 0.9 -N 2000 -o sigma=0.25" if cmd == "md" else ""
        # free cooling MD collapses unless N (1 - alpha) is small (5000 rods at 0.9 did)
        cooling = "0.99 -N 1000" if cmd == "md" else "0.9 -N 5000"
        p = sub.add_parser(cmd, help=COMMANDS[cmd][1],
                           description=_DESCRIPTION[cmd],
                           epilog=EPILOG.format(cmd=cmd, extra=extra, cooling=cooling),
                           formatter_class=argparse.RawDescriptionHelpFormatter)
        add_model_arguments(p, heated=True)
        p.add_argument("-N", "--particles", dest="n_particles", type=int, required=True,
                       metavar="N", help="number of particles")
        p.add_argument("--collisions", type=float, default=None, metavar="C",
                       help="run length in collisions per particle (default: the "
                            "simulation's)")
        p.add_argument("--cooling", action="store_true",
                       help="free cooling instead of the heated steady state")
        p.add_argument("--seed", type=int, default=None,
                       help="root seed (default: fresh entropy, recorded in the result)")
        p.add_argument("--checkpoint", type=Path, default=None, metavar="FILE",
                       help="write the state to FILE during the run and at its end")
        p.add_argument("--resume", action="store_true",
                       help="continue bit-identically from --checkpoint if it exists")
        p.add_argument("--progress", action="store_true",
                       help="progress bar on stderr (the default; --quiet hides it)")
        p.add_argument("--out", type=Path, default=None, metavar="FILE",
                       help="save the distribution: .npz, .vtu or .xdmf")
        p.add_argument("-o", "--option", dest="options", type=key_value, action="append",
                       default=[], metavar="KEY=VALUE",
                       help="further keyword of the simulation, repeatable")
        p.add_argument("--quiet", action="store_true",
                       help="no progress bar and no log messages")
        parsers.append(p)
    return parsers


_SET_BY_FLAGS = ("alpha", "n_particles", "density", "diffusion", "friction", "kernel", "seed",
                 "collisions_per_particle", "checkpoint", "resume", "progress")


def _keywords(args: argparse.Namespace, function: Any) -> dict[str, Any]:
    params = inspect.signature(function).parameters
    kw: dict[str, Any] = {"density": args.density, "seed": args.seed,
                          "progress": args.progress or not args.quiet}
    model = {"kernel": (args.kernel, 1.0)}
    if args.cooling:
        for name, default in (("diffusion", 1.0), ("friction", 0.0)):
            if getattr(args, name) != default:
                raise ValueError(f"--{name} applies to the heated gas, not with --cooling")
    else:
        kw["diffusion"] = args.diffusion
        model["friction"] = (args.friction, 0.0)
    for name, (value, default) in model.items():
        if name in params:
            kw[name] = value
        elif value != default:
            raise ValueError(f"this installation's {function.__module__}.{function.__name__} "
                             f"takes no {name}; it supports {name} = {default} only")
    if args.collisions is not None:
        kw["collisions_per_particle"] = args.collisions
    if args.resume and args.checkpoint is None:
        raise ValueError("--resume needs --checkpoint FILE")
    if args.checkpoint is not None:
        if args.seed is None and args.command == "dsmc":
            # a DSMC checkpoint belongs to its root seed: without --seed one is drawn here,
            # so that the Ctrl-C line can name it for --resume (MD keeps an unseeded run's
            # random state in the checkpoint and resumes without one)
            if args.resume:
                raise ValueError("--resume of a dsmc run needs the --seed of the run it "
                                 "continues (the interrupted run's Ctrl-C line names it)")
            import numpy as np

            entropy = np.random.SeedSequence().entropy
            assert isinstance(entropy, int)  # drawn, not given: one int
            args.seed = entropy
            kw["seed"] = args.seed
        if args.out is not None and (npz_path(args.out).resolve()
                                     == npz_path(args.checkpoint).resolve()):
            raise ValueError(f"--out {str(args.out)!r} and --checkpoint "
                             f"{str(args.checkpoint)!r} would write the same .npz file")
        kw.update(checkpoint=args.checkpoint, resume=args.resume)
    options = dict(args.options)
    check_options(function, options, f"{function.__module__}.{function.__name__}",
                  exclude=_SET_BY_FLAGS)
    return {**kw, **options}


def interrupt_note(args: argparse.Namespace) -> str:
    """What a Ctrl-C kept: the last checkpoint, if any, and how to resume.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    str
    """
    if args.checkpoint is None:
        return ("nothing was kept (no --checkpoint); add --checkpoint FILE to keep the "
                "state and resume with --resume")
    path = npz_path(args.checkpoint)
    if not path.exists():
        return (f"no checkpoint was written yet to {path} (one is written every "
                "checkpoint_every seconds); run the command again")
    seed = "" if args.seed is None else f" --seed {args.seed}"
    return f"the state last written to {path} is kept; add{seed} --resume to continue from it"


def run(args: argparse.Namespace) -> int:
    """Run ``kinetic-fem dsmc`` or ``md``: simulate, print the measured figures, save.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        Exit status: 0, or 1 if the run did not converge (the result is still saved).
    """
    check_out(args.out)
    module = importlib.import_module(f"particles.{args.command}")
    function = module.simulate_cooling if args.cooling else module.simulate_heated
    kw = _keywords(args, function)
    alpha = restitution_of(args)
    start = time.perf_counter()
    result = function(alpha, args.n_particles, **kw)
    wall = time.perf_counter() - start
    dist = result.distribution
    entropy = args.seed if args.seed is not None else dist.info.extra.get("seed_entropy")
    state = "converged" if dist.info.converged else f"NOT converged ({dist.info.message})"
    print(f"{args.command} {'cooling' if args.cooling else 'heated'} alpha={alpha} "
          f"N={args.n_particles} seed={entropy}: T = {result.temperature:.6g}  "
          f"a2 = {result.a2:.5g} +- {result.a2_error:.2g}  "
          f"{result.n_collisions:.4g} collisions in {wall:.3g} s "
          f"({result.n_collisions / wall:.3g} /s), {state}")
    if args.out is not None:
        print(f"saved to {save(dist, args.out)}")
    return 0 if dist.info.converged else 1
