"""Options that travel together: one object, or its fields by keyword (kinetic_fem.options)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from kinetic_fem.distribution import VelocityDistribution
from kinetic_fem.evolution_error import RTOL_RATIO, default_rtol, rerun_recipe
from kinetic_fem.evolve import evolve_cooling, evolve_heated
from kinetic_fem.model.protocol import Protocol
from kinetic_fem.options import (
    gather,
    gather_groups,
    is_option_group,
    option_default,
    option_group,
    option_names,
)
from kinetic_fem.solve import lookup_solver
from kinetic_fem.solvers.fem.cooling import solve_fem_cooling
from kinetic_fem.solvers.fem.heated import solve_fem_heated, steady_state
from kinetic_fem.solvers.fem.options import CoolingEvolveOptions, EvolveOptions, MeshOptions
from kinetic_fem.solvers.finite_difference import FDScheme, MarchOptions, solve_fd_heated
from kinetic_fem.solvers.maxwell import MomentOptions, evolve_moments


@option_group
@dataclasses.dataclass(frozen=True)
class _Opts:
    a: int = 1
    b: float | None = None


@dataclasses.dataclass(frozen=True)
class _Plain:  # a dataclass argument, not an option object
    c: int = 1


def test_gather_merges_keywords_over_the_object():
    assert gather(_Opts, None, {}, "f") == _Opts()
    assert gather(_Opts, _Opts(a=2), {"b": 0.5}, "f") == _Opts(a=2, b=0.5)
    with pytest.raises(TypeError, match=r"f\(\) got an unexpected keyword argument 'c'"):
        gather(_Opts, None, {"c": 1}, "f")
    with pytest.raises(TypeError, match="as a _Opts"):
        gather(_Opts, {"a": 1}, {}, "f")


def test_gather_groups_sends_each_keyword_to_its_object():
    first, second = gather_groups(((_Opts, None), (FDScheme, FDScheme(spacing=0.1))),
                                  {"a": 3, "richardson": 0}, "f")
    assert first == _Opts(a=3) and second == FDScheme(spacing=0.1, richardson=0)
    with pytest.raises(TypeError, match=r"'c'; its options are \['a', 'b', 'spacing'"):
        gather_groups(((_Opts, None), (FDScheme, None)), {"c": 1}, "f")


def test_option_names_list_the_fd_fields_not_the_problem_fields():
    names = set(option_names(solve_fd_heated) or ())
    fields = {f.name for cls in (FDScheme, MarchOptions) for f in dataclasses.fields(cls)}
    assert fields | {"scheme", "marching", "steady", "initial_temperature"} <= names
    assert not {"gas", "thermostat"} & names  # the problem is an argument, not options
    assert "gas" not in (option_names(solve_fem_heated) or ())


def test_option_names_list_the_mesh_fields():
    names = option_names(solve_fem_heated)
    assert names is not None
    assert {"order", "spacing", "cutoff", "vertices", "intorder", "mesh", "tol",
            "max_iter", "accuracy", "symmetric"} <= set(names)
    assert {"resolution", "initial"} <= set(option_names(solve_fem_cooling) or ())

    def anything(**kw):
        return kw

    assert option_names(anything) is None


def test_mesh_object_and_keywords_give_the_same_state():
    by_keywords = steady_state(0.5, order=2, spacing=0.4, cutoff=20.0)
    by_object = steady_state(0.5, mesh=MeshOptions(order=2, spacing=0.4, cutoff=20.0))
    np.testing.assert_array_equal(by_keywords.u, by_object.u)
    with pytest.raises(TypeError, match="spacnig"):
        solve_fem_heated(None, spacnig=0.2)  # refused before the problem is looked at


def test_option_default_reads_a_parameter_or_an_option_field():
    def run(x: float, *, tol: float = 1e-3, options: _Opts | None = None, **kw: float) -> None:
        pass

    assert option_default(run, "tol") == 1e-3
    assert option_default(run, "a") == 1            # a field of the option object
    with pytest.raises(KeyError, match="'x'"):
        option_default(run, "x")                    # no default
    with pytest.raises(KeyError, match="'c'"):
        option_default(run, "c")


def test_transient_drivers_take_their_options_as_one_object_or_by_keyword():
    heated = lookup_solver("transient-heated", "fem")
    cooling = lookup_solver("transient-cooling", "fem")
    for solver, cls in ((heated, EvolveOptions), (cooling, CoolingEvolveOptions)):
        names = set(option_names(solver) or ())
        assert {f.name for f in dataclasses.fields(cls)} | {"options", "progress"} <= names
        assert not {"diffusion", "friction", "restitution"} & names  # the protocol's
    assert default_rtol(heated) == 1e-4 and default_rtol(cooling) == 1e-6
    times = [0.1]
    by_keywords = evolve_cooling(0.8, times=times, spacing=0.5, rtol=1e-3, rescale=3.0)
    by_object = evolve_cooling(0.8, times=times, options=CoolingEvolveOptions(
        spacing=0.5, rtol=1e-3, rescale=3.0))
    np.testing.assert_array_equal(by_keywords.values, by_object.values)
    # the error estimate reruns at a tighter rtol than the object's (a stand-in rerun)
    asked = []

    def rerun(**options):
        asked.append(options)
        return by_object

    options = {"options": CoolingEvolveOptions(rtol=1e-3)}
    assert rerun_recipe(rerun, cooling, options)(by_object).rtol == 1e-3
    assert asked[0]["rtol"] == 1e-3 / RTOL_RATIO
    with pytest.raises(TypeError, match="'spacnig'; its CoolingEvolveOptions options"):
        evolve_cooling(0.8, times=times, spacnig=0.5)
    with pytest.raises(TypeError, match="'rescale'; its EvolveOptions options"):
        evolve_heated(0.8, times=times, rescale=2.0)


def test_moment_options_object_and_keywords_agree():
    by_keywords = evolve_moments(0.5, [0.0, 1.0], order=6, rtol=1e-10)
    by_object = evolve_moments(0.5, [0.0, 1.0], options=MomentOptions(order=6, rtol=1e-10))
    np.testing.assert_array_equal(by_keywords.moments, by_object.moments)
    with pytest.raises(TypeError, match="'ordre'"):
        evolve_moments(0.5, [0.0, 1.0], ordre=6)



def test_option_names_skip_dataclass_arguments_that_are_not_option_objects():
    """A start state, a protocol or any unmarked dataclass with a default is an argument:
    it adds no names; only classes marked ``option_group`` do (the former rule listed
    every optional dataclass argument's fields)."""
    from kinetic_fem.solvers.fem.cooling_transient import evolve_cooling_fem

    def run(x: float, *, initial: VelocityDistribution | None = None,
            protocol: Protocol | None = None, plain: _Plain | None = None,
            options: _Opts | None = None, **keywords: float) -> None:
        pass

    def run_plain(x: float, *, plain: _Plain | None = None, **keywords: float) -> None:
        pass

    assert is_option_group(_Opts) and not is_option_group(_Plain)
    assert option_names(run) == ["a", "b", "initial", "options", "plain", "protocol", "x"]
    assert option_names(run_plain) is None          # **keywords with no option object
    with pytest.raises(KeyError, match="'c'"):
        option_default(run, "c")
    names = set(option_names(evolve_cooling_fem) or ())
    assert {f.name for f in dataclasses.fields(CoolingEvolveOptions)} <= names
    assert {"initial", "protocol", "initial_temperature", "times"} <= names
    state = {f.name for f in dataclasses.fields(VelocityDistribution)}
    assert not (state - {"times"}) & names            # the state's fields are not options
    assert not state & set(option_names(solve_fem_cooling) or ())
    with pytest.raises(TypeError, match="option_group takes a dataclass"):
        option_group(int)
