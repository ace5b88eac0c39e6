"""Options every command spells the same way: DESIGN, ``--out``, pressures, seeds, progress.

DESIGN is always a command's first positional argument (a preset name such
as ``paper`` or the path of a design ``.toml``); where a command can do
without one it defaults to ``paper``. ``--out DIR`` is the one output
folder of a command that writes files.
"""

from __future__ import annotations

import argparse
import contextlib
from collections.abc import Iterator
from pathlib import Path

from softcath.core.errors import DesignError
from softcath.core.limits import check_pressure

DEFAULT_DESIGN = "paper"
DESIGN_HELP = "preset name (e.g. paper) or path to a design .toml"


def add_design(parser: argparse.ArgumentParser, *, optional: bool = False) -> None:
    """DESIGN, the first positional; ``optional`` makes it default to ``paper``."""
    if optional:
        parser.add_argument(
            "design",
            nargs="?",
            default=DEFAULT_DESIGN,
            metavar="DESIGN",
            help=f"{DESIGN_HELP} (default: paper)",
        )
    else:
        parser.add_argument("design", metavar="DESIGN", help=DESIGN_HELP)


def model_name(text: str) -> str:
    """``type`` of a ``--model`` option: a tier's name; an old spelling (``analytic``) maps to its name.

    The option's ``choices`` then refuse what is not a tier of the command
    (the names: :mod:`softcath.studies.tiers`).
    """
    from softcath.studies.tiers import (  # the library loads when a command runs, not for --help
        ALIASES,
        tier_name,
    )

    return tier_name(text, parameter="--model") if text in ALIASES else text


def add_out(parser: argparse.ArgumentParser, *, required: bool = True, what: str = "output folder") -> None:
    """``--out DIR``: where the command writes its files (created; refused if it is a file)."""
    parser.add_argument("--out", type=Path, required=required, metavar="DIR", help=what)


#: How every pressure option is written (its metavar and the bound of its refusal).
PRESSURE_SYNTAX = "P,P,... or START:STOP:N"
_PRESSURE_BOUND = (
    "expected START:STOP:N (MPa, MPa, count), one value or comma-separated numbers in MPa "
    "(items may mix both: 0,0.1:0.5:5)"
)


def add_pressure_range(parser: argparse.ArgumentParser, *, default: str) -> None:
    """``--pressure``: pressures in MPa as a list ``P,P,...``, a range ``START:STOP:N`` or both."""
    parser.add_argument(
        "--pressure", default=default, metavar=PRESSURE_SYNTAX, help=f"pressures in MPa (default {default})"
    )


def add_pressure_list(parser: argparse.ArgumentParser, *, default: str) -> None:
    """``--pressures``: the same syntax as ``--pressure`` (:func:`parse_pressures`)."""
    parser.add_argument(
        "--pressures", default=default, metavar=PRESSURE_SYNTAX, help=f"pressures in MPa (default {default})"
    )


def parse_pressures(text: str, *, param: str = "--pressure", increasing: bool = False):
    """Every command's pressures: comma-separated items, each one value or ``START:STOP:N``, in MPa.

    ``0.1,0.3,0.6`` is three pressures, ``0:1:3`` the three of ``linspace(0, 1, 3)``
    (N >= 2 points, both ends included), ``0,0.2:0.6:3`` four. An item has exactly one or
    three fields (``0:1:3:4`` is refused, not read as ``0:1:3``); every pressure is checked
    (finite, within ±100 MPa) before any work.

    Parameters
    ----------
    text
        The option's value.
    param
        The option, for the refusal.
    increasing
        Refuse pressures that do not strictly increase.

    Returns
    -------
    numpy.ndarray
        The pressures in the order given, MPa.

    Raises
    ------
    DesignError
        Naming ``param`` and ``text``, with the syntax or the violated bound.
    """
    import numpy as np

    items = [item for item in text.split(",") if item.strip()]  # "0.1,0.3," : an empty item is nothing
    if not items:
        raise DesignError(param, text, "must hold at least one pressure in MPa")
    parts: list[np.ndarray] = []
    for item in items:
        fields = item.strip().split(":")
        try:
            if len(fields) not in (1, 3):
                raise ValueError
            numbers = [float(f) for f in fields[:2]]
            n = int(fields[2]) if len(fields) == 3 else 1
        except ValueError:
            raise DesignError(param, text, _PRESSURE_BOUND) from None
        if len(fields) == 1:
            parts.append(check_pressure(np.array(numbers), param=param))
            continue
        start, stop = numbers
        if n < 2 or n > 1_000_000:
            raise DesignError(param, text, f"count N = {n} must be in [2, 1000000]")
        check_pressure([start, stop], param=param)
        parts.append(np.linspace(start, stop, n))
    values = np.concatenate(parts)
    if values.size > 1_000_000:
        raise DesignError(param, text, f"gives {values.size} pressures, must be at most 1000000")
    if increasing and np.any(np.diff(values) <= 0):
        raise DesignError(param, text, "must be strictly increasing")
    return values


def parse_pressure_range(text: str, *, param: str = "--pressure"):
    """:func:`parse_pressures` (kept under its older name): a checked numpy array, MPa."""
    return parse_pressures(text, param=param)


def parse_pressure_list(text: str, *, param: str = "--pressures", increasing: bool = False) -> list[float]:
    """:func:`parse_pressures` as a list of floats (kept under its older name), MPa."""
    return [float(v) for v in parse_pressures(text, param=param, increasing=increasing)]


@contextlib.contextmanager
def as_options(names: dict[str, str]) -> Iterator[None]:
    """Say a library's refusal in the command's terms: ``{library parameter: option}``.

    The library names its own parameters (``samples``, ``seed``); a command renames the
    ones it passes through from an option, keeping the value and the bound.
    """
    try:
        yield
    except DesignError as exc:
        head, _, rest = exc.parameter.partition(" ")  # "vary tube.h low": the option and its item
        if exc.parameter in names:
            raise DesignError(names[exc.parameter], exc.value, exc.bound) from None
        if rest and head in names:
            raise DesignError(f"{names[head]} {rest}", exc.value, exc.bound) from None
        raise


def add_seed(parser: argparse.ArgumentParser, *, what: str = "random seed") -> None:
    """``--seed N``: one integer makes every random draw of the command reproducible."""
    parser.add_argument(
        "--seed", type=_seed, default=0, metavar="N", help=f"{what} (default 0, at most 2**32 - 1)"
    )


def _seed(text: str) -> int:
    """A seed numpy's generators take: an integer in [0, 2**32 - 1] (argparse refuses anything else)."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"invalid seed {text!r}: must be an integer") from None
    if not 0 <= value <= 2**32 - 1:
        raise argparse.ArgumentTypeError(f"invalid seed {value}: must be in [0, 4294967295]")
    return value


def add_progress(parser: argparse.ArgumentParser) -> None:
    """``--no-progress``: hide the progress bar (it goes to stderr)."""
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bar")


def design_or_data(design: str, data: Path | None) -> tuple[str, Path | None]:
    """``[DESIGN] [DATA]`` with one positional given: a ``.csv`` file or a folder is DATA, not DESIGN.

    A design is a preset name or a ``.toml`` file, so the two never look alike.
    """
    if data is None and design != DEFAULT_DESIGN:
        candidate = Path(design)
        if candidate.suffix.lower() == ".csv" or candidate.is_dir():
            return DEFAULT_DESIGN, candidate
    return design, data


def add_assembly(parser: argparse.ArgumentParser) -> None:
    """``--assembly KEY=VALUE`` (repeatable): override one key of the design's ``[assembly]``."""
    parser.add_argument(
        "--assembly",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="as-built option overriding the design's [assembly] table, repeatable: tube_coil, tube_channel, "
        "channel_coil, filler_coil = bonded|sliding|tied-at-tip; filler = full|coat|none; "
        "filler_coat_thickness = mm; proximal = clamped|tube-free",
    )


def resolve_design(args: argparse.Namespace):
    """The design of ``args.design`` with ``--assembly`` overrides applied."""
    from dataclasses import replace

    from softcath import design  # the library loads when a command runs, not for --help

    d = design.resolve(args.design)
    overrides = getattr(args, "assembly", None) or []
    return replace(d, assembly=d.assembly.with_overrides(overrides)) if overrides else d


#: Library parameter names that are not their option's ``dest`` (the rest are found by dest).
_ALIASES: dict[str, tuple[str, ...]] = {
    "out_dir": ("out",),
    "silicone_poisson": ("poisson",),
    "pressures": ("pressures", "pressure"),
    "pressure": ("pressure", "pressures"),
    "load factors": ("pressure", "pressures"),
    "objectives": ("objective",),
    "constraints": ("constraint",),
    "variables": ("vary",),
    "backend": ("workers", "scheduler"),
    "ranges": ("robust_vary", "ranges"),
}


#: Library parameters whose refusals name an item after the name (``vary.tube.h``, ``vary tube.h low``).
_ITEM_HEADS = ("vary", "objectives", "constraints", "pressures", "ranges", "initial_tension", "samples")


def option_terms(parser: argparse.ArgumentParser) -> dict[str, str]:
    """``{dest: option}`` of a command's parser (the long spelling: ``mesh_size`` -> ``--mesh-size``)."""
    terms: dict[str, str] = {}
    for action in parser._actions:
        longs = [s for s in action.option_strings if s.startswith("--")]
        if longs and action.dest not in ("help", "version"):
            terms[action.dest] = longs[0]
    return terms


def _option_for(name: str, terms: dict[str, str]) -> str | None:
    for dest in (*_ALIASES.get(name, ()), name, name.replace("-", "_")):
        if dest in terms:
            if name == "backend" and {"workers", "scheduler"} <= set(terms):
                return f"{terms['workers']}/{terms['scheduler']}"
            return terms[dest]
    return None


def in_command_terms(exc: Exception, terms: dict[str, str]) -> Exception:
    """``exc`` naming the command's option where the library named its own parameter.

    The one translation every command shares: a :class:`~softcath.design.errors.DesignError`
    whose parameter is an option's ``dest`` (``mesh_size``, ``hoop_cap``, ``scheduler``) or a
    known alias of one (``silicone_poisson`` -> ``--poisson``, ``pressures`` -> ``--pressure``)
    is said with the option; a dotted or spaced tail is kept (``vary.tube.h`` ->
    ``--vary tube.h``). Anything else is returned unchanged.
    """
    if not isinstance(exc, DesignError) or not isinstance(exc.parameter, str):
        return exc
    name = exc.parameter
    if name.startswith("-"):
        return exc
    option = _option_for(name, terms)
    if option is not None:
        return DesignError(option, exc.value, exc.bound)
    for sep in (" ", "."):
        head, found, rest = name.partition(sep)
        option = _option_for(head, terms) if found and head in _ITEM_HEADS else None
        if option is not None:
            return DesignError(f"{option} {rest}", exc.value, exc.bound)
    return exc


def _robust(args) -> bool:
    return getattr(args, "robust", None) is not None


def _slow_tier(args) -> bool:
    """Whether ``--model`` or ``--compare`` names a slow linear tier (the 3-D FEM: its own sample size)."""
    from softcath import models  # the library loads when a command runs, not for --help

    named = [args.model, *str(getattr(args, "compare", "")).replace(" ", "").split(",")]
    return any(n in models.linear_names() and models.get(n).slow for n in named)


#: Options that act only together with another: command -> ((dests, active(args), why), ...).
#: Given without it (a value other than the parser's default) they are refused, not ignored.
_ACTS_ONLY_WITH: dict[str, tuple] = {
    "optimise": ((("samples", "robust_vary", "ranges"), _robust, "has no effect without --robust"),),
    "select": (
        (("vary", "ranges", "samples", "seed", "robust_model"), _robust, "has no effect without --robust"),
    ),
    "predict": (
        (("curve_samples",), lambda a: a.nonlinear, "has no effect without --nonlinear"),
        (("fem_samples",), _slow_tier, "has no effect without the fem tier (--model fem or --compare fem)"),
    ),
    "fem": (
        (
            ("steps", "layers", "curvature_points", "area_true_section", "mixed", "compare_linear"),
            lambda a: a.nonlinear,
            "has no effect without --nonlinear",
        ),
        (
            ("mesher", "coil_modulus", "no_cache", "no_png"),
            lambda a: not a.nonlinear,
            "is an option of the linear check; it has no effect with --nonlinear",
        ),
    ),
}


def check_option_effects(args: argparse.Namespace, command: str, defaults: dict) -> None:
    """Refuse an option given where it has no effect (e.g. ``optimise --samples`` without ``--robust``).

    Raises
    ------
    DesignError
        Naming the option, its value and the option it needs.
    """
    terms = getattr(args, "_terms", {})
    for dests, active, why in _ACTS_ONLY_WITH.get(command, ()):
        if active(args):
            continue
        for dest in dests:
            value = getattr(args, dest, None)
            if dest in defaults and value != defaults[dest]:
                raise DesignError(terms.get(dest, dest), value, why)


def add_model_option(
    parser: argparse.ArgumentParser | argparse._ArgumentGroup, *, tiers: tuple = (), where: str = ""
) -> None:
    """``--model-option [TIER.]NAME=VALUE`` (repeatable): an option of a model tier the command runs.

    ``tiers`` are the registry's :class:`~softcath.models.Tier` objects the command may run;
    the help lists their :attr:`~softcath.models.Tier.options`, so a tier's new option is
    offered here without an edit. The command reads the values with
    :func:`softcath.models.parse_tier_options`.
    """
    known = "; ".join(f"{t.name}: {', '.join(t.options) or 'none'}" for t in tiers)
    parser.add_argument(
        "--model-option",
        action="append",
        default=[],
        metavar="[TIER.]NAME=VALUE",
        help="option of a model tier, repeatable; NAME alone sets it on every tier of the command that "
        f"takes it{where}" + (f" (options: {known})" if known else ""),
    )


def refuse_model_options(args: argparse.Namespace, why: str) -> None:
    """Refuse ``--model-option`` where the command runs no tier it could reach (``why`` says so)."""
    given = getattr(args, "model_option", None) or []
    if given:
        raise DesignError("--model-option", given[0], why)
