"""Options that travel together: typed objects, and the keywords that name their fields.

A solver takes the options that belong together (a mesh's degree, spacing and cut-off;
Newton's tolerance and iteration limit) as one frozen dataclass, and still takes each of
them by keyword, as users pass them (``kf.solve_heated(0.5, spacing=0.2)``).  One rule
turns the keywords into the object and refuses the names it does not know
(:func:`gather`; :func:`gather_groups` for several objects); :func:`option_names` lists
every name a function takes, its own parameters and the fields of its option objects,
for the command line's check of ``-o KEY=VALUE``; :func:`option_default` gives the default
of one of them.
"""

from __future__ import annotations

import dataclasses
import inspect
import typing
from collections.abc import Callable, Mapping, Sequence
from typing import Any, TypeVar

__all__ = ["option_group", "is_option_group", "gather", "gather_groups", "option_names",
           "option_default"]

T = TypeVar("T")

_MARK = "__option_group__"


def option_group(cls: type[T]) -> type[T]:
    """Mark a frozen dataclass as an option object: a function that takes it (with a
    default) and ``**keywords`` accepts its fields by keyword (:func:`gather`), so
    :func:`option_names` and :func:`option_default` list them.

    A dataclass argument that is not marked (a state, a protocol, a problem) is an
    argument, not a group of keywords, whether or not it has a default.

    Parameters
    ----------
    cls : dataclass type

    Returns
    -------
    cls
        The same class, marked (subclasses inherit the mark).

    Raises
    ------
    TypeError
        If ``cls`` is not a dataclass.

    Examples
    --------
    >>> @option_group
    ... @dataclasses.dataclass(frozen=True)
    ... class Grid:
    ...     spacing: float = 0.1
    >>> is_option_group(Grid), is_option_group(int)
    (True, False)
    """
    if not (isinstance(cls, type) and dataclasses.is_dataclass(cls)):
        raise TypeError(f"option_group takes a dataclass, got {cls!r}")
    setattr(cls, _MARK, True)
    return cls


def is_option_group(cls: Any) -> bool:
    """Whether ``cls`` is a class marked by :func:`option_group`."""
    return isinstance(cls, type) and dataclasses.is_dataclass(cls) and \
        bool(getattr(cls, _MARK, False))


def gather(cls: type[T], given: T | None, keywords: Mapping[str, Any], where: str) -> T:
    """``given`` (or the defaults of ``cls``) with the fields that ``keywords`` name.

    Parameters
    ----------
    cls : dataclass type
        The options' class.
    given : cls, optional
        The options passed as one object.
    keywords : mapping
        Fields of ``cls`` passed by keyword (they override ``given``).
    where : str
        The function's name, for the message.

    Returns
    -------
    cls

    Raises
    ------
    TypeError
        For a keyword that is not a field of ``cls``, naming the allowed ones.

    Examples
    --------
    >>> @dataclasses.dataclass(frozen=True)
    ... class Mesh:
    ...     order: int = 2
    ...     spacing: float | None = None
    >>> gather(Mesh, None, {"spacing": 0.1}, "solve")
    Mesh(order=2, spacing=0.1)
    >>> gather(Mesh, Mesh(order=3), {"spacing": 0.1}, "solve")
    Mesh(order=3, spacing=0.1)
    >>> gather(Mesh, None, {"spacnig": 0.1}, "solve")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    TypeError: solve() got an unexpected keyword argument 'spacnig'; its Mesh options ...
    """
    names = [f.name for f in dataclasses.fields(cls)]  # type: ignore[arg-type]
    unknown = sorted(set(keywords) - set(names))
    if unknown:
        raise TypeError(f"{where}() got an unexpected keyword argument {unknown[0]!r}; its "
                        f"{cls.__name__} options are {names}")
    if given is None:
        return cls(**keywords)
    if not isinstance(given, cls):
        raise TypeError(f"{where}() takes its options as a {cls.__name__}, got "
                        f"{type(given).__name__}")
    return dataclasses.replace(given, **keywords)  # type: ignore[type-var]


def gather_groups(groups: Sequence[tuple[type, Any]], keywords: Mapping[str, Any],
                  where: str) -> tuple[Any, ...]:
    """:func:`gather` for a function with several option objects: each keyword goes to
    the first group with a field of its name.

    Parameters
    ----------
    groups : sequence of (dataclass type, given or None)
        The options' classes, each with the object passed (None: its defaults).
    keywords : mapping
        Fields of any of the classes passed by keyword.
    where : str
        The function's name, for the message.

    Returns
    -------
    tuple
        One object per group, in order.

    Raises
    ------
    TypeError
        For a keyword that is no group's field, naming the allowed ones.

    Examples
    --------
    >>> @dataclasses.dataclass(frozen=True)
    ... class Grid:
    ...     spacing: float = 0.1
    >>> @dataclasses.dataclass(frozen=True)
    ... class Steps:
    ...     dt: float = 1.0
    >>> gather_groups(((Grid, None), (Steps, Steps(dt=2.0))), {"spacing": 0.2}, "run")
    (Grid(spacing=0.2), Steps(dt=2.0))
    >>> gather_groups(((Grid, None), (Steps, None)), {"dx": 0.2}, "run")
    Traceback (most recent call last):
    ...
    TypeError: run() got an unexpected keyword argument 'dx'; its options are ['spacing', 'dt']
    """
    fields = [[f.name for f in dataclasses.fields(cls)] for cls, _ in groups]
    allowed = [name for names in fields for name in names]
    unknown = [name for name in keywords if name not in allowed]
    if unknown:
        raise TypeError(f"{where}() got an unexpected keyword argument {unknown[0]!r}; its "
                        f"options are {allowed}")
    out = []
    taken: set[str] = set()
    for (cls, given), names in zip(groups, fields, strict=True):
        mine = {k: v for k, v in keywords.items() if k in names and k not in taken}
        taken |= set(mine)
        out.append(gather(cls, given, mine, where))
    return tuple(out)


def _option_groups(function: Callable[..., Any]) -> list[type] | None:
    """The option objects' classes of ``function``: its parameters with a default typed
    by a class marked :func:`option_group` (a required one, such as the problem, and a
    dataclass that is not an option object, such as a start state or a protocol, are
    arguments, not groups of keywords); None if its annotations cannot be resolved."""
    params = inspect.signature(function).parameters
    try:
        hints = typing.get_type_hints(function)
    except Exception:  # noqa: BLE001 (unresolvable annotations: no names to add)
        return None
    optional = [n for n, p in params.items() if p.default is not p.empty]
    return [arg for name in optional for arg in typing.get_args(hints.get(name)) or
            (hints.get(name),) if is_option_group(arg)]


def option_names(function: Callable[..., Any]) -> list[str] | None:
    """The keywords ``function`` takes: its named parameters, and for a ``**keywords``
    parameter the fields of its option objects (its parameters with a default typed by
    an :func:`option_group` class; other dataclass arguments add no names).

    Parameters
    ----------
    function : callable

    Returns
    -------
    list of str or None
        Sorted names; None if ``function`` takes any keyword (a ``**keywords`` parameter
        with no option object to name them) or has no signature.
    """
    try:
        params = inspect.signature(function).parameters
    except (TypeError, ValueError):
        return None
    names = {n for n, p in params.items()
             if p.kind in (p.KEYWORD_ONLY, p.POSITIONAL_OR_KEYWORD)}
    if not any(p.kind is p.VAR_KEYWORD for p in params.values()):
        return sorted(names)
    groups = _option_groups(function)
    if not groups:
        return None
    for group in groups:
        names |= {f.name for f in dataclasses.fields(group)}
    return sorted(names)


def option_default(function: Callable[..., Any], name: str) -> Any:
    """The default of the keyword ``name`` of ``function``: of its parameter of that
    name, else of the field of that name of its first option object that has one.

    Parameters
    ----------
    function : callable
    name : str

    Returns
    -------
    object

    Raises
    ------
    KeyError
        If ``function`` takes no keyword ``name`` with a default.

    Examples
    --------
    >>> @option_group
    ... @dataclasses.dataclass(frozen=True)
    ... class Steps:
    ...     rtol: float = 1e-6
    >>> def run(x: float, options: Steps | None = None, **keywords: Any) -> None:
    ...     pass
    >>> option_default(run, "rtol")
    1e-06
    """
    params = inspect.signature(function).parameters
    param = params.get(name)
    if param is not None and param.default is not param.empty:
        return param.default
    if param is None and any(p.kind is p.VAR_KEYWORD for p in params.values()):
        for group in _option_groups(function) or ():
            for f in dataclasses.fields(group):
                if f.name == name and f.default is not dataclasses.MISSING:
                    return f.default
    raise KeyError(f"{getattr(function, '__name__', function)!r} has no default {name!r}")
