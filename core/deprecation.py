"""Renamed keywords and names: the old spelling keeps working for a while, with a ``DeprecationWarning``.

:func:`renamed_keyword` decorates a function (the old keyword is passed on under the new name)
or a frozen dataclass (its constructor takes the old keyword, and a read-only property of the
old name returns the new field). Either way the warning names the old and the new spelling.
:func:`renamed_names` serves a module's old names, and :func:`moved_names` the names of a module
that moved, from its new place.
"""

from __future__ import annotations

import functools
import warnings
from collections.abc import Callable, Iterable
from types import ModuleType
from typing import Any, TypeVar

__all__ = ["moved_names", "renamed_keyword", "renamed_names"]

T = TypeVar("T")


def _message(owner: str, old: str, new: str) -> str:
    return f"{owner}: '{old}' is deprecated, use '{new}' (the same values and units)"


def _renamed_call(func: Callable, owner: str, old: str, new: str) -> Callable:
    @functools.wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        if old in kwargs:
            if new in kwargs:
                raise TypeError(f"{owner}: give '{new}' only, not both '{new}' and '{old}'")
            # stacklevel 2: the warning points at the caller that still spells it the old way
            warnings.warn(_message(owner, old, new), DeprecationWarning, stacklevel=2)
            kwargs[new] = kwargs.pop(old)
        return func(*args, **kwargs)

    return wrapper


def _old_attribute(owner: str, old: str, new: str) -> property:
    def getter(self: Any) -> Any:
        warnings.warn(_message(owner, old, new), DeprecationWarning, stacklevel=2)
        return getattr(self, new)

    getter.__doc__ = f"Deprecated spelling of :attr:`{new}` (warns)."
    return property(getter)


def renamed_keyword(*, old: str, new: str) -> Callable[[T], T]:
    """A decorator that accepts keyword ``old`` as ``new``, with a ``DeprecationWarning``.

    Parameters
    ----------
    old
        The keyword's former spelling (e.g. ``"pressures_MPa"``).
    new
        Its spelling now (e.g. ``"pressures"``).

    Returns
    -------
    Callable
        A decorator. On a function, a call with ``old=...`` warns once and runs as
        ``new=...``. On a class (a frozen dataclass with a field ``new``), the constructor does
        the same, and the class gains a read-only property ``old`` that warns and returns the
        field ``new``. Giving both spellings raises ``TypeError``.
    """
    if not (old.isidentifier() and new.isidentifier()) or old == new:
        raise ValueError(f"renamed_keyword: old = {old!r}, new = {new!r}: must be two distinct identifiers")

    def decorate(target: T) -> T:
        owner = getattr(target, "__qualname__", repr(target))
        if isinstance(target, type):
            if hasattr(target, old) or old in getattr(target, "__dataclass_fields__", {}):
                raise TypeError(f"renamed_keyword: {owner} already has an attribute {old!r}")
            # setattr: type checkers refuse a plain assignment to a class's __init__
            setattr(target, "__init__", _renamed_call(target.__init__, owner, old, new))  # noqa: B010
            setattr(target, old, _old_attribute(owner, old, new))
            return target
        if not callable(target):
            raise TypeError(f"renamed_keyword: {owner} is neither a class nor a function")
        return _renamed_call(target, owner, old, new)

    return decorate


def renamed_names(module: str, /, **renamed: Any) -> Callable[[str], Any]:
    """A module ``__getattr__`` that serves each old name as its new object, with a ``DeprecationWarning``.

    Parameters
    ----------
    module
        The module's ``__name__`` (for the messages).
    **renamed
        Old name -> the object now under its own name (e.g. ``BendCurve=NonlinearFemCurve``).

    Returns
    -------
    Callable
        Assign it to the module's ``__getattr__``; any other unknown name raises ``AttributeError``.
    """

    def module_getattr(name: str) -> Any:
        if name in renamed:
            new = renamed[name]
            # stacklevel 2: the warning points at the code that still uses the old name
            warnings.warn(
                f"{module}.{name} is deprecated: use {new.__name__}", DeprecationWarning, stacklevel=2
            )
            return new
        raise AttributeError(f"module {module!r} has no attribute {name!r}")

    return module_getattr


def moved_names(module: str, new: ModuleType, names: Iterable[str], /) -> Callable[[str], Any]:
    """A module ``__getattr__`` for a module that moved: its names come from the new module, with a warning.

    The old module keeps no names of its own, so importing it (or walking the package tree, as
    the API reference and the import checks do) is silent; using one of its names warns.

    Parameters
    ----------
    module
        The old module's ``__name__`` (for the messages).
    new
        The module where its names are now.
    names
        The names the old module exported; each must exist in ``new``.

    Returns
    -------
    Callable
        Assign it to the old module's ``__getattr__``: a name of ``names`` warns with a
        ``DeprecationWarning`` naming ``new`` and returns ``new``'s object; any other name
        raises ``AttributeError``.

    Raises
    ------
    ValueError
        A name of ``names`` that ``new`` does not have (the stand-in would serve nothing).
    """
    served = frozenset(names)
    missing = sorted(n for n in served if not hasattr(new, n))
    if missing:
        raise ValueError(f"moved_names: names = {missing}: not in {new.__name__}")

    def module_getattr(name: str) -> Any:
        if name in served:
            # stacklevel 2: the warning points at the code that still imports the old place
            warnings.warn(
                f"{module} is deprecated: it moved to {new.__name__} (import {name} from there)",
                DeprecationWarning,
                stacklevel=2,
            )
            return getattr(new, name)
        raise AttributeError(f"module {module!r} has no attribute {name!r}")

    return module_getattr
