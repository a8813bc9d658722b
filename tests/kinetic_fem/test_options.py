"""Options that travel together: one object, or its fields by keyword (kinetic_fem.options)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from kinetic_fem.options import gather, gather_groups, option_names
from kinetic_fem.solvers.fem.cooling import solve_fem_cooling
from kinetic_fem.solvers.fem.heated import solve_fem_heated, steady_state
from kinetic_fem.solvers.fem.options import MeshOptions
from kinetic_fem.solvers.finite_difference import FDScheme, MarchOptions, solve_fd_heated


@dataclasses.dataclass(frozen=True)
class _Opts:
    a: int = 1
    b: float | None = None


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
