"""Point-by-point persistence of a sweep: one small netCDF file per finished point.

Layout of a store directory::

    sweep.json          what the store holds: function, fixed options, c-grid
    point-<hash>.nc     one finished point (netCDF3, written by xarray's scipy engine)

Each point file is written whole to a temporary name in the same directory, flushed to
disk (``fsync``) and renamed over its final name with :func:`os.replace`, which is
atomic on POSIX file systems: a reader sees either no file or a complete one, and
processes never write the same file, so any number of sweeps (or a killed one and its
rerun) can share a store without locks (two sweeps running at once may compute the same
point twice; each rename leaves a complete file).  Every file
carries the SHA-256 checksum of its point key and data; a file that cannot be read or
whose checksum does not match (a truncated copy, a disk error) is logged, removed and
recomputed, never read as data.
"""

from __future__ import annotations

import hashlib
import io
import json
import logging
import os
import secrets
from pathlib import Path
from typing import Any, Mapping

import numpy as np
from numpy.typing import NDArray

__all__ = ["PointStore", "record_checksum", "point_filename"]

logger = logging.getLogger(__name__)

MANIFEST = "sweep.json"
FORMAT_VERSION = 1


def record_checksum(key: str, data: Mapping[str, NDArray[Any]]) -> str:
    """SHA-256 of a point key and its arrays (names, shapes and little-endian float64 bytes).

    Parameters
    ----------
    key : str
        Canonical key of the point.
    data : mapping of str to ndarray
        The point's arrays.

    Returns
    -------
    str
        Hexadecimal digest.
    """
    h = hashlib.sha256(key.encode())
    for name in sorted(data):
        a = np.ascontiguousarray(data[name], dtype="<f8")
        h.update(f"|{name}:{a.shape}|".encode())
        h.update(a.tobytes())
    return h.hexdigest()


def point_filename(key: str) -> str:
    """File name of the point with canonical key ``key`` inside a store directory.

    Parameters
    ----------
    key : str
        Canonical key of the point (:func:`kinetic_fem.sweep.grid.point_key`).

    Returns
    -------
    str
    """
    return f"point-{hashlib.sha256(key.encode()).hexdigest()[:20]}.nc"


def _write_atomic(path: Path, payload: bytes | memoryview) -> None:
    # a unique temporary name; mode 0o666 less the umask (mkstemp would give 0o600)
    tmp = path.parent / f".{path.name}.{os.getpid()}.{secrets.token_hex(6)}.tmp"
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(payload)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


class PointStore:
    """A directory of finished sweep points.

    Parameters
    ----------
    path : str or Path
        The store directory (created if missing).
    manifest : dict
        JSON-serialisable description of the sweep (function, fixed options, c-grid).
        A store created for another sweep raises ``ValueError`` instead of mixing points.
    """

    def __init__(self, path: str | Path, manifest: Mapping[str, Any]) -> None:
        self.path = Path(path)
        if self.path.exists() and not self.path.is_dir():
            raise ValueError(f"store {str(self.path)!r} exists and is not a directory")
        self.path.mkdir(parents=True, exist_ok=True)
        want = {"format": FORMAT_VERSION, **manifest}
        file = self.path / MANIFEST
        if file.exists():
            try:
                have = json.loads(file.read_text())
            except (OSError, ValueError) as exc:
                raise ValueError(f"store manifest {file} is unreadable ({exc}); remove it "
                                 "to reuse this store") from exc
            if have != json.loads(json.dumps(want)):
                diff = {k: (have.get(k), want.get(k)) for k in {*have, *want}
                        if have.get(k) != json.loads(json.dumps(want)).get(k)}
                raise ValueError(f"store {str(self.path)!r} holds another sweep; differences "
                                 f"(stored, requested): {diff}; use a new store path or the "
                                 "same function and fixed options")
        else:
            _write_atomic(file, json.dumps(want, indent=1, sort_keys=True).encode())

    def file_of(self, key: str) -> Path:
        """The file of the point with canonical key ``key``."""
        return self.path / point_filename(key)

    def save(self, key: str, data: Mapping[str, NDArray[Any]],
             attrs: Mapping[str, str]) -> Path:
        """Write one point atomically; ``data`` holds float arrays, ``attrs`` strings."""
        import xarray as xr

        dims = {"f": ("c",), "f_error": ("c",), "sonine": ("p",),
                **{name: ("species",) for name in ("T_species", "T_species_error",
                                                   "a2_species", "a2_species_error")}}
        ds = xr.Dataset({name: (dims.get(name, ()), np.asarray(a, dtype=float))
                         for name, a in data.items()})
        ds.attrs.update({**attrs, "point": key, "sha256": record_checksum(key, data)})
        path = self.file_of(key)
        _write_atomic(path, ds.to_netcdf(engine="scipy"))
        return path

    def load(self, key: str) -> tuple[dict[str, NDArray[np.float64]], dict[str, str]] | None:
        """The stored point ``(data, attrs)``, or None if absent or damaged (then removed)."""
        import xarray as xr

        path = self.file_of(key)
        if not path.exists():
            return None
        try:
            with xr.open_dataset(io.BytesIO(path.read_bytes()), engine="scipy") as ds:
                data = {name: np.asarray(var.values, dtype=float)
                        for name, var in ds.data_vars.items()}
                attrs = {k: str(v) for k, v in ds.attrs.items()}
            ok = attrs.get("point") == key and attrs.get("sha256") == record_checksum(key, data)
            reason = "checksum or point key does not match"
        except Exception as exc:  # any unreadable file is recomputed
            ok, reason = False, f"{type(exc).__name__}: {exc}"
        if not ok:
            logger.warning("store file %s is damaged (%s): removed, the point is recomputed",
                           path, reason)
            path.unlink(missing_ok=True)
            return None
        attrs = {k: v for k, v in attrs.items() if k not in {"point", "sha256"}}
        return data, attrs
