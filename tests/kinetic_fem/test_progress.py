"""Tests of kinetic_fem/progress.py and the ``progress=`` argument of the long calls."""

from __future__ import annotations

import time

import pytest

import kinetic_fem as kf
from kinetic_fem.progress import resolve_progress, working


def test_resolve_progress_refuses_strings() -> None:
    with pytest.raises(TypeError, match="progress must be True, False or None"):
        resolve_progress("yes")  # type: ignore[arg-type]


@pytest.mark.parametrize("progress, shown", [(True, True), (None, False)])
def test_evolve_cooling_progress_bar_on_stderr(progress: bool | None, shown: bool,
                                               capsys: pytest.CaptureFixture[str]) -> None:
    """``evolve_cooling(progress=...)``: a tqdm bar on stderr when asked; None under
    pytest (stderr captured, not a terminal) stays quiet."""
    ev = kf.evolve_cooling(0.8, times=[0.1], spacing=0.5, rtol=1e-2, progress=progress)
    assert ev.temperature[0] < 1.0
    err = capsys.readouterr().err
    assert ("evolve_cooling" in err or "%|" in err) is shown, err[-300:]


def test_evolve_heated_progress_is_checked() -> None:
    with pytest.raises(TypeError, match="progress"):
        kf.evolve_heated(0.5, times=[0.5], initial_temperature=0.5, spacing=0.5,
                         progress="on")  # type: ignore[arg-type]


def test_working_line_appears_only_for_a_long_call(capsys: pytest.CaptureFixture[str]) -> None:
    """:func:`working`: its name and clock once the call outlasts ``delay``; nothing for a
    call that ends before."""
    with working("long solve", True, delay=0.05, interval=0.05):
        time.sleep(0.4)
    assert "long solve" in capsys.readouterr().err
    with working("quick solve", True, delay=30.0, interval=0.05):
        time.sleep(0.2)
    assert capsys.readouterr().err == ""


def test_solve_checks_progress_and_stays_quiet_when_not_watched(
        capsys: pytest.CaptureFixture[str]) -> None:
    """``solve_heated/solve_cooling(progress=...)``: a bad value fails before any work;
    the default under pytest (not a terminal) prints nothing."""
    with pytest.raises(TypeError, match="progress must be"):
        kf.solve_heated(0.6, progress="yes")  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="progress must be"):
        kf.solve_cooling(0.6, progress=1)  # type: ignore[arg-type]
    assert kf.solve_heated(0.6, method="spectral").info.converged
    assert capsys.readouterr().err == ""


def _solve_reporting_progress(alpha: float, progress: bool | None = None) -> object:
    """A sweep function that records the ``progress`` it was given."""
    SEEN.append(progress)
    return kf.solve_heated(alpha, method="spectral")


SEEN: list[bool | None] = []


def test_sweep_runs_its_points_quiet() -> None:
    """The sweep's own bar counts the points: a function that takes ``progress`` gets
    ``False`` at every point."""
    SEEN.clear()
    kf.sweep(_solve_reporting_progress, {"alpha": [0.3, 0.6]}, executor="serial")
    assert SEEN == [False, False]


@pytest.mark.parametrize("progress, shown", [(True, True), (None, False)])
def test_dsmc_progress_defaults_to_when_watched(progress: bool | None, shown: bool,
                                                capsys: pytest.CaptureFixture[str]) -> None:
    """DSMC's ``progress`` defaults to None: a bar when asked, none under pytest (stderr
    not a terminal)."""
    from particles.dsmc import simulate_heated

    run = simulate_heated(0.6, 200, seed=1, collisions_per_particle=10.0, n_batches=2,
                          progress=progress)
    assert run.temperature > 0
    assert ("DSMC" in capsys.readouterr().err) is shown


@pytest.mark.parametrize("progress, shown", [(True, True), (None, False)])
def test_md_progress_defaults_to_when_watched(progress: bool | None, shown: bool,
                                              capsys: pytest.CaptureFixture[str]) -> None:
    """MD's ``progress`` as DSMC's: a bar named "MD" when asked, none under pytest."""
    from particles.md import simulate_heated

    run = simulate_heated(0.6, 200, seed=1, collisions_per_particle=10.0, n_batches=2,
                          progress=progress)
    assert run.temperature > 0
    assert ("MD" in capsys.readouterr().err) is shown
