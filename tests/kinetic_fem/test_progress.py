"""Tests of kinetic_fem/progress.py and the ``progress=`` argument of the long calls."""

from __future__ import annotations

import pytest

import kinetic_fem as kf
from kinetic_fem.progress import resolve_progress


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
