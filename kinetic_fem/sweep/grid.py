"""Grid points of a parameter sweep: the outer product, canonical keys and derived seeds.

A grid is a mapping ``name -> values`` (e.g. ``{"alpha": [0.3, 0.6], "kernel": [0, 1]}``);
its points are the outer product of the values in the order of the mapping (the last
name varies fastest, as in :func:`itertools.product`).  Each point has a canonical key,
the JSON text of ``{name: value}`` with sorted names and exact float representations,
from which its store file name and its random seed are derived, so both depend on the
point only, never on the order in which points finish or on the number of workers.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import numbers
from typing import Any, Mapping

import numpy as np
from numpy.typing import NDArray

__all__ = ["grid_points", "point_key", "point_seed", "canonical_value"]


def canonical_value(value: Any, name: str = "value") -> bool | int | float | str:
    """A grid value as a plain Python ``bool``, ``int``, ``float`` or ``str``.

    Parameters
    ----------
    value : bool, int, float or str (or a numpy scalar of those)
        The grid value.
    name : str
        Name of the grid dimension, used in the error message.

    Returns
    -------
    bool, int, float or str

    Raises
    ------
    TypeError
        For anything else (arrays, objects): grid values must be scalars.
    """
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, numbers.Integral):
        return int(value)
    if isinstance(value, numbers.Real):
        return float(value)
    if isinstance(value, str):
        return value
    raise TypeError(f"grid values must be numbers, booleans or strings; {name} has "
                    f"{type(value).__name__} {value!r} (pass objects as fixed options)")


def grid_points(grid: Mapping[str, Any]
                ) -> tuple[dict[str, NDArray[Any]], list[dict[str, Any]]]:
    """Coordinates and points of the outer product of ``grid``.

    Parameters
    ----------
    grid : mapping of str to sequence
        Parameter name -> one-dimensional sequence of distinct scalar values (a single
        scalar counts as one value).

    Returns
    -------
    coords : dict of str to ndarray
        The values of each name, in the order given.
    points : list of dict
        ``prod(len(values))`` points, the last name varying fastest.

    Raises
    ------
    TypeError, ValueError
        For an empty grid, a name that is not an identifier, empty or repeated values,
        or values of different kinds (numbers, bools, strings) under one name.

    Examples
    --------
    >>> coords, points = grid_points({"alpha": [0.3, 0.6], "kernel": [0, 1]})
    >>> len(points), points[1]
    (4, {'alpha': 0.3, 'kernel': 1})
    """
    if not isinstance(grid, Mapping) or not grid:
        raise TypeError(f"grid must be a non-empty dict of name -> values, got {grid!r}")
    coords: dict[str, NDArray[Any]] = {}
    values_of: dict[str, list[Any]] = {}
    for name, values in grid.items():
        if not isinstance(name, str) or not name.isidentifier():
            raise ValueError(f"grid names must be Python identifiers, got {name!r}")
        if isinstance(values, (str, bytes)) or np.ndim(values) == 0:
            values = [values]
        vals = [canonical_value(v, name) for v in values]
        if not vals:
            raise ValueError(f"grid[{name!r}] is empty; give at least one value")
        if len(set(map(repr, vals))) != len(vals):
            raise ValueError(f"grid[{name!r}] repeats a value: {vals}")
        kinds = {"bool" if isinstance(v, bool) else "str" if isinstance(v, str) else "number"
                 for v in vals}
        if len(kinds) > 1:  # an array would turn 0.5 into '0.5', or True into 1
            raise TypeError(f"grid[{name!r}] mixes {' and '.join(sorted(kinds))} values "
                            f"{vals}: give one kind per name (a bool is not the number 1)")
        if kinds == {"number"} and any(isinstance(v, float) for v in vals):
            vals = [float(v) for v in vals]  # one dtype, as the coordinate holds them
        coords[name] = np.asarray(vals)
        values_of[name] = vals
    points = [dict(zip(values_of, combo, strict=True))
              for combo in itertools.product(*values_of.values())]
    return coords, points


def point_key(point: Mapping[str, Any]) -> str:
    """Canonical text of a point: sorted JSON with exact floats.

    >>> point_key({"kernel": 1, "alpha": 0.5})
    '{"alpha": 0.5, "kernel": 1}'

    Parameters
    ----------
    point : mapping of str to scalar
        One grid point.

    Returns
    -------
    str
    """
    return json.dumps({k: canonical_value(v, k) for k, v in point.items()}, sort_keys=True)


def point_seed(point: Mapping[str, Any], root: int | None = None) -> int:
    """A 63-bit seed derived from the point (and an optional root seed) by SHA-256.

    The same point always gets the same seed, whatever the executor, the number of
    workers or the order of completion; distinct points get independent seeds.

    >>> point_seed({"alpha": 0.5}) == point_seed({"alpha": 0.5})
    True
    >>> point_seed({"alpha": 0.5}) != point_seed({"alpha": 0.5}, root=1)
    True

    Parameters
    ----------
    point : mapping of str to scalar
        One grid point.
    root : int, optional
        Root seed of the sweep.

    Returns
    -------
    int
    """
    text = point_key(point) if root is None else f"{int(root)}|{point_key(point)}"
    digest = hashlib.sha256(text.encode()).digest()
    return int.from_bytes(digest[:8], "little") & (2**63 - 1)
