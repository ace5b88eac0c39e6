"""The measured curvature gain κ/p with a standard error that honours correlated samples.

Samples of a filtered or slowly varying series are not independent, so the
ordinary least-squares standard error (which assumes they are) is far too
small. The gain is instead estimated per group, runs when there are at least
three, otherwise five contiguous blocks (batch means), and its standard error
is the spread of the group gains over √groups.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from softcath.design.measurement import Measurement

__all__ = ["DataGain", "data_gain"]

#: groups whose gains differ by more than this ratio are said not to share one gain
SPREAD_FLAG = 1.5


@dataclass(frozen=True)
class DataGain:
    """Least-squares gain of the data and its uncertainty (1/(mm MPa)).

    Attributes
    ----------
    gain
        Σ p κ / Σ p² over all rows.
    stderr
        Standard error from the spread of the group gains (None with < 2 groups).
    by_group
        Gain per group (run label or ``block k``).
    method
        How the groups were formed.
    """

    gain: float
    stderr: float | None
    by_group: dict[str, float]
    method: str

    @property
    def groups_disagree(self) -> bool:
        g = np.array(list(self.by_group.values()))
        return bool(g.size >= 2 and np.all(g > 0) and g.max() / g.min() > SPREAD_FLAG)

    def describe(self) -> str:
        """One sentence for reports."""
        se = f" ± {self.stderr:.2g}" if self.stderr is not None else ""
        text = f"data gain {self.gain:.4g}{se} 1/(mm MPa) (s.e. from {self.method})"
        if self.groups_disagree:
            g = self.by_group
            lo, hi = min(g, key=g.get), max(g, key=g.get)
            text += (
                f"; the groups do not share one gain ({lo} {g[lo]:.3g} to {hi} {g[hi]:.3g}): "
                "one linear model cannot describe them all"
            )
        return text


def data_gain(m: Measurement, *, blocks: int = 5) -> DataGain:
    """The gain κ/p of ``m`` with a standard error from runs or contiguous blocks."""
    p, k = np.asarray(m.pressure_MPa, float), np.asarray(m.curvature_per_mm, float)
    spp = float(p @ p)
    gain = float(p @ k) / spp if spp > 0 else float("nan")
    if len(m.runs) >= 3:
        labels = m.run_labels()
        groups = {r: labels == r for r in m.runs}
        method = f"{len(m.runs)} runs"
    else:
        idx = np.array_split(np.arange(p.size), blocks)
        groups = {f"block {i + 1}": np.isin(np.arange(p.size), b) for i, b in enumerate(idx)}
        method = f"{blocks} contiguous blocks"
    by = {}
    for name, sel in groups.items():
        s = float(p[sel] @ p[sel])
        if s > 0:
            by[name] = float(p[sel] @ k[sel]) / s
    g = np.array(list(by.values()))
    se = float(np.std(g, ddof=1) / np.sqrt(g.size)) if g.size >= 2 else None
    return DataGain(gain=gain, stderr=se, by_group=by, method=method)
