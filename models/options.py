"""Tier options as every command takes them: ``NAME=VALUE`` texts and ``{tier: {name: value}}`` tables.

A tier's :attr:`~softcath.models.Tier.options` (name -> default) are the only options it
takes; this module reads them from a command line (``--model-option NAME=VALUE`` or
``--model-option TIER.NAME=VALUE``, repeatable) and from a table (a sweep's
``[sweep.options.<tier>]``), coerces each value to its default's type and checks it
against the tier (its :attr:`~softcath.models.Tier.option_choices`). The result is one
mapping, tier name -> options, that the library functions behind the commands take as
``options`` and hand to :meth:`~softcath.models.Tier.responses`; a new option of a tier
reaches every command without further edits.

>>> from softcath import models
>>> models.parse_tier_options(["mesh_size=0.1"], tiers=["section"])
{'section': {'mesh_size': 0.1}}
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from typing import Any

from softcath.design.errors import DesignError
from softcath.models.tier import REGISTERED, Tier

__all__ = ["check_tier_options", "coerce_option", "options_of", "parse_tier_options"]

_TRUE = ("true", "yes", "on", "1")
_FALSE = ("false", "no", "off", "0")


def _known(tier: Tier) -> str:
    if not tier.options:
        return f"{tier.name} takes no options"
    return f"{tier.name} takes the options " + ", ".join(
        f"{k} (default {v!r})" for k, v in tier.options.items()
    )


def _from_text(text: str, default: Any, parameter: str) -> Any:
    """``text`` read as a value of ``default``'s type (a ``None`` default: a number, a flag or text)."""
    t = text.strip()
    if isinstance(default, bool) or default is None and t.lower() in _TRUE + _FALSE:
        if t.lower() in _TRUE + _FALSE:
            return t.lower() in _TRUE
        raise DesignError(parameter, text, "must be true or false")
    if isinstance(default, int) or default is None:
        try:
            return int(t)
        except ValueError:
            if isinstance(default, int):
                raise DesignError(parameter, text, f"must be an integer (default {default})") from None
    if isinstance(default, float) or default is None:
        try:
            return float(t)
        except ValueError:
            if isinstance(default, float):
                raise DesignError(parameter, text, f"must be a number (default {default:g})") from None
    return t


def _typed(value: Any, default: Any, parameter: str) -> Any:
    """A table's ``value`` checked against ``default``'s type (an integer is a valid float)."""
    if default is None or isinstance(default, str) and isinstance(value, str):
        return value
    if isinstance(default, bool):
        if isinstance(value, bool):
            return value
        raise DesignError(parameter, value, "must be true or false")
    if isinstance(value, bool) or not isinstance(value, (int, float)) or isinstance(default, str):
        raise DesignError(parameter, value, f"must be of the type of its default {default!r}")
    if isinstance(default, int) and not isinstance(default, bool):
        if float(value) != int(value):
            raise DesignError(parameter, value, f"must be an integer (default {default})")
        return int(value)
    return float(value)


def coerce_option(tier: Tier, name: str, value: Any, *, parameter: str | None = None) -> Any:
    """``value`` of option ``name`` of ``tier``, coerced to its default's type and checked.

    A text is read (``"0.1"`` -> 0.1 for a float default, ``"true"`` for a flag); any
    other value must already be of the default's type (an integer is a valid float).

    Raises
    ------
    DesignError
        ``name`` is not an option of ``tier`` (the message names the tier and its options),
        or ``value`` is not of the default's type or not one of the option's choices.
    """
    parameter = parameter or f"{tier.name}.{name}"
    if name not in tier.options:
        raise DesignError(parameter, value, f"is not an option of {tier.name}: {_known(tier)}")
    default = tier.options[name]
    v = _from_text(value, default, parameter) if isinstance(value, str) else _typed(value, default, parameter)
    try:
        tier.check_options({name: v})
    except (
        DesignError
    ) as exc:  # named as the caller names the setting (``--model-option NAME``, a table's key)
        raise DesignError(parameter, v, exc.bound) from None
    return v


def parse_tier_options(
    items: Iterable[str], *, tiers: Sequence[str], parameter: str = "--model-option"
) -> dict[str, dict[str, Any]]:
    """``{tier: {name: value}}`` of ``NAME=VALUE`` or ``TIER.NAME=VALUE`` texts.

    Parameters
    ----------
    items
        The texts (a command's repeated ``--model-option``).
    tiers
        The tiers the command runs: ``NAME`` alone goes to each of them that takes it;
        ``TIER.NAME`` must name one of them.
    parameter
        How the command names the setting, for the refusals.

    Raises
    ------
    DesignError
        An item without ``=``, a tier the command does not run, an option none of its tiers
        takes (the message names each tier and its options) or a bad value (its bound).
    """
    run = [REGISTERED[t] for t in dict.fromkeys(tiers) if t in REGISTERED]
    out: dict[str, dict[str, Any]] = {}
    for item in items:
        key, eq, text = str(item).partition("=")
        key = key.strip()
        if not eq or not key:
            raise DesignError(parameter, item, "must be NAME=VALUE or TIER.NAME=VALUE")
        head, dot, name = key.rpartition(".")
        if dot:
            if head not in REGISTERED or head not in {t.name for t in run}:
                ran = ", ".join(t.name for t in run) or "none"
                raise DesignError(parameter, item, f"names tier {head!r}; this command runs the tiers {ran}")
            targets = [REGISTERED[head]]
        else:
            name = key
            targets = [t for t in run if name in t.options]
            if not targets:
                known = "; ".join(_known(t) for t in run) or "this command runs no model tier"
                raise DesignError(parameter, item, f"unknown option {name!r}: {known}")
        for t in targets:
            out.setdefault(t.name, {})[name] = coerce_option(t, name, text, parameter=f"{parameter} {key}")
    return out


def check_tier_options(
    table: Mapping[str, Any] | None, *, parameter: str = "options", tiers: Sequence[str] | None = None
) -> dict[str, dict[str, Any]]:
    """A ``{tier: {name: value}}`` table checked and coerced (tiers in registry order, empty ones left out).

    ``tiers`` limits the tiers the table may name (those the caller runs).

    Raises
    ------
    DesignError
        Naming ``parameter.<tier>`` or ``parameter.<tier>.<name>`` with the value and the bound.
    """
    if table is None:
        return {}
    if not isinstance(table, Mapping):
        raise DesignError(parameter, table, "must be a table of tier name -> {option: value}")
    allowed = tuple(REGISTERED) if tiers is None else tuple(tiers)
    out: dict[str, dict[str, Any]] = {}
    for name, opts in table.items():
        if name not in allowed or name not in REGISTERED:
            raise DesignError(f"{parameter}.{name}", opts, f"must name a tier run here: {', '.join(allowed)}")
        if not isinstance(opts, Mapping):
            raise DesignError(f"{parameter}.{name}", opts, "must be a table of option -> value")
        tier = REGISTERED[name]
        checked = {k: coerce_option(tier, k, v, parameter=f"{parameter}.{name}.{k}") for k, v in opts.items()}
        if checked:
            out[name] = checked
    return {n: out[n] for n in REGISTERED if n in out}


def options_of(options: Mapping[str, Mapping[str, Any]] | None, tier: str | Tier) -> dict[str, Any]:
    """The options of ``tier`` (a name or a :class:`Tier`) in a ``{tier: {name: value}}`` mapping."""
    name = tier.name if isinstance(tier, Tier) else tier
    return dict((options or {}).get(name) or {})
