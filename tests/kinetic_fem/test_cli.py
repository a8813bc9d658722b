"""Tests of the kinetic-fem command (kinetic_fem.cli and python -m kinetic_fem)."""

import logging
import subprocess
import sys

import numpy as np
import pytest

from kinetic_fem import VelocityDistribution, reproduce
from kinetic_fem.cli import build_parser, main, select_items
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
    assert select_items(None) == sorted(reproduce.ITEMS, key=reproduce._order)
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
    assert "available:" in capsys.readouterr().err


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
    assert "n_vv" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["solve-heated", "0.5", "-o", "no-equals-sign"])
    assert "expected KEY=VALUE" in capsys.readouterr().err


def test_solve_cooling_prints_zeta_and_saves(tmp_path, capsys):
    path = tmp_path / "hcs.npz"
    assert main(["solve-cooling", "0.5", "--method", "spectral", "-o", "order=4",
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
