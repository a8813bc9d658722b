"""Tests of the kinetic-fem command (kinetic_fem.cli and python -m kinetic_fem)."""

import contextlib
import io
import logging
import re
import shlex
import subprocess
import sys
import textwrap
import warnings

import numpy as np
import pytest

from kinetic_fem import VelocityDistribution, reproduce, solve_heated
from kinetic_fem.cli import COMMANDS, build_parser, main, select_items
from kinetic_fem.io import read_distribution
from kinetic_fem.solve import HEATED_SOLVERS, register_solver


@pytest.fixture(autouse=True)
def _restore_logging():
    """main() attaches stderr handlers to the package loggers; remove them afterwards.

    Otherwise later tests would log into this test's (closed) captured stderr.
    """
    yield
    for name in ("kinetic_fem", "particles"):
        log = logging.getLogger(name)
        for handler in [h for h in log.handlers if getattr(h, "_kinetic_fem", False)]:
            log.removeHandler(handler)
        log.setLevel(logging.NOTSET)


def test_help_explains_the_package(capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["--help"])
    assert exit_.value.code == 0
    out = capsys.readouterr().out
    for words in ("inelastic", "restitution", "reproduce --quick", "solve-heated"):
        assert words in out
    with pytest.raises(SystemExit):
        main(["reproduce", "--help"])
    out = capsys.readouterr().out
    for words in ("--quick", "--full", "--only", "--list", "--quiet", "--seed", "claims.md"):
        assert words in out


def test_no_command_prints_help(capsys):
    assert main([]) == 0
    assert "usage: kinetic-fem" in capsys.readouterr().out


def test_reproduce_writes_figures_and_table(tmp_path, capsys):
    out = tmp_path / "rep"
    assert main(["reproduce", "--quick", "--only", "S1", "--out", str(out), "--quiet"]) == 0
    printed = capsys.readouterr()
    assert "| C3 |" in printed.out and "claims table:" in printed.out
    assert printed.err == ""  # --quiet: no progress bar, no log
    assert (out / "claims.md").exists() and (out / "claims.csv").exists()
    assert (out / "S1_a2_first_order.png").exists()


@pytest.fixture
def toy_item():
    """An item checking its own claim C98, so tests do not depend on others' items."""

    @reproduce.register("Z8", "a toy item for the CLI tests", claims=("C98",))
    def run(ctx):
        return [reproduce.ClaimRow("C98", "toy", "1", "1", True, "toy")]

    yield
    reproduce.ITEMS.pop("Z8")


def test_reproduce_progress_and_log_go_to_stderr(tmp_path, capsys, toy_item):
    assert main(["reproduce", "--only", "C98", "--out", str(tmp_path)]) == 0
    captured = capsys.readouterr()
    assert "reproduce Z8" in captured.err  # the log line
    assert "1/1" in captured.err  # the progress bar
    assert "| C98 | toy | 1 | 1 | yes | toy |" in captured.out


def test_reproduce_list(capsys):
    assert main(["reproduce", "--list"]) == 0
    assert "S1" in capsys.readouterr().out


def test_select_items_maps_claims(toy_item):
    reproduce.load_plugins()
    assert select_items(["C98"]) == ["Z8"]
    assert select_items(["Z8", "C98", "S1"]) == ["S1", "Z8"]
    assert "S1" in select_items(["C3"])
    assert select_items(None) == sorted(reproduce.ITEMS, key=reproduce.item_order)
    with pytest.raises(ValueError, match=r"unknown item or claim \['F99'\]"):
        select_items(["F99"])


def test_bad_input_exits_with_a_message(capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["reproduce", "--only", "F99,S1"])
    assert exit_.value.code == 2
    assert "unknown item or claim ['F99']" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["reproduce", "--quick", "--full"])
    with pytest.raises(SystemExit):
        main(["solve-heated", "0.5", "--method", "no-such-method"])
    err = capsys.readouterr().err
    assert "invalid choice: 'no-such-method'" in err and "'fem'" in err


@pytest.fixture
def toy_solver():
    def solver(problem, *, n_v=161, label="x"):
        assert isinstance(label, str)
        v = np.linspace(-8, 8, n_v) * problem.velocity_scale
        return VelocityDistribution.from_values(v, np.exp(-v**2 / 2), method="cli-toy")

    register_solver("cli-toy", problem="heated")(solver)
    yield
    HEATED_SOLVERS.pop("cli-toy")


@pytest.mark.parametrize("suffix", [".npz", ".vtu"])
def test_solve_heated_prints_t_and_a2_and_saves(tmp_path, capsys, toy_solver, suffix):
    path = tmp_path / f"d{suffix}"
    assert main(["solve-heated", "0.5", "--method", "cli-toy", "--out", str(path),
                 "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "T = 1" in out and "a2 = " in out
    back = VelocityDistribution.load(path) if suffix == ".npz" else read_distribution(path)
    assert back.method == "cli-toy"


def test_solve_heated_rejects_bad_alpha(capsys, toy_solver):
    with pytest.raises(SystemExit) as exit_:
        main(["solve-heated", "1.0", "--method", "cli-toy"])
    assert exit_.value.code == 2
    assert "no steady state" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["solve-heated", "0.5", "--method", "cli-toy", "--out", "x.txt"])
    assert "--out must end in" in capsys.readouterr().err


def test_parser_defaults():
    args = build_parser().parse_args(["reproduce"])
    assert args.quick is True and args.only is None and args.seed == reproduce.Context.seed
    assert build_parser().parse_args(["reproduce", "--full"]).quick is False


def test_python_dash_m_runs_the_command():
    done = subprocess.run([sys.executable, "-m", "kinetic_fem", "reproduce", "--list"],
                          capture_output=True, text=True, timeout=120, check=False)
    assert done.returncode == 0, done.stderr
    assert "S1" in done.stdout


def test_solve_heated_passes_solver_options(tmp_path, capsys, toy_solver):
    path = tmp_path / "d.npz"
    assert main(["solve-heated", "0.5", "--method", "cli-toy", "-o", "n_v=41",
                 "--option", "label=abc", "--out", str(path), "--quiet"]) == 0
    assert VelocityDistribution.load(path).v.size == 41
    with pytest.raises(SystemExit) as exit_:
        main(["solve-heated", "0.5", "--method", "cli-toy", "-o", "n_vv=41"])
    assert exit_.value.code == 2
    assert "unknown option(s) ['n_vv'] for method 'cli-toy'; valid -o names: ['label', 'n_v']" \
        in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["solve-heated", "0.5", "-o", "no-equals-sign"])
    assert "expected KEY=VALUE" in capsys.readouterr().err


def test_solve_cooling_prints_zeta_and_saves(tmp_path, capsys):
    path = tmp_path / "hcs.npz"
    assert main(["solve-cooling", "0.8", "--method", "spectral", "-o", "order=4",
                 "--out", str(path), "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "zeta = " in out and "a2 = " in out
    assert path.exists()


def test_solve_cooling_errors_without_traceback(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["solve-cooling", "1.5"])
    assert exc.value.code == 2
    with pytest.raises(SystemExit) as exc:
        main(["solve-cooling", "0.5", "--method", "spectral", "-o", "order=8", "--quiet"])
    assert exc.value.code == 1
    assert "solver failed" in capsys.readouterr().err


def test_option_typo_prints_the_subcommand_usage_and_valid_options(capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["solve-heated", "0.5", "--methd", "fem"])
    assert exit_.value.code == 2
    err = capsys.readouterr().err
    assert "usage: kinetic-fem solve-heated" in err
    assert "--methd -> did you mean --method?" in err
    assert "valid options of 'kinetic-fem solve-heated': --help, --restitution" in err
    for cmd in (["dsmc", "0.5", "-N", "10"], ["md", "0.5", "-N", "10"], ["sweep"],
                ["solve-cooling", "0.5"], ["reproduce"]):
        with pytest.raises(SystemExit):
            main([*cmd, "--no-such-option"])
        err = capsys.readouterr().err
        assert f"usage: kinetic-fem {cmd[0]}" in err
        assert f"valid options of 'kinetic-fem {cmd[0]}'" in err


def test_method_help_lists_the_choices(capsys):
    for cmd in ("solve-heated", "solve-cooling", "sweep"):
        with pytest.raises(SystemExit):
            main([cmd, "--help"])
        out = capsys.readouterr().out
        assert "one of: " in out and "spectral" in out and "examples:" in out
    with pytest.raises(SystemExit):
        main(["sweep", "--help"])
    assert "dsmc, fd, fem, md, spectral" in capsys.readouterr().out


def test_solve_heated_model_options(capsys, toy_solver):
    assert main(["solve-heated", "0.5", "--method", "cli-toy", "--kernel", "0", "--friction",
                 "0.5", "--quiet"]) == 0
    assert "friction=0.5 kernel=0.0" in capsys.readouterr().out
    assert main(["solve-heated", "0.5", "--method", "cli-toy", "--restitution",
                 "threshold:0.1", "--quiet"]) == 0
    assert "ThresholdRestitution(alpha=0.5, threshold=0.1)" in capsys.readouterr().out
    assert main(["solve-heated", "--method", "cli-toy", "--restitution", "viscoelastic:0.05",
                 "--quiet"]) == 0
    assert "ViscoelasticRestitution(delta=0.05)" in capsys.readouterr().out
    for argv, message in [([], "alpha is required"),
                          (["0.5", "--restitution", "viscoelastic:0.1"], "not both"),
                          (["0.5", "--kernel", "3"], "gamma"),
                          (["0.5", "--restitution", "elastic"], "expected constant")]:
        with pytest.raises(SystemExit) as exit_:
            main(["solve-heated", *argv, "--method", "cli-toy", "--quiet"])
        assert exit_.value.code == 2
        assert message in capsys.readouterr().err


def _summary_without_time(text):
    return text.split(" collisions in")[0]


def test_dsmc_command_checkpoint_resume_and_output(tmp_path, capsys):
    ckpt, out = tmp_path / "run.ckpt", tmp_path / "dist.npz"
    argv = ["dsmc", "0.6", "-N", "400", "--collisions", "10", "--seed", "3", "-o",
            "n_batches=5", "--checkpoint", str(ckpt), "--quiet"]
    assert main([*argv, "--out", str(out)]) == 0
    first = capsys.readouterr().out
    assert first.startswith("dsmc heated alpha=0.6 N=400 seed=3: T = ") and "a2 = " in first
    assert "collisions/s" not in first and "/s), converged" in first
    assert VelocityDistribution.load(out).method == "dsmc"
    assert main([*argv, "--resume"]) == 0
    assert _summary_without_time(capsys.readouterr().out) == _summary_without_time(first)
    with pytest.raises(SystemExit):
        main(["dsmc", "0.6", "-N", "400", "-o", "n_batch=5"])
    assert "valid -o names: ['average_every', 'bins', 'c_max'" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main([*argv, "--out", str(tmp_path / "run.ckpt.npz")])
    assert "would write the same .npz file" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["dsmc", "0.6", "-N", "400", "--resume"])
    assert "--resume needs --checkpoint" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["dsmc", "0.6", "-N", "400", "--checkpoint", str(ckpt), "--resume"])
    assert "--resume of a dsmc run needs the --seed" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["dsmc", "0.6", "-N", "400", "--cooling", "--friction", "1"])
    assert "--friction applies to the heated gas" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["dsmc", "0.6"])
    assert "-N/--particles" in capsys.readouterr().err


def test_md_command(capsys):
    assert main(["md", "0.9", "-N", "50", "--collisions", "4", "--seed", "1", "--cooling",
                 "--quiet"]) == 0
    assert capsys.readouterr().out.startswith("md cooling alpha=0.9 N=50 seed=1: T = ")


def test_sweep_command_store_out_and_rerun(tmp_path, capsys):
    import xarray as xr

    store, out = tmp_path / "s", tmp_path / "s.nc"
    argv = ["sweep", "--method", "spectral", "--alpha", "0.5,0.9", "--density", "1,2",
            "--store", str(store), "--workers", "1", "--quiet"]
    assert main([*argv, "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "4/4 point(s) converged" in printed and "alpha  density" in printed
    ds = xr.open_dataset(out, engine="scipy").load()
    assert ds.a2.dims == ("alpha", "density") and ds.attrs["fixed_method"] == "spectral"
    assert float(ds.T.sel(alpha=0.9, density=2.0)) == pytest.approx(
        solve_heated(0.9, density=2.0, method="spectral").temperature, rel=1e-12)
    assert len(list(store.glob("point-*.nc"))) == 4
    assert main(argv) == 0
    assert "4/4 point(s) converged" in capsys.readouterr().out


def test_sweep_command_reads_a_toml_grid(tmp_path, capsys):
    config = tmp_path / "grid.toml"
    config.write_text('method = "dsmc"\nseed = 4\nworkers = 1\n[grid]\nalpha = [0.5, 0.9]\n'
                      'n_particles = [300]\n[options]\ncollisions_per_particle = 8\n'
                      'n_batches = 4\n')
    assert main(["sweep", "--config", str(config), "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "alpha  n_particles" in out and "2/2 point(s)" in out and "simulate_heated" in out
    assert main(["sweep", "--config", str(config), "--quiet", "--replicas", "2",
                 "--alpha", "0.5"]) == 0
    out = capsys.readouterr().out
    assert "alpha  n_particles  replica" in out and "2/2 point(s)" in out
    config.write_text("[grid]\nalpha = [0.5]\n[optoins]\n")
    with pytest.raises(SystemExit):
        main(["sweep", "--config", str(config)])
    assert "unknown key(s) ['optoins']" in capsys.readouterr().err


@pytest.mark.parametrize("argv, message", [
    ([], "empty grid"),
    (["--alpha", "0.5", "--out", "x.txt"], "--out must end in .nc"),
    (["--alpha", "0.5", "--method", "dsmc"], "needs --particles"),
    (["--alpha", "0.5", "--workers", "0"], "--workers must be >= 1"),
    (["--alpha", "0.5", "--workers", "2", "--scheduler", "tcp://x:1"], "not both"),
    (["--alpha", "0.5,x"], "comma-separated numbers"),
    (["--alpha", "0.5", "--method", "spectral", "-o", "ordr=4"], "valid -o names"),
])
def test_sweep_command_errors(argv, message, capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["sweep", *argv])
    assert exit_.value.code == 2
    assert message in capsys.readouterr().err


def test_sweep_command_on_a_dask_scheduler(capsys):
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False,
                                  dashboard_address=None) as cluster:
        assert main(["sweep", "--method", "spectral", "--alpha", "0.5,0.9", "--scheduler",
                     cluster.scheduler_address, "--quiet"]) == 0
    assert "2/2 point(s) converged" in capsys.readouterr().out


def test_sweep_command_in_a_subprocess(tmp_path):
    done = subprocess.run([sys.executable, "-m", "kinetic_fem", "sweep", "--method", "spectral",
                           "--alpha", "0.5,0.9", "--workers", "2", "--store",
                           str(tmp_path / "s"), "--quiet"],
                          capture_output=True, text=True, timeout=120, check=False)
    assert done.returncode == 0, done.stderr
    assert "2/2 point(s) converged" in done.stdout


# ------------------------------------------------------------------ issue 30: first hour
def test_top_level_help_loads_no_solver():
    """``kinetic-fem --help`` builds only the command list: no scipy, numba or solver."""
    code = ("import sys\nfrom kinetic_fem.cli import main\n"
            "try:\n    main(['--help'])\nexcept SystemExit:\n    pass\n"
            "print(sorted(m for m in ('scipy', 'numba', 'skfem', 'xarray', 'kinetic_fem.solve')"
            " if m in sys.modules))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True, timeout=120)
    assert done.stdout.strip().endswith("[]") and "solve-cooling" in done.stdout


def test_import_is_light_and_dir_is_clean():
    code = ("import sys, kinetic_fem as kf\n"
            "print(sorted(m for m in ('scipy', 'numba', 'skfem', 'xarray', 'matplotlib')"
            " if m in sys.modules), 'logging' in dir(kf), 'sys' in dir(kf))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True, timeout=120)
    assert done.stdout.split() == ["[]", "False", "False"]


def test_cli_takes_the_api_defaults():
    import inspect

    import kinetic_fem as kf

    parser = build_parser()
    for command, function in (("solve-heated", kf.solve_heated),
                              ("solve-cooling", kf.solve_cooling)):
        sub = parser.commands[command]
        for name in ("method", "density", "kernel"):
            assert sub.get_default(name) == inspect.signature(function).parameters[name].default
    assert parser.commands["solve-cooling"].get_default("method") == "fem"


def test_sweep_refuses_a_bad_value_before_any_point(tmp_path, capsys):
    store = tmp_path / "s"
    with pytest.raises(SystemExit) as exc:
        main(["sweep", "--alpha", "0.3,1.5", "--store", str(store), "--quiet"])
    assert exc.value.code == 2
    assert "{'alpha': 1.5} is invalid (nothing was computed)" in capsys.readouterr().err
    assert not list(store.glob("point-*.nc")) if store.exists() else True


def test_ctrl_c_on_a_sweep_says_what_was_kept(tmp_path):
    """SIGINT to the process group (as a terminal's Ctrl-C) after the first stored point:
    one line, exit status 130, no traceback from the command or its workers."""
    import os
    import signal
    import time

    store = tmp_path / "s"
    # 181 points (~0.15 s each): a first point that is stored cannot be the last one
    # before the signal lands, even when the first point waits for a loaded machine
    # (with 19 points the whole sweep once ended between the check and the signal, and
    # the signal then hit the interpreter's exit, status -2)
    n_points = 181
    alphas = ",".join(f"{a:.3f}" for a in np.linspace(0.05, 0.95, n_points))
    child = subprocess.Popen([sys.executable, "-m", "kinetic_fem", "sweep", "--alpha", alphas,
                              "--method", "spectral", "--store", str(store), "--workers", "2"],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                             start_new_session=True)
    deadline = time.monotonic() + 240
    while not list(store.glob("point-*.nc")) and time.monotonic() < deadline \
            and child.poll() is None:
        time.sleep(0.2)
    if child.poll() is not None:
        pytest.skip("the sweep finished before it could be interrupted")
    os.killpg(child.pid, signal.SIGINT)
    _, err = child.communicate(timeout=120)
    if child.returncode != 130 and len(list(store.glob("point-*.nc"))) == n_points:
        pytest.skip("the sweep finished before the interrupt landed")
    assert child.returncode == 130, err
    assert "Traceback" not in err
    last = err.strip().splitlines()[-1]
    assert last.startswith("kinetic-fem: interrupted: ") and f"kept in {store}" in last


def _help_text(args):
    out = io.StringIO()
    with contextlib.redirect_stdout(out), pytest.raises(SystemExit):
        main(args)
    return out.getvalue()


def help_examples():
    """Every example command of ``kinetic-fem --help`` and of each sub-command's ``--help``,
    without ``kinetic-fem`` and the comment after it, and the mix.toml the mixture
    examples read (shown in that command's help)."""
    examples = []
    for args in (["--help"], *([cmd, "--help"] for cmd in COMMANDS)):
        text = _help_text(args)
        if args[0] == "mixture":
            mix_toml = textwrap.dedent(text.split("mix.toml:\n", 1)[1])
        block = text.split("examples:\n", 1)[1].split("\n\n", 1)[0]
        for line in re.sub(r"\s*\\\n\s*", " ", block).splitlines():
            command = re.split(r"\s{2,}", line.strip())[0]  # comments follow 2+ spaces
            assert command.startswith("kinetic-fem "), line
            examples.append(command.removeprefix("kinetic-fem "))
    return examples, mix_toml


# The --help examples cheap enough for the default run, in-process (0.2-2.7 s each with
# --durations at load 10 on 2 cores, about 1.7 times their idle cost).
FAST_HELP_EXAMPLES = [
    "reproduce --list",
    "solve-heated 0.9 --method fem --out a09.vtu",
    "solve-heated 0.8 --kernel 0 --friction 0.5",
    "solve-heated 0.7 --restitution threshold:0.1",
    "solve-heated --restitution viscoelastic:0.05",
    "solve-cooling 0.8 --method spectral -o order=4",
    "dsmc 0.9 -N 10000 --collisions 400 --seed 1 --out run.npz",
    "dsmc 0.9 -N 5000 -o n_batches=5",
    "md 0.9 -N 5000 -o n_batches=5",
    "md 0.9 -N 2000 -o sigma=0.25",
    "mixture mix.toml",
]
# Run by the slow test (a subprocess each, under -W error): worker processes, long runs
# (the FEM cooling solves: 3.3 s and more at load 10).
SLOW_HELP_EXAMPLES = [
    "reproduce --quick --out reproduce-out",
    "sweep --alpha 0.3,0.6,0.9 --store s",
    "reproduce --quick --only F2,F3 --out out --seed 7",
    "solve-heated 0.5 --method fd -o cutoff=20.0",
    "solve-cooling 0.8 --kernel 0 --method fem",
    "solve-cooling 0.9 --out hcs09.vtu",
    "dsmc 0.6 -N 100000 --progress --checkpoint run.ckpt --seed 1",
    "dsmc 0.6 -N 100000 --progress --checkpoint run.ckpt --seed 1 --resume",
    "dsmc 0.9 -N 5000 --cooling --collisions 50 -o n_batches=4",
    "md 0.9 -N 10000 --collisions 400 --seed 1 --out run.npz",
    "md 0.6 -N 100000 --progress --checkpoint run.ckpt --seed 1",
    "md 0.6 -N 100000 --progress --checkpoint run.ckpt --seed 1 --resume",
    "md 0.99 -N 1000 --cooling --collisions 50 -o n_batches=4",
    "sweep --method fem --alpha 0.3,0.6,0.9 --kernel 0,1 --store a2-map",
    "sweep --method dsmc --alpha 0.5,0.9 --particles 10000 --replicas 8 "
    "-o collisions_per_particle=50 -o n_batches=4",
    "sweep --method spectral --problem cooling --alpha 0.7,0.9 -o order=4 --out hcs.nc",
    "mixture mix.toml --method dsmc -N 4000 --collisions 300 --seed 1",
]
# Examples that another one runs with an --out added (the same computation, then saved).
SAVED_BY_HELP_EXAMPLES = {
    "solve-heated 0.9 --method fem": "solve-heated 0.9 --method fem --out a09.vtu",
    "dsmc 0.9 -N 10000 --collisions 400 --seed 1":
        "dsmc 0.9 -N 10000 --collisions 400 --seed 1 --out run.npz",
}
NOT_RUN_HELP_EXAMPLES = {
    "<command> --help": "a placeholder (each command's --help is printed by the tests above)",
    "reproduce --full --out paper-sizes": "the paper's sizes, hours",
    "sweep --config grid.toml --scheduler tcp://10.0.0.1:8786":
        "needs a grid file and a running dask scheduler",
}


def test_every_help_example_is_run_by_a_test():
    """A new example in a --help text must be added to one of the lists above."""
    examples, _ = help_examples()
    listed = (FAST_HELP_EXAMPLES + SLOW_HELP_EXAMPLES + list(SAVED_BY_HELP_EXAMPLES)
              + list(NOT_RUN_HELP_EXAMPLES))
    assert sorted(set(examples)) == sorted(listed)
    for short, saved in SAVED_BY_HELP_EXAMPLES.items():
        assert saved.startswith(short + " --out ") and saved in FAST_HELP_EXAMPLES


def _run_help_example(command, tmp_path, monkeypatch, caplog):
    _, mix_toml = help_examples()
    (tmp_path / "mix.toml").write_text(mix_toml)
    monkeypatch.chdir(tmp_path)
    with warnings.catch_warnings(), caplog.at_level(logging.WARNING):
        warnings.simplefilter("error")
        assert main([*shlex.split(command), "--quiet"]) == 0
    assert not [r for r in caplog.records if r.levelno >= logging.WARNING], caplog.text


@pytest.mark.parametrize("command", FAST_HELP_EXAMPLES)
def test_help_examples_run_without_a_warning(command, tmp_path, monkeypatch, caplog):
    """The cheap examples of the --help texts run with warnings as errors and log no
    warning (some warned before: an asymptotic Sonine order, DSMC batches shorter than
    the relaxation window)."""
    _run_help_example(command, tmp_path, monkeypatch, caplog)


@pytest.mark.slow
@pytest.mark.parametrize("command", [
    c for c in SLOW_HELP_EXAMPLES if not c.endswith("--resume")])
def test_slow_help_examples_run_without_a_warning(command, tmp_path):
    """The other --help examples, each as a command of its own under ``-W error`` (the
    sweeps' worker processes inherit it); a checkpointed run is then resumed (``--resume``
    example).  Minutes in all, ``reproduce --quick`` most of them."""
    _, mix_toml = help_examples()
    (tmp_path / "mix.toml").write_text(mix_toml)
    commands = [command] + [c for c in SLOW_HELP_EXAMPLES if c == f"{command} --resume"]
    for line in commands:
        done = subprocess.run([sys.executable, "-W", "error", "-m", "kinetic_fem",
                               *shlex.split(line), "--quiet"], cwd=tmp_path,
                              capture_output=True, text=True, timeout=3600)
        assert done.returncode == 0, done.stderr
        assert "Warning" not in done.stderr and "WARNING" not in done.stderr, done.stderr


def test_dsmc_checkpoint_without_a_seed_names_the_drawn_seed_for_resume(tmp_path, capsys):
    """An unseeded checkpointed DSMC run draws its root seed up front; the Ctrl-C line
    names it, and resuming with that seed continues the same run (the final line agrees)."""
    from kinetic_fem.cli import build_parser
    from kinetic_fem.cli.cmd_particles import interrupt_note

    ckpt = tmp_path / "run.ckpt"
    argv = ["dsmc", "0.6", "-N", "400", "--collisions", "10", "-o", "n_batches=5",
            "--checkpoint", str(ckpt), "--quiet"]
    assert main(argv) == 0
    first = capsys.readouterr().out
    seed = first.split("seed=")[1].split(":")[0]
    assert seed.isdigit()
    args = build_parser().parse_args([*argv, "--seed", seed])
    assert interrupt_note(args).endswith(f"add --seed {seed} --resume to continue from it")
    assert main([*argv, "--seed", seed, "--resume"]) == 0
    assert _summary_without_time(capsys.readouterr().out) == _summary_without_time(first)
