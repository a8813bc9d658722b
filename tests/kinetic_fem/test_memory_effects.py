"""Tests of kinetic_fem.analysis.memory_effects (Kovacs and Mpemba protocols).

Fast checks only, where the answer is exact: the Maxwell model's energy balance is
closed (dT/dt = 2D - k(alpha) n T depends on T alone), so its Kovacs hump
vanishes and no Mpemba crossing exists; the first-Sonine threshold for hard rods is a
property of two ODEs, found by bisection.
"""

from __future__ import annotations

import numpy as np
import pytest

from kinetic_fem.analysis.memory_effects import kovacs, mpemba, mpemba_threshold


def test_maxwell_kovacs_has_no_hump():
    """Closed energy balance: T stays at T_st(D2) after the switch, to the ODE tolerance."""
    k = kovacs(0.6, kernel=0.0)
    assert k.waiting_time > 0
    assert abs(k.hump) < 1e-8
    assert np.all(np.diff(k.exact.times) >= 0)


def test_maxwell_has_no_mpemba_threshold():
    assert mpemba_threshold(0.6, kernel=0.0) is None
    assert mpemba(0.6, kernel=0.0).threshold is None


def test_hard_rod_sonine_threshold_crosses():
    """Above the threshold the first-Sonine hot curve overtakes the cold one, below not."""
    a_c = mpemba_threshold(0.6)
    assert a_c is not None and 0.0 < a_c < 4.0 / 3.0
    wider = mpemba_threshold(0.6, hot=1.6)  # a larger head start needs a larger a2
    assert wider is None or wider > a_c


def test_bad_protocol_raises():
    with pytest.raises(ValueError, match="d_quench < d_final < d_start"):
        kovacs(0.6, kernel=0.0, d_quench=0.5, d_final=0.3)
    with pytest.raises(ValueError, match="hot > cold"):
        mpemba(0.6, kernel=0.0, hot=1.0, cold=1.2)
