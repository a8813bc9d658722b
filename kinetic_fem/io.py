"""Export and import of velocity distributions with meshio (VTU, XDMF).

A :class:`~kinetic_fem.VelocityDistribution` is written as a *line mesh* in
velocity space: the nodes are the points :math:`(v_j, 0, 0)`, consecutive nodes
are joined by ``line`` cells, and the point data are

.. math::

    P(v_j), \\qquad c_j = (v_j - u)/\\sqrt{T}, \\qquad f(c_j) = \\sqrt{T}\\, P(v_j)

(plus ``P_error`` and ``f_error`` for sampled distributions), ready for ParaView or
any meshio reader.  What a mesh file cannot hold (raw and batch moments, method,
parameters, run information and the time series in ``series``) goes into a JSON
sidecar ``<file>.json`` beside it, with every float written by :func:`repr`, so
:func:`read_distribution` restores the distribution exactly (bitwise).

VTU is written as compressed binary; XDMF as a one-step temporal collection with
XML text data of 17 significant digits (exact for float64, and no HDF5 library
needed: meshio's single-grid XDMF reader and writer would require ``h5py``).

:func:`write_time_series` writes a sequence of distributions on one velocity mesh
(a transient of a time-stepping solver) as an XDMF time series.
"""

from __future__ import annotations

import json
from dataclasses import asdict
from pathlib import Path
from typing import Any, Mapping, Sequence

import meshio
import numpy as np
from numpy.typing import ArrayLike, NDArray

from .distribution import RunInfo, VelocityDistribution
from .exceptions import FileFormatError
from .files import check_loaded_values, output_path, reading
from .gas import check_finite_array

__all__ = ["FileFormatError", "FORMATS", "write_distribution", "read_distribution",
           "write_time_series", "read_time_series", "sidecar_path"]

FORMATS = {".vtu": "vtu", ".xdmf": "xdmf"}
"""File suffixes understood by :func:`write_distribution` and the meshio format used."""

_SCHEMA = "kinetic_fem.io/1"


def sidecar_path(path: str | Path) -> Path:
    """The JSON sidecar that holds what the mesh file cannot: ``<path>.json``.

    Parameters
    ----------
    path : str or Path
        A mesh file path.

    Returns
    -------
    Path

    Examples
    --------
    >>> sidecar_path("run/alpha0.9.vtu").as_posix()
    'run/alpha0.9.vtu.json'
    """
    path = Path(path)
    return path.with_name(path.name + ".json")


def _format_of(path: Path) -> str:
    try:
        return FORMATS[path.suffix.lower()]
    except KeyError:
        raise ValueError(f"cannot tell the format of {str(path)!r}: the suffix must be one of "
                         f"{sorted(FORMATS)}") from None


def _line_mesh(v: NDArray[np.float64], point_data: dict[str, NDArray[np.float64]]
               ) -> meshio.Mesh:
    points = np.zeros((v.size, 3))
    points[:, 0] = v
    cells = np.column_stack([np.arange(v.size - 1), np.arange(1, v.size)])
    return meshio.Mesh(points, [("line", cells)], point_data=point_data)


def _point_data(dist: VelocityDistribution) -> dict[str, NDArray[np.float64]]:
    data = {"P": dist.values, "c": dist.c, "f": dist.f_values}
    f_errors = dist.f_errors
    if dist.errors is not None and f_errors is not None:
        data["P_error"] = dist.errors
        data["f_error"] = f_errors
    return data


def _floats(a: NDArray[Any] | None) -> Any:
    """Nested lists of Python floats (``json`` writes them with ``repr``: exact)."""
    return None if a is None else np.asarray(a, dtype=float).tolist()


def _array(x: Any) -> NDArray[np.float64] | None:
    return None if x is None else np.asarray(x, dtype=float)


def _json_default(obj: Any) -> Any:
    """numpy scalars and arrays in ``params``/``info.extra`` as plain Python values."""
    if isinstance(obj, (np.generic, np.ndarray)):
        return obj.tolist()
    raise TypeError(f"{type(obj).__name__} {obj!r} cannot be stored in the JSON sidecar")


def _meta(dist: VelocityDistribution) -> dict[str, Any]:
    return {
        "schema": _SCHEMA,
        "method": dist.method,
        "params": dict(dist.params),
        "info": asdict(dist.info),
        "raw_moments": _floats(dist.raw_moments),
        "batch_moments": _floats(dist.batch_moments),
        "series": {k: _floats(s) for k, s in dist.series.items()},
    }


def write_distribution(dist: VelocityDistribution, path: str | Path) -> Path:
    """Write ``dist`` as a line mesh in ``v`` (VTU or XDMF, by suffix) plus a JSON sidecar.

    Parameters
    ----------
    dist : VelocityDistribution
        Any distribution (deterministic or sampled).
    path : str or Path
        Target file ending in ``.vtu`` or ``.xdmf``; the sidecar is
        :func:`sidecar_path` (``path + ".json"``).

    Returns
    -------
    Path
        The mesh file written.

    Raises
    ------
    ValueError
        For an unknown suffix.
    TypeError
        If ``dist`` is not a :class:`VelocityDistribution`.
    OSError
        If the directory does not exist or is not writable
        (:func:`kinetic_fem.files.output_path`).

    Examples
    --------
    >>> import tempfile, os
    >>> v = np.linspace(-8, 8, 161)
    >>> d = VelocityDistribution.from_values(v, np.exp(-v**2 / 2), method="demo")
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     p = write_distribution(d, os.path.join(tmp, "gauss.vtu"))
    ...     back = read_distribution(p)
    >>> bool(np.array_equal(back.values, d.values)), back.method
    (True, 'demo')
    """
    if not isinstance(dist, VelocityDistribution):
        raise TypeError(f"dist must be a VelocityDistribution, got {type(dist).__name__}")
    path = output_path(path)
    fmt = _format_of(path)
    if fmt == "xdmf":
        _write_xdmf(path, [0.0], [dist])
    else:
        meshio.write(path, _line_mesh(dist.v, _point_data(dist)), file_format=fmt)
    sidecar_path(path).write_text(json.dumps(_meta(dist), indent=1, default=_json_default))
    return path


def read_distribution(path: str | Path) -> VelocityDistribution:
    """Read a distribution written by :func:`write_distribution`, exactly.

    ``v`` comes from the mesh points, ``values`` and ``errors`` from the point data
    ``P`` and ``P_error``, everything else from the JSON sidecar.

    Parameters
    ----------
    path : str or Path
        The mesh file (``.vtu`` or ``.xdmf``) written by :func:`write_distribution`; its
        sidecar ``<path>.json`` must lie beside it.

    Returns
    -------
    VelocityDistribution
        The distribution as it was written (values, errors, info and parameters).

    Raises
    ------
    FileNotFoundError
        If the mesh file or its sidecar is missing.
    FileFormatError
        If the file or its sidecar is damaged, foreign (not a line mesh written by this
        module) or holds non-finite values (a ``ValueError``).
    """
    path = Path(path)
    fmt = _format_of(path)
    side = sidecar_path(path)
    if not path.exists():
        raise FileNotFoundError(f"{str(path)!r} does not exist")
    if not side.exists():
        raise FileNotFoundError(f"{str(side)!r} (the metadata sidecar of {str(path)!r}) is "
                                "missing; files not written by kinetic_fem.io cannot be read")
    with reading(side, "kinetic_fem.io JSON sidecar"):
        meta = json.loads(side.read_text())
    if not isinstance(meta, dict) or meta.get("schema") != _SCHEMA:
        got = meta.get("schema") if isinstance(meta, dict) else type(meta).__name__
        raise FileFormatError(f"{str(side)!r} is not a kinetic_fem.io sidecar "
                              f"(schema {got!r}, expected {_SCHEMA!r})")
    point_data: Mapping[str, Any]
    with reading(path, f"{fmt.upper()} line mesh of kinetic_fem.io"):
        if fmt == "xdmf":
            v, steps = _read_xdmf(path, last_only=True)
            point_data = steps[-1]
        else:
            mesh = meshio.read(path, file_format=fmt)
            v, point_data = mesh.points[:, 0], mesh.point_data
    if "P" not in point_data:
        raise FileFormatError(f"{str(path)!r} holds no point data 'P'")
    errors = point_data.get("P_error")
    with reading(side, "kinetic_fem.io JSON sidecar"):
        info = dict(meta["info"])
        info["residual"] = float(info["residual"])
        info["wall_time"] = float(info["wall_time"])
        raw = np.asarray(meta["raw_moments"], dtype=np.float64)
        batch = _array(meta["batch_moments"])
        series = {k: np.asarray(s, dtype=np.float64) for k, s in meta["series"].items()}
    check_loaded_values(path, v=v, P=point_data["P"], P_error=errors)
    check_loaded_values(side, raw_moments=raw, batch_moments=batch)
    with reading(path, "distribution of kinetic_fem.io"):
        return VelocityDistribution(
            v=np.ascontiguousarray(v, dtype=float),
            values=np.asarray(point_data["P"], dtype=np.float64),
            raw_moments=raw,
            errors=None if errors is None else np.asarray(errors, dtype=float),
            batch_moments=batch,
            method=meta["method"],
            params=meta["params"],
            info=RunInfo(**info),
            series=series,
        )


def write_time_series(path: str | Path, times: ArrayLike,
                      distributions: Sequence[VelocityDistribution]) -> Path:
    """Write distributions on one velocity mesh at ``times`` as an XDMF time series.

    Parameters
    ----------
    path : str or Path
        Target ``.xdmf`` file (XML data, no HDF5 needed).
    times : array_like, shape (n_t,)
        Finite, strictly increasing times.
    distributions : sequence of VelocityDistribution, length n_t
        All on the same nodes ``v``.

    Raises
    ------
    ValueError
        For a wrong suffix, mismatched lengths, non-increasing times or differing
        velocity meshes.
    """
    path = Path(path)
    if path.suffix.lower() != ".xdmf":
        raise ValueError(f"time series are written as .xdmf, got {str(path)!r}")
    t = check_finite_array("times", times, ndim=1)
    dists = list(distributions)
    if len(dists) != t.size or t.size == 0:
        raise ValueError(f"need one distribution per time: {len(dists)} distributions, "
                         f"{t.size} times")
    if np.any(np.diff(t) <= 0):
        raise ValueError("times must be strictly increasing")
    v = dists[0].v
    if any(d.v.shape != v.shape or not np.array_equal(d.v, v) for d in dists):
        raise ValueError("all distributions of a time series must share the velocity mesh")
    _write_xdmf(path, t, dists)
    return path


def _write_xdmf(path: Path, times: Sequence[float] | NDArray[np.float64],
                dists: Sequence[VelocityDistribution]) -> None:
    mesh = _line_mesh(dists[0].v, {})
    with meshio.xdmf.TimeSeriesWriter(path, data_format="XML") as writer:
        writer.write_points_cells(mesh.points, mesh.cells)
        for ti, d in zip(times, dists, strict=True):
            writer.write_data(float(ti), point_data=_point_data(d))


def _read_xdmf(path: Path, *, last_only: bool = False
               ) -> tuple[NDArray[np.float64], list[dict[str, NDArray[np.float64]]]]:
    """Nodes and per-step point data of an XDMF time series (times in ``"_t"``)."""
    steps = []
    with meshio.xdmf.TimeSeriesReader(path) as reader:
        points, _ = reader.read_points_cells()
        first = reader.num_steps - 1 if last_only else 0
        for k in range(first, reader.num_steps):
            t, point_data, _ = reader.read_data(k)
            steps.append({"_t": float(t), **point_data})
    return points[:, 0], steps


def read_time_series(path: str | Path) -> tuple[NDArray[np.float64], NDArray[np.float64],
                                                 NDArray[np.float64]]:
    """Read an XDMF time series of :func:`write_time_series`.

    Parameters
    ----------
    path : str or Path
        The ``.xdmf`` file written by :func:`write_time_series`.

    Returns
    -------
    times : ndarray, shape (n_t,)
    v : ndarray, shape (n_v,)
    values : ndarray, shape (n_t, n_v)
        :math:`P(v, t)` at each time.
    """
    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(f"{str(path)!r} does not exist")
    with reading(path, "XDMF time series of kinetic_fem.io"):
        v, steps = _read_xdmf(path)
    check_loaded_values(path, **{f"P at step {k}": s.get("P") for k, s in enumerate(steps)})
    times = np.array([step["_t"] for step in steps])
    values = np.array([np.asarray(step["P"], dtype=float) for step in steps])
    return times, np.asarray(v, dtype=float), values
