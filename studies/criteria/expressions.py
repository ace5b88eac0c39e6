"""Arithmetic expressions over result columns: parsed with :mod:`ast`, checked, evaluated per row.

Allowed: column names (dotted paths such as ``tube.h``), numbers, ``+ - * /``,
unary minus and ``abs()``; anything else is refused with a :class:`SelectionError`
that names the operator.
"""

from __future__ import annotations

import ast
from dataclasses import dataclass

import numpy as np

from softcath.design.errors import SoftcathError

__all__ = [
    "SelectionError",
    "Expr",
    "COMPARE",
    "MAX_EXPR_CHARS",
    "MAX_EXPR_DEPTH",
    "check_tree",
    "parse_tree",
    "parse_expr",
    "finite_constant",
    "op_name",
    "short",
]

#: Longest expression accepted, characters (a selection reads a few column names and numbers).
MAX_EXPR_CHARS = 1000
#: Deepest nesting of operators, calls and parentheses accepted in one expression.
MAX_EXPR_DEPTH = 50

COMPARE = {ast.Lt: "<", ast.LtE: "<=", ast.Gt: ">", ast.GtE: ">=", ast.Eq: "==", ast.NotEq: "!="}
_BINOPS = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/"}
_FUNCS = {"abs": np.abs}


class SelectionError(SoftcathError):
    """A selection expression that cannot be parsed or names an unknown column or operator."""


def op_name(node: ast.AST) -> str:
    names = {
        ast.Pow: "**",
        ast.Mod: "%",
        ast.FloorDiv: "//",
        ast.BitAnd: "&",
        ast.BitOr: "|",
        ast.BitXor: "^",
        ast.And: "and",
        ast.Or: "or",
        ast.Not: "not",
        ast.In: "in",
        ast.NotIn: "not in",
        ast.Is: "is",
        ast.MatMult: "@",
        ast.LShift: "<<",
        ast.RShift: ">>",
        ast.Invert: "~",
    }
    return names.get(type(node), type(node).__name__)


def _dotted(node: ast.AST) -> str | None:
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.Attribute):
        head = _dotted(node.value)
        return None if head is None else f"{head}.{node.attr}"
    return None


@dataclass(frozen=True)
class Expr:
    """One checked expression: its text and its syntax tree."""

    text: str
    tree: ast.AST

    def columns(self) -> set[str]:
        out: set[str] = set()

        def walk(n: ast.AST) -> None:
            name = _dotted(n)
            if name is not None:
                out.add(name)
                return
            if isinstance(n, ast.Call):
                for a in n.args:
                    walk(a)
                return
            for child in ast.iter_child_nodes(n):
                walk(child)

        walk(self.tree)
        return out

    def evaluate(self, df) -> np.ndarray:
        def ev(n: ast.AST):
            name = _dotted(n)
            if name is not None:
                try:
                    return df[name].to_numpy(dtype=float)
                except (TypeError, ValueError):
                    raise SelectionError(f"in '{self.text}': column '{name}' is not numeric") from None
            if isinstance(n, ast.Constant) and isinstance(n.value, (int, float)):  # (checked: numbers only)
                return np.float64(n.value)  # numpy division: x/0 is ±inf per row, not an exception
            if isinstance(n, ast.UnaryOp):
                v = ev(n.operand)
                return -v if isinstance(n.op, ast.USub) else v
            if isinstance(n, ast.BinOp):
                a, b = ev(n.left), ev(n.right)
                with np.errstate(all="ignore"):
                    if isinstance(n.op, ast.Add):
                        return a + b
                    if isinstance(n.op, ast.Sub):
                        return a - b
                    if isinstance(n.op, ast.Mult):
                        return a * b
                    return a / b
            if isinstance(n, ast.Call) and isinstance(n.func, ast.Name):  # (checked: abs(x) only)
                return _FUNCS[n.func.id](ev(n.args[0]))
            raise AssertionError(f"unchecked node {n!r}")  # _check_tree rejects everything else

        return np.broadcast_to(np.asarray(ev(self.tree), dtype=float), (len(df),))


def short(text: str, limit: int = 80) -> str:
    """``text`` as a message quotes it: whole when short, else its start and its length."""
    return text if len(text) <= limit else f"{text[: limit - 20]}... ({len(text)} characters)"


def _depth(tree: ast.AST) -> int:
    """Nesting depth of ``tree`` (iterative: a deep tree must not exhaust the stack here)."""
    deepest, stack = 0, [(tree, 1)]
    while stack:
        node, d = stack.pop()
        deepest = max(deepest, d)
        if deepest > MAX_EXPR_DEPTH:
            return deepest
        stack.extend((child, d + 1) for child in ast.iter_child_nodes(node))
    return deepest


def parse_tree(text: str, whole: str) -> ast.AST:
    """The syntax tree of ``text`` (part of the expression ``whole``), size and depth checked first.

    Raises
    ------
    SelectionError
        Longer than :data:`MAX_EXPR_CHARS`, nested deeper than :data:`MAX_EXPR_DEPTH`, or not
        Python expression syntax; nothing is evaluated before these checks.
    """
    if len(whole) > MAX_EXPR_CHARS:
        raise SelectionError(
            f"'{short(whole)}' is {len(whole)} characters long; at most {MAX_EXPR_CHARS} are accepted"
        )
    try:
        tree = ast.parse(text.strip(), mode="eval").body
    except SyntaxError as exc:
        raise SelectionError(f"cannot parse '{short(whole)}': {exc.msg}") from None
    except (RecursionError, MemoryError):
        tree = None
    if tree is None or _depth(tree) > MAX_EXPR_DEPTH:
        raise SelectionError(f"'{short(whole)}' is nested deeper than {MAX_EXPR_DEPTH} levels")
    return tree


def check_tree(node: ast.AST, text: str) -> None:
    if _dotted(node) is not None:
        return
    if isinstance(node, ast.Constant):
        if isinstance(node.value, bool) or not isinstance(node.value, (int, float)):
            raise SelectionError(f"in '{text}': only numbers are allowed as constants, not {node.value!r}")
        if not np.isfinite(float(node.value)):
            raise SelectionError(f"in '{text}': the number {ast.unparse(node)} is not finite")
        return
    if isinstance(node, ast.UnaryOp):
        if not isinstance(node.op, (ast.USub, ast.UAdd)):
            raise SelectionError(
                f"in '{text}': operator '{op_name(node.op)}' is not allowed (use + - * / abs())"
            )
        check_tree(node.operand, text)
        return
    if isinstance(node, ast.BinOp):
        if type(node.op) not in _BINOPS:
            raise SelectionError(
                f"in '{text}': operator '{op_name(node.op)}' is not allowed (use + - * / abs())"
            )
        check_tree(node.left, text)
        check_tree(node.right, text)
        return
    if isinstance(node, ast.Call):
        fname = node.func.id if isinstance(node.func, ast.Name) else ast.unparse(node.func)
        if fname not in _FUNCS or len(node.args) != 1 or node.keywords:
            raise SelectionError(f"in '{text}': function '{fname}' is not allowed (only abs(x))")
        check_tree(node.args[0], text)
        return
    if isinstance(node, (ast.BoolOp, ast.Compare)):
        op = node.op if isinstance(node, ast.BoolOp) else node.ops[0]
        raise SelectionError(
            f"in '{text}': operator '{COMPARE.get(type(op)) or op_name(op)}' is not allowed here"
        )
    raise SelectionError(
        f"in '{text}': '{ast.unparse(node)}' is not allowed (use columns, numbers, + - * / abs())"
    )


def parse_expr(text: str, whole: str) -> Expr:
    """A checked :class:`Expr` of ``text`` (part of ``whole``, named in refusals)."""
    tree = parse_tree(text, whole)
    check_tree(tree, whole)
    return finite_constant(Expr(text.strip(), tree), whole)


def finite_constant(expr: Expr, whole: str) -> Expr:
    """Refuse an expression without columns whose value is not finite (e.g. ``1/0``)."""
    if not expr.columns():
        import pandas as pd

        with np.errstate(all="ignore"):
            value = expr.evaluate(pd.DataFrame(index=[0]))[0]
        if not np.isfinite(value):
            raise SelectionError(f"in '{whole}': '{expr.text}' is not a finite number ({value})")
    return expr
