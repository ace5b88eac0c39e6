"""Design selection before fabrication: readable constraints and objectives over result columns.

Expressions
-----------
A constraint compares two arithmetic expressions over result columns::

    bend_angle_deg >= 90 at p_max
    max_strain <= 0.3
    outer_diameter_mm <= 0.8
    abs(rel_diff_curvature) < 0.2 at p=0.5

An objective names a direction and an expression::

    maximise bend_per_MPa_deg
    minimise elongation at p_max
    minimise abs_rel_diff_curvature

Columns are those of ``results.csv`` (swept parameters by their dotted path,
e.g. ``tube.h``). Allowed: numbers, ``+ - * /``, unary minus, ``abs()``, and
the comparisons ``< <= > >= == !=``. ``at p_max``, ``at p_min`` or ``at p=NUM``
picks the pressure row; without it a constraint must hold at every pressure
and an objective is taken at p_max. Rows where an expression is undefined
(NaN, e.g. a per-MPa value at 0 MPa, or FEM columns of an analytic-only
sweep) are skipped; a design with no defined row fails the constraint.

Model and load: the best-estimate columns ``curvature_per_mm``,
``elongation``, ``bend_angle_deg``, ``max_strain`` and ``bend_per_MPa_deg``
resolve to one model's columns (:func:`softcath.studies.results.model_columns`). By
default that is the section model under the lumen load (the real load) when
the sweep has section-model columns, else the paper's formula (analytic
model) under the cap load, with a note saying so; ``model`` and ``load``
choose explicitly (``paper``, ``section`` or ``fem``; ``cap`` or ``lumen``).

Ranking: designs that fail (status) or break a constraint are dropped; the
rest are ordered Pareto front first (no other design is at least as good in
every objective and better in one), each group by the first objective.
"""

from __future__ import annotations

import ast
import difflib
import json
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from softcath.design.errors import SoftcathError

__all__ = [
    "Constraint",
    "Objective",
    "Selection",
    "SelectionError",
    "parse_constraint",
    "parse_objective",
    "pareto_front",
    "resolve_model",
    "select",
    "write_selection",
]

_COMPARE = {ast.Lt: "<", ast.LtE: "<=", ast.Gt: ">", ast.GtE: ">=", ast.Eq: "==", ast.NotEq: "!="}
_BINOPS = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/"}
_FUNCS = {"abs": np.abs}
_AT = re.compile(r"^(?P<expr>.*?)\s+at\s+(?P<where>p_max|p_min|p\s*=\s*[-+0-9.eE]+)\s*$")
MAX_POINTS = 5000
_DIRECTIONS = {"maximise": -1.0, "maximize": -1.0, "max": -1.0, "minimise": 1.0, "minimize": 1.0, "min": 1.0}


class SelectionError(SoftcathError):
    """A selection expression that cannot be parsed or names an unknown column or operator."""


def _op_name(node: ast.AST) -> str:
    names = {
        ast.Pow: "**", ast.Mod: "%", ast.FloorDiv: "//", ast.BitAnd: "&", ast.BitOr: "|", ast.BitXor: "^",
        ast.And: "and", ast.Or: "or", ast.Not: "not", ast.In: "in", ast.NotIn: "not in", ast.Is: "is",
        ast.MatMult: "@", ast.LShift: "<<", ast.RShift: ">>", ast.Invert: "~",
    }  # fmt: skip
    return names.get(type(node), type(node).__name__)


def _dotted(node: ast.AST) -> str | None:
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.Attribute):
        head = _dotted(node.value)
        return None if head is None else f"{head}.{node.attr}"
    return None


@dataclass(frozen=True)
class _Expr:
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
            if isinstance(n, ast.Constant):
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
            if isinstance(n, ast.Call):
                return _FUNCS[n.func.id](ev(n.args[0]))
            raise AssertionError(f"unchecked node {n!r}")  # _check_tree rejects everything else

        return np.broadcast_to(np.asarray(ev(self.tree), dtype=float), (len(df),))


def _check_tree(node: ast.AST, text: str) -> None:
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
                f"in '{text}': operator '{_op_name(node.op)}' is not allowed (use + - * / abs())"
            )
        _check_tree(node.operand, text)
        return
    if isinstance(node, ast.BinOp):
        if type(node.op) not in _BINOPS:
            raise SelectionError(
                f"in '{text}': operator '{_op_name(node.op)}' is not allowed (use + - * / abs())"
            )
        _check_tree(node.left, text)
        _check_tree(node.right, text)
        return
    if isinstance(node, ast.Call):
        fname = node.func.id if isinstance(node.func, ast.Name) else ast.unparse(node.func)
        if fname not in _FUNCS or len(node.args) != 1 or node.keywords:
            raise SelectionError(f"in '{text}': function '{fname}' is not allowed (only abs(x))")
        _check_tree(node.args[0], text)
        return
    if isinstance(node, (ast.BoolOp, ast.Compare)):
        op = node.op if isinstance(node, ast.BoolOp) else node.ops[0]
        raise SelectionError(
            f"in '{text}': operator '{_COMPARE.get(type(op)) or _op_name(op)}' is not allowed here"
        )
    raise SelectionError(
        f"in '{text}': '{ast.unparse(node)}' is not allowed (use columns, numbers, + - * / abs())"
    )


def _parse_expr(text: str, whole: str) -> _Expr:
    try:
        tree = ast.parse(text.strip(), mode="eval").body
    except SyntaxError as exc:
        raise SelectionError(f"cannot parse '{whole}': {exc.msg}") from None
    _check_tree(tree, whole)
    return _finite_constant(_Expr(text.strip(), tree), whole)


def _finite_constant(expr: _Expr, whole: str) -> _Expr:
    """Refuse an expression without columns whose value is not finite (e.g. ``1/0``)."""
    if not expr.columns():
        import pandas as pd

        with np.errstate(all="ignore"):
            value = expr.evaluate(pd.DataFrame(index=[0]))[0]
        if not np.isfinite(value):
            raise SelectionError(f"in '{whole}': '{expr.text}' is not a finite number ({value})")
    return expr


def _split_at(text: str) -> tuple[str, str | None]:
    m = _AT.match(text.strip())
    if m:
        return m.group("expr"), re.sub(r"\s+", "", m.group("where"))
    if re.search(r"\sat\s", text):
        raise SelectionError(f"in '{text}': 'at' must be followed by p_max, p_min or p=NUMBER")
    return text, None


@dataclass(frozen=True)
class Constraint:
    """``left OP right [at WHERE]`` (see module docstring)."""

    text: str
    left: _Expr
    op: str
    right: _Expr
    where: str | None

    def columns(self) -> set[str]:
        return self.left.columns() | self.right.columns()


@dataclass(frozen=True)
class Objective:
    """``maximise|minimise EXPR [at WHERE]``; ``sign`` is +1 to minimise, −1 to maximise."""

    text: str
    sign: float
    expr: _Expr
    where: str | None

    def columns(self) -> set[str]:
        return self.expr.columns()


def parse_constraint(text: str) -> Constraint:
    """Parse a constraint such as ``bend_angle_deg >= 90 at p_max``."""
    body, where = _split_at(text)
    try:
        tree = ast.parse(body.strip(), mode="eval").body
    except SyntaxError as exc:
        raise SelectionError(f"cannot parse '{text}': {exc.msg}") from None
    if isinstance(tree, ast.BoolOp):
        raise SelectionError(
            f"in '{text}': operator '{_op_name(tree.op)}' is not allowed; give one --constraint per condition"
        )
    if not isinstance(tree, ast.Compare):
        raise SelectionError(f"'{text}' is not a comparison: use one of {' '.join(_COMPARE.values())}")
    if len(tree.ops) != 1:
        raise SelectionError(f"in '{text}': use one comparison per constraint (give several --constraint)")
    op = type(tree.ops[0])
    if op not in _COMPARE:
        raise SelectionError(
            f"in '{text}': operator '{_op_name(tree.ops[0])}' is not allowed; use {' '.join(_COMPARE.values())}"
        )
    left, right = tree.left, tree.comparators[0]
    _check_tree(left, text)
    _check_tree(right, text)
    return Constraint(
        text,
        _finite_constant(_Expr(ast.unparse(left), left), text),
        _COMPARE[op],
        _finite_constant(_Expr(ast.unparse(right), right), text),
        where,
    )


def parse_objective(text: str) -> Objective:
    """Parse an objective such as ``maximise bend_per_MPa_deg`` or ``minimise elongation at p_max``."""
    body, where = _split_at(text)
    parts = body.strip().split(None, 1)
    if len(parts) != 2 or parts[0].lower() not in _DIRECTIONS:
        raise SelectionError(f"objective '{text}' must start with maximise or minimise, then an expression")
    return Objective(text, _DIRECTIONS[parts[0].lower()], _parse_expr(parts[1], text), where)


def _check_columns(items, columns) -> None:
    known = set(columns)
    for item in items:
        for name in sorted(item.columns()):
            if name not in known:
                close = difflib.get_close_matches(name, sorted(known), n=3)
                hint = f"; did you mean {', '.join(close)}?" if close else "; see columns.json for the list"
                raise SelectionError(f"unknown column '{name}' in '{item.text}'{hint}")


def _rows_at(df, where: str | None, default_all: bool):
    p = df["pressure_MPa"].to_numpy(float)
    if where is None:
        return np.ones(len(df), bool) if default_all else np.isclose(p, np.nanmax(p))
    if where == "p_max":
        return np.isclose(p, np.nanmax(p))
    if where == "p_min":
        return np.isclose(p, np.nanmin(p))
    value = float(where.split("=", 1)[1])
    mask = np.isclose(p, value, rtol=1e-9, atol=1e-12)
    if not mask.any():
        raise SelectionError(
            f"'at {where}': no results at that pressure; swept pressures: {sorted(set(p.tolist()))} MPa"
        )
    return mask


def pareto_front(values: np.ndarray) -> np.ndarray:
    """Boolean mask of the non-dominated rows of ``values`` (n × k, every column minimised)."""
    values = np.asarray(values, dtype=float)
    n = len(values)
    on = np.zeros(n, bool)
    if n == 0:
        return on
    order = np.lexsort(values.T[::-1])  # lexicographic: a dominating point always comes first
    front: list[np.ndarray] = []
    for i in order:
        f = values[i]
        if front:
            fr = np.asarray(front)
            if np.any(np.all(fr <= f, axis=1) & np.any(fr < f, axis=1)):
                continue
        front.append(f)
        on[i] = True
    return on


@dataclass(frozen=True)
class Selection:
    """Result of :func:`select`.

    Attributes
    ----------
    load
        The load case whose rows were used.
    model
        Which model the best-estimate columns came from (``paper``, ``section``,
        ``fem``), or ``table`` when the results carry no model columns.
    note
        Why that model or load was used when it was not asked for (else empty).
    constraints, objectives
        The expressions as given.
    n_designs, n_feasible
        Designs in the sweep, and designs that passed status and every constraint.
    rejected
        Per constraint (and ``"status failed"``): how many designs it removed.
    ranked
        Feasible designs, best first: ``design_id``, ``rank``, ``pareto``, ``objectives``, ``parameters``.
    pareto_front
        Design ids on the Pareto front.
    points
        ``[design_id, pareto (0/1), objective values...]`` of up to :data:`MAX_POINTS`
        feasible designs (the report's Pareto plot).
    """

    load: str
    constraints: tuple[str, ...]
    objectives: tuple[str, ...]
    n_designs: int
    n_feasible: int
    rejected: dict[str, int]
    ranked: list[dict] = field(default_factory=list)
    pareto_front: list[int] = field(default_factory=list)
    points: list[list[float]] = field(default_factory=list)
    model: str = "table"
    note: str = ""

    def to_json(self) -> dict:
        return {
            "load": self.load,
            "model": self.model,
            "note": self.note,
            "constraints": list(self.constraints),
            "objectives": list(self.objectives),
            "n_designs": self.n_designs,
            "n_feasible": self.n_feasible,
            "rejected": self.rejected,
            "pareto_front": self.pareto_front,
            "ranked": self.ranked,
            "points": self.points,
        }


MODEL_NAMES = {"paper": "the paper's formula", "section": "the section model", "fem": "the 3-D FEM"}


def resolve_model(df, model: str | None = None, load: str | None = None):
    """``(table, model, load, note)``: the results with their best-estimate columns from one model.

    See the module docstring for the defaults; ``note`` says what was chosen
    for the user when it was not asked for.
    """
    from softcath.studies.results import has_model, model_columns

    loads = sorted(set(df["load"]))
    notes = []
    if model is None:
        if has_model(df, "section"):
            model = "section"
        elif "curvature_analytic_per_mm" in df.columns:
            model = "paper"
            notes.append(
                "this sweep has no section-model results: ranked on the paper's formula (analytic model); "
                'add "section" to the sweep\'s evaluators for 3-D-FEM-grade curvature'
            )
    elif model not in MODEL_NAMES:
        raise SelectionError(f"model '{model}' is unknown; choose from {', '.join(MODEL_NAMES)}")
    elif not has_model(df, model):
        raise SelectionError(f"model '{model}': this sweep has no results of {MODEL_NAMES[model]}")
    if load is None:
        load = "cap" if model in (None, "paper") else "lumen"
        if load not in loads:
            notes.append(f"the sweep has no {load} load: used {loads[0]}")
            load = loads[0]
    if model is not None:
        df = model_columns(df, model)
    return df, (model or "table"), load, "; ".join(notes)


def select(
    df,
    *,
    constraints=(),
    objectives=(),
    load: str | None = None,
    top: int | None = None,
    parameters=(),
    model: str | None = None,
) -> Selection:
    """Rank the designs of a results table (see module docstring).

    Parameters
    ----------
    df
        The results table (:func:`softcath.studies.results.read_results`).
    constraints, objectives
        Expression strings.
    load
        Load case to select on (``cap`` or ``lumen``); default: see :func:`resolve_model`.
    model
        ``paper``, ``section`` or ``fem``; default: see :func:`resolve_model`.
    top
        Keep only the best ``top`` designs in ``ranked`` (the counts cover all).
    parameters
        Column names reported for each ranked design (default: swept parameters + outer diameter).
    """
    cons = [parse_constraint(c) for c in constraints]
    objs = [parse_objective(o) for o in objectives]
    if not objs:
        raise SelectionError("give at least one --objective, e.g. 'maximise bend_per_MPa_deg'")
    df, model, load, note = resolve_model(df, model, load)
    _check_columns([*cons, *objs], df.columns)
    loads = sorted(set(df["load"]))
    if load not in loads:
        raise SelectionError(f"load '{load}' is not in the results; available: {', '.join(loads)}")
    sub = df[df["load"] == load].reset_index(drop=True)
    ids = sub["design_id"].to_numpy()
    all_ids = np.unique(ids)
    alive = {int(i) for i in all_ids}
    rejected: dict[str, int] = {}
    failed = {int(i) for i in np.unique(ids[(sub["status"] != "ok").to_numpy()])}
    rejected["status failed"] = len(failed & alive)
    alive -= failed
    for c in cons:
        mask = _rows_at(sub, c.where, default_all=True)
        lv, rv = c.left.evaluate(sub), c.right.evaluate(sub)
        with np.errstate(invalid="ignore"):
            ok = {"<": lv < rv, "<=": lv <= rv, ">": lv > rv, ">=": lv >= rv, "==": lv == rv, "!=": lv != rv}[
                c.op
            ]
        defined = mask & np.isfinite(lv) & np.isfinite(rv)
        bad_ids = set(ids[defined & ~ok].tolist())
        good_ids = set(ids[defined].tolist())
        drop = (bad_ids | (alive - good_ids)) & alive
        rejected[c.text] = len(drop)
        alive -= drop
    obj_vals = {}
    for o in objs:
        mask = _rows_at(sub, o.where, default_all=False)
        v = o.expr.evaluate(sub)
        rows = mask & np.isfinite(v)
        obj_vals[o.text] = dict(zip(ids[rows].tolist(), v[rows].tolist(), strict=True))
    undefined = {i for i in alive if any(i not in vals for vals in obj_vals.values())}
    if undefined:
        rejected["objective undefined"] = len(undefined)
    alive -= undefined
    feasible = sorted(alive)
    matrix = np.array([[o.sign * obj_vals[o.text][i] for o in objs] for i in feasible]).reshape(
        len(feasible), len(objs)
    )
    on_front = pareto_front(matrix)
    order = sorted(range(len(feasible)), key=lambda k: (not on_front[k], matrix[k, 0], feasible[k]))
    if not parameters:
        skip = {"design_id", "task_id"}
        parameters = [
            c for c in df.columns[: list(df.columns).index("outer_diameter_mm") + 1] if c not in skip
        ]
    first = sub.drop_duplicates("design_id").set_index("design_id")
    ranked = []
    for rank, k in enumerate(order[: top if top else None], start=1):
        did = feasible[k]
        ranked.append(
            {
                "rank": rank,
                "design_id": int(did),
                "pareto": bool(on_front[k]),
                "objectives": {o.text: obj_vals[o.text][did] for o in objs},
                "parameters": {p: _jsonable(first.at[did, p]) for p in parameters if p in first.columns},
            }
        )
    keep = order[:MAX_POINTS]
    points = [
        [int(feasible[k]), int(on_front[k]), *(float(obj_vals[o.text][feasible[k]]) for o in objs)]
        for k in keep
    ]
    return Selection(
        points=points,
        load=load,
        model=model,
        note=note,
        constraints=tuple(constraints),
        objectives=tuple(objectives),
        n_designs=len(all_ids),
        n_feasible=len(feasible),
        rejected=rejected,
        ranked=ranked,
        pareto_front=sorted(int(feasible[k]) for k in range(len(feasible)) if on_front[k]),
    )


def _jsonable(v):
    if hasattr(v, "item"):
        v = v.item()
    if isinstance(v, float) and not np.isfinite(v):
        return None
    return v


def write_selection(selection: Selection, out_dir: str | Path) -> Path:
    """Write ``DIR/selection.json`` (atomically)."""
    import os

    path = Path(out_dir) / "selection.json"
    tmp = path.with_name(".selection.json.tmp")
    tmp.write_text(json.dumps(selection.to_json(), indent=1), encoding="utf-8")
    os.replace(tmp, path)
    return path
