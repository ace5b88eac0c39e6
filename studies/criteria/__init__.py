"""Constraints and objectives: ``left OP right [at WHERE]`` and ``maximise|minimise EXPR [at WHERE]``.

The criteria that ``select`` (:mod:`softcath.studies.selection`) and ``optimise``
(:mod:`softcath.studies.optimise`) share; below both, so that each imports them at its top.
Their expressions are parsed by :mod:`softcath.studies.criteria.expressions`.

Also where they apply: :func:`rows_at` picks the pressure rows of ``at p_max``,
``at p_min`` or ``at p=NUM``, and :func:`check_columns` names unknown columns.
"""

from __future__ import annotations

import ast
import difflib
import math
import re
from dataclasses import dataclass

import numpy as np

from softcath.core.limits import MAX_PRESSURE_MPA
from softcath.studies.criteria.expressions import (
    COMPARE,
    MAX_EXPR_CHARS,
    Expr,
    SelectionError,
    check_tree,
    finite_constant,
    op_name,
    parse_expr,
    parse_tree,
    short,
)

__all__ = [
    "Constraint",
    "Objective",
    "at_pressure",
    "parse_constraint",
    "parse_objective",
    "check_columns",
    "rows_at",
    "without_text",
]

_AT = re.compile(r"^(?P<expr>.*?)\s+at\s+(?P<where>p_max|p_min|p\s*=\s*\S+)\s*$")
_DIRECTIONS = {"maximise": -1.0, "maximize": -1.0, "max": -1.0, "minimise": 1.0, "minimize": 1.0, "min": 1.0}


def _split_at(text: str) -> tuple[str, str | None]:
    """``(expression, where)``: ``where`` is p_max, p_min or ``p=VALUE`` with VALUE checked.

    VALUE follows the rule of every pressure a command takes (a finite number within
    ±:data:`~softcath.core.limits.MAX_PRESSURE_MPA` MPa), checked here, before
    any evaluation.
    """
    if len(text) > MAX_EXPR_CHARS:
        raise SelectionError(
            f"'{short(text)}' is {len(text)} characters long; at most {MAX_EXPR_CHARS} are accepted"
        )
    m = _AT.match(text.strip())
    if m:
        where = re.sub(r"\s+", "", m.group("where"))
        if where.startswith("p="):
            at_pressure(where, text)
        return m.group("expr"), where
    if re.search(r"\sat\s", text):
        raise SelectionError(f"in '{short(text)}': 'at' must be followed by p_max, p_min or p=NUMBER")
    return text, None


def at_pressure(where: str, text: str) -> float:
    """The pressure of ``at p=VALUE`` in MPa: a finite number within ±100 MPa (the options' rule)."""

    value = where.split("=", 1)[1]
    try:
        p = float(value)
    except ValueError:
        raise SelectionError(
            f"in '{short(text)}': 'at p={value}': the pressure must be a number in MPa"
        ) from None
    if not (math.isfinite(p) and abs(p) <= MAX_PRESSURE_MPA):
        raise SelectionError(
            f"in '{short(text)}': 'at p={value}': the pressure must be finite and within "
            f"±{MAX_PRESSURE_MPA:g} MPa (no model holds beyond)"
        )
    return p


@dataclass(frozen=True)
class Constraint:
    """``left OP right [at WHERE]`` (see module docstring)."""

    text: str
    left: Expr
    op: str
    right: Expr
    where: str | None

    def columns(self) -> set[str]:
        return self.left.columns() | self.right.columns()


@dataclass(frozen=True)
class Objective:
    """``maximise|minimise EXPR [at WHERE]``; ``sign`` is +1 to minimise, −1 to maximise."""

    text: str
    sign: float
    expr: Expr
    where: str | None

    def columns(self) -> set[str]:
        return self.expr.columns()


def parse_constraint(text: str) -> Constraint:
    """Parse a constraint such as ``bend_angle_deg >= 90 at p_max``."""
    body, where = _split_at(text)
    tree = parse_tree(body, text)
    if isinstance(tree, ast.BoolOp):
        raise SelectionError(
            f"in '{text}': operator '{op_name(tree.op)}' is not allowed; give one constraint per condition"
        )
    if not isinstance(tree, ast.Compare):
        raise SelectionError(f"'{text}' is not a comparison: use one of {' '.join(COMPARE.values())}")
    if len(tree.ops) != 1:
        raise SelectionError(f"in '{text}': use one comparison per constraint (give several constraints)")
    op = type(tree.ops[0])
    if op not in COMPARE:
        raise SelectionError(
            f"in '{text}': operator '{op_name(tree.ops[0])}' is not allowed; use {' '.join(COMPARE.values())}"
        )
    left, right = tree.left, tree.comparators[0]
    check_tree(left, text)
    check_tree(right, text)
    return Constraint(
        text,
        finite_constant(Expr(ast.unparse(left), left), text),
        COMPARE[op],
        finite_constant(Expr(ast.unparse(right), right), text),
        where,
    )


def parse_objective(text: str) -> Objective:
    """Parse an objective such as ``maximise bend_per_MPa_deg`` or ``minimise elongation at p_max``."""
    body, where = _split_at(text)
    parts = body.strip().split(None, 1)
    if len(parts) != 2 or parts[0].lower() not in _DIRECTIONS:
        raise SelectionError(f"objective '{text}' must start with maximise or minimise, then an expression")
    return Objective(text, _DIRECTIONS[parts[0].lower()], parse_expr(parts[1], text), where)


def check_columns(items, columns, *, listed: str = "see columns.json for the list") -> None:
    """Refuse a column the results do not have, suggesting close names (else ``listed``)."""
    known = set(columns)
    for item in items:
        for name in sorted(item.columns()):
            if name not in known:
                close = difflib.get_close_matches(name, sorted(known), n=3)
                hint = f"; did you mean {', '.join(close)}?" if close else f"; {listed}"
                raise SelectionError(f"unknown column '{name}' in '{short(item.text)}'{hint}")


def without_text(message: str, text: str) -> str:
    """A :class:`SelectionError` message without its quotes of ``text`` (the caller names it)."""
    for lead in (f"in '{short(text)}': ", f"in '{text}': ", f"'{short(text)}' ", f"'{text}' "):
        if message.startswith(lead):
            message = message[len(lead) :]
            break
    for quoted in (f" in '{short(text)}'", f" in '{text}'"):
        message = message.replace(quoted, "")
    return message


def rows_at(df, where: str | None, default_all: bool):
    """Rows (mask) at the pressure ``where`` names; without it every row or the p_max rows."""
    p = df["pressure_MPa"].to_numpy(float)
    if where is None:
        return np.ones(len(df), bool) if default_all else np.isclose(p, np.nanmax(p))
    if where == "p_max":
        return np.isclose(p, np.nanmax(p))
    if where == "p_min":
        return np.isclose(p, np.nanmin(p))
    value = at_pressure(where, where)
    mask = np.isclose(p, value, rtol=1e-9, atol=1e-12)
    if not mask.any():
        raise SelectionError(
            f"'at {where}': no results at that pressure; swept pressures: {sorted(set(p.tolist()))} MPa"
        )
    return mask
