"""Objective values and constraint margins of evaluated designs, read from a results table.

A constraint's margin is how far it is met: ``right − left`` for ``<``/``<=``,
``left − right`` for ``>``/``>=``, ``−|left − right|`` for ``==`` and
``|left − right|`` for ``!=``; ≥ 0 when met. Without ``at`` a constraint must
hold at every pressure, so its margin is the smallest over the pressure rows.
A design that failed, or whose expression is undefined everywhere, gets
``-inf`` (a violation, never a crash).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from softcath.studies.criteria import Constraint, Objective, rows_at

__all__ = ["margin_rows", "score_table"]


def margin_rows(c: Constraint, df) -> np.ndarray:
    """Per-row margin of ``c`` (NaN where undefined)."""
    lv, rv = c.left.evaluate(df), c.right.evaluate(df)
    with np.errstate(invalid="ignore"):
        if c.op in ("<", "<="):
            m = rv - lv
        elif c.op in (">", ">="):
            m = lv - rv
        elif c.op == "==":
            m = -np.abs(lv - rv)
        else:
            m = np.abs(lv - rv)
    return np.where(np.isfinite(m), m, np.nan)


def score_table(
    df, ids: Sequence[int], objectives: Sequence[Objective], constraints: Sequence[Constraint]
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(objectives (n, k), margins (n, m), ok (n,))`` of the designs ``ids`` in ``df`` (one load).

    Objectives are the raw expression values (NaN where undefined), margins as
    in the module docstring, ``ok`` whether the design evaluated (status ok).
    """
    import pandas as pd

    ids = list(ids)
    n = len(ids)
    objs = np.full((n, len(objectives)), np.nan)
    margins = np.full((n, len(constraints)), -np.inf)
    if df.empty:
        return objs, margins, np.zeros(n, bool)
    did = df["design_id"].to_numpy()
    pos = pd.Index(ids)
    status = df.drop_duplicates("design_id").set_index("design_id")["status"]
    ok = np.array([status.get(i, "failed") == "ok" for i in ids])
    good = (df["status"] == "ok").to_numpy()
    for j, o in enumerate(objectives):
        mask = rows_at(df, o.where, default_all=False) & good
        v = o.expr.evaluate(df)
        rows = mask & np.isfinite(v)
        objs[pos.get_indexer(did[rows]), j] = v[rows]
    for j, c in enumerate(constraints):
        mask = rows_at(df, c.where, default_all=True) & good
        m = margin_rows(c, df)
        rows = mask & np.isfinite(m)
        worst = pd.Series(m[rows]).groupby(did[rows]).min()
        idx = pos.get_indexer(worst.index)
        margins[idx[idx >= 0], j] = worst.to_numpy()[idx >= 0]
    return objs, margins, ok
