"""Only when needed: effects named on the way are dropped if the final model does not need them."""

from __future__ import annotations

from softcath.design.measurement import Measurement
from softcath.studies.discrepancy import naming, necessity
from softcath.studies.discrepancy.prepare import prepare
from softcath.virtualbench.hidden_effects import make_case


def test_a_small_hysteresis_keeps_only_hysteresis(monkeypatch):
    case = make_case(("hysteresis",), seed=3, effect_to_noise=2.0, noise_fraction=0.01)
    prep = prepare(Measurement.from_table(case.table))
    # Forward naming with no margin and no share rule over-names (noise and form error).
    monkeypatch.setattr(necessity, "drop_unneeded", lambda prep, steps, **kw: list(steps))
    steps = naming.name_effects(prep, margin=0.0, min_share=0.0, max_effects=3)
    monkeypatch.undo()
    over = [s.named for s in steps if s.named]
    assert over[0] == "hysteresis" and len(over) > 1
    out = necessity.drop_unneeded(prep, steps, margin=0.05, min_share=0.05)
    assert [s.named for s in out if s.named] == ["hysteresis"]
    assert set(out[-1].extra["not_needed"]) == set(over[1:])
    assert out[-1].baseline.effects == ("hysteresis",)
