"""Excitation protocols of the hidden-effect generator: sines, step-and-hold, quasi-static.

A :class:`Protocol` gives the pressure history of every run (what the syringe
or pump does) and which samples of it end up in the data: every sample for a
time series, the end of each hold for quasi-static points (one reading per
pressure step, ``time_s`` the step index, as a lab without a clock records).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["FS_HZ", "Protocol", "default_protocol", "step_protocol", "quasi_static_protocol"]

FS_HZ = 200.0
#: a syringe pump ramps between levels in about half a second; it cannot jump
RAMP_S = 0.5


@dataclass(frozen=True)
class Protocol:
    """Excitation of one data set (pressure histories per run).

    Parameters
    ----------
    p_max_MPa
        Peak pressure (MPa).
    frequencies_hz
        One sine run (``p_max/2 (1 - cos 2 pi f t)``) per frequency.
    cycles
        Cycles per sine run.
    step_hold
        Add a step-and-hold run (up to p_max, hold, down to p_max/2, hold, release).
    hold_s
        Hold duration of each level (s).
    fs_hz
        Sample rate (Hz).
    staircase
        Add a staircase run: up in quarters of p_max and back down, each level
        held ``hold_s / 2`` (loading and unloading at several levels).
    quasi_static_levels
        If > 0, the protocol is quasi-static: ``quasi_static_runs`` staircases of
        this many levels up to p_max and back down to 0, each held ``hold_s``, of
        which only the end of each hold is recorded (``time_s`` = step index).
        The sine and step runs are then not used.
    quasi_static_runs
        Repeats of the quasi-static staircase (one run each).
    """

    p_max_MPa: float = 2.0
    frequencies_hz: tuple[float, ...] = (0.05, 0.1, 0.2)
    cycles: int = 3
    step_hold: bool = True
    hold_s: float = 15.0
    fs_hz: float = FS_HZ
    staircase: bool = False
    quasi_static_levels: int = 0
    quasi_static_runs: int = 2

    @property
    def quasi_static(self) -> bool:
        return self.quasi_static_levels > 0

    def _levels_run(self, levels: list[float], hold: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Time, pressure and the index of each hold's last sample for a list of levels."""
        knots_t, knots_p, ends = [0.0, 3.0], [0.0, 0.0], [3.0]
        for lv in levels:
            knots_t += [knots_t[-1] + RAMP_S, knots_t[-1] + RAMP_S + hold]
            knots_p += [lv, lv]
            ends.append(knots_t[-1])
        t = np.arange(0, knots_t[-1], 1 / self.fs_hz)
        idx = np.minimum(np.searchsorted(t, np.array(ends) - 1e-9) - 1, t.size - 1)
        return t, self.p_max_MPa * np.interp(t, knots_t, knots_p), idx

    def runs(self) -> list[tuple[str, np.ndarray, np.ndarray]]:
        """(label, time s, pressure MPa) per run."""
        return [(label, t, p) for label, t, p, _ in self._runs()]

    def recorded(self, label: str, t: np.ndarray) -> np.ndarray:
        """Indices of the samples of run ``label`` that the data hold."""
        for lab, _, _, idx in self._runs():
            if lab == label:
                return idx if idx is not None else np.arange(t.size)
        raise KeyError(label)

    def _runs(self):
        out = []
        if self.quasi_static:
            n = self.quasi_static_levels
            up = [k / n for k in range(1, n + 1)]
            levels = up + up[-2::-1] + [0.0]
            for r in range(self.quasi_static_runs):
                t, p, idx = self._levels_run(levels, self.hold_s)
                out.append((f"quasi_static_{r + 1}", t, p, idx))
            return out
        for f in self.frequencies_hz:
            t = np.arange(0, self.cycles / f, 1 / self.fs_hz)
            out.append((f"sine_{f:g}Hz", t, self.p_max_MPa / 2 * (1 - np.cos(2 * np.pi * f * t)), None))
        if self.step_hold:
            h = self.hold_s
            knots_t = [0, 3, 3.5, 3.5 + h, 4 + h, 4 + 2 * h, 4.5 + 2 * h, 4.5 + 3 * h]
            knots_p = [0, 0, 1, 1, 0.5, 0.5, 0, 0]
            t = np.arange(0, knots_t[-1], 1 / self.fs_hz)
            out.append(("step_hold", t, self.p_max_MPa * np.interp(t, knots_t, knots_p), None))
        if self.staircase:
            t, p, _ = self._levels_run([0.25, 0.5, 0.75, 1.0, 0.75, 0.5, 0.25, 0.0], self.hold_s / 2)
            out.append(("staircase", t, p, None))
        return out


def default_protocol(p_max_MPa: float = 2.0) -> Protocol:
    """Three sine frequencies (0.05, 0.1, 0.2 Hz) and a step-and-hold: about 160 s."""
    return Protocol(p_max_MPa=p_max_MPa)


def step_protocol(p_max_MPa: float = 2.0) -> Protocol:
    """Steps only: a step-and-hold (15 s holds) and a staircase up and down (7.5 s holds)."""
    return Protocol(p_max_MPa=p_max_MPa, frequencies_hz=(), step_hold=True, staircase=True)


def quasi_static_protocol(p_max_MPa: float = 2.0) -> Protocol:
    """Two staircases of 10 levels up and down, one reading at the end of each 15 s hold.

    At 50 Hz (enough for the 10 Hz sensor response): only the hold ends are kept.
    """
    return Protocol(p_max_MPa=p_max_MPa, quasi_static_levels=10, fs_hz=50.0)
