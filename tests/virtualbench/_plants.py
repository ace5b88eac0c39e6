"""Shared helpers of the plant and truth-effect tests: a plant with given effects, a sine input."""

import numpy as np

from softcath.virtualbench.plant import Plant

FS = 200.0


def plant_with(*effects, g=2.0, e=0.3, length=5.0):
    return Plant(curvature_per_mpa=g, elongation_per_mpa=e, length_mm=length, effects=effects)


def sine(f=0.1, cycles=3, pmax=0.2):
    t = np.arange(0, cycles / f, 1 / FS)
    return t, pmax / 2 * (1 - np.cos(2 * np.pi * f * t))
