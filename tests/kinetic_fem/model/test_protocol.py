"""Tests of kinetic_fem/protocol.py: schedules, protocols and their validation."""

import math

import pytest

from kinetic_fem.model.protocol import Protocol, Schedule, ramp, steps


def test_step_schedule_is_right_continuous_with_left_limits():
    s = steps([1.0, 2.0], [1.0, 3.0, 0.5])
    assert [s(0.0), s(1.0), s(1.5), s(2.0), s(9.0)] == [1.0, 3.0, 3.0, 0.5, 0.5]
    assert s(1.0, left=True) == 1.0 and s(2.0, left=True) == 3.0
    assert s.discontinuities == (1.0, 2.0)


def test_ramp_is_linear_between_knots_and_constant_outside():
    r = ramp([1.0, 3.0], [2.0, 4.0])
    assert [r(0.0), r(2.0), r(5.0)] == [2.0, 3.0, 4.0]


def test_protocol_values_and_breakpoints():
    p = Protocol(diffusion=steps([2.0], [1.0, 4.0]), friction=lambda t: 0.1 * t,
                 restitution=[(1.0, 0.8), (3.0, 0.6)])
    assert p.diffusion_at(2.5, 9.0) == 4.0
    assert p.diffusion_at(2.0, 9.0, left=True) == 1.0
    assert p.friction_at(2.0, 0.0) == pytest.approx(0.2)
    assert p.restitution_at(0.5, 0.9).alpha == 0.9
    assert p.restitution_at(1.0, 0.9).alpha == 0.8
    assert p.restitution_at(5.0, 0.9).alpha == 0.6
    assert p.breakpoints(10.0) == (1.0, 2.0, 3.0)
    assert p.breakpoints(2.5) == (1.0, 2.0)
    assert Protocol().diffusion_at(1.0, 2.5) == 2.5


@pytest.mark.parametrize("bad, match", [
    (lambda: steps([1.0], [1.0, -2.0]), ">= 0"),
    (lambda: steps([1.0], [1.0, math.inf]), "finite"),
    (lambda: steps([1.0], [math.nan, 1.0]), "NaN"),
    (lambda: steps([2.0, 1.0], [1.0, 1.0, 1.0]), "increasing"),
    (lambda: steps([-1.0], [1.0, 1.0]), ">= 0"),
    (lambda: steps([1.0], [1.0]), "needs 2 value"),
    (lambda: Schedule((1.0,), (1.0,), kind="cubic"), "kind"),
    (lambda: Protocol(diffusion=-1.0), "diffusion"),
    (lambda: Protocol(diffusion=0.0), "diffusion"),
    (lambda: Protocol(friction=math.inf), "finite"),
    (lambda: Protocol(restitution=[(2.0, 0.5), (1.0, 0.7)]), "increasing"),
    (lambda: Protocol(restitution=[(1.0, 1.5)]), "alpha"),
    (lambda: Protocol(restitution=[0.5]), "pairs"),
    (lambda: Protocol(diffusion=lambda t: -1.0).diffusion_at(0.5, 1.0), "t=0.5"),
    (lambda: Protocol(friction=lambda t: math.nan).friction_at(0.5, 1.0), "NaN"),
])
def test_bad_protocols_raise_clear_errors(bad, match):
    with pytest.raises(ValueError, match=match):
        bad()


def test_protocol_type_errors():
    with pytest.raises(TypeError, match="Schedule or a callable"):
        Protocol(diffusion="fast")
