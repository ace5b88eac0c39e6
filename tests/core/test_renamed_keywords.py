"""softcath.core.deprecation: the old keyword ``pressures_MPa`` still works, warns, means ``pressures``."""

from __future__ import annotations

import dataclasses
import inspect
import pickle
import tomllib

import pytest

from softcath.core.deprecation import renamed_keyword
from softcath.design import presets
from softcath.studies.optimise import Problem, make_problem
from softcath.studies.sweep.spec import SweepSpec, parse_spec

E_TUBE = "materials.medical_silicone_tubing.youngs_modulus"
OLD = r"'pressures_MPa' is deprecated, use 'pressures'"


@pytest.fixture(scope="module")
def table():
    return tomllib.loads(presets.text("paper"))


def _problem(table, **pressures):
    return make_problem(
        table, variables=[f"{E_TUBE}=1:4"], objectives=["maximise bend_angle_deg"], model="paper", **pressures
    )


def test_a_public_function_takes_the_old_keyword_with_a_warning(table):
    new = _problem(table, pressures=[0.5, 0.2])
    with pytest.warns(DeprecationWarning, match=rf"make_problem: {OLD}") as record:
        old = _problem(table, pressures_MPa=[0.5, 0.2])
    assert len(record) == 1  # one warning a call, not one a layer
    assert record[0].filename == __file__  # it points at the caller that spells it the old way
    assert old.pressures == new.pressures == (0.2, 0.5)
    assert old.variables == new.variables  # the rest of the problem is the same


def test_the_old_keyword_is_checked_as_the_new_one(table):
    # the refusal names the keyword as it is spelt now
    with pytest.warns(DeprecationWarning, match=OLD), pytest.raises(Exception, match=r"pressures = -1"):
        _problem(table, pressures_MPa=[-1.0])


def test_both_spellings_at_once_are_refused(table):
    with pytest.raises(TypeError, match=r"make_problem: give 'pressures' only, not both"):
        _problem(table, pressures=[0.5], pressures_MPa=[0.5])


def test_the_signature_shows_the_new_keyword():
    params = inspect.signature(make_problem).parameters
    assert "pressures" in params and "pressures_MPa" not in params


def test_a_frozen_dataclass_takes_the_old_field_name_and_reads_it_with_a_warning(table):
    problem = _problem(table, pressures=[0.5])
    fields = {f.name: getattr(problem, f.name) for f in dataclasses.fields(problem)}
    fields["pressures_MPa"] = fields.pop("pressures")
    with pytest.warns(DeprecationWarning, match=rf"Problem: {OLD}"):
        rebuilt = Problem(**fields)
    assert rebuilt == problem
    with pytest.warns(DeprecationWarning, match=rf"Problem: {OLD}"):
        assert problem.pressures_MPa == (0.5,)  # pyright: ignore[reportAttributeAccessIssue]  # added by the decorator
    with pytest.raises(AttributeError):
        problem.pressures_MPa = (1.0,)  # pyright: ignore[reportAttributeAccessIssue]  # read-only, like the field it stands for
    assert "pressures_MPa" not in {f.name for f in dataclasses.fields(Problem)}
    shipped = pickle.loads(pickle.dumps(problem))  # process backends ship it
    assert shipped.pressures == (0.5,) and shipped.variables == problem.variables


def test_the_sweep_spec_keeps_its_file_key_and_deprecates_the_attribute():
    spec = parse_spec({"sweep": {"base": "paper", "pressures_MPa": [1.0, 0.5]}})
    assert spec.pressures == (0.5, 1.0)
    assert spec.to_json()["pressures_MPa"] == [0.5, 1.0]  # the file format keeps its key
    with pytest.warns(DeprecationWarning, match=rf"SweepSpec: {OLD}"):
        assert spec.pressures_MPa == spec.pressures  # pyright: ignore[reportAttributeAccessIssue]  # added by the decorator
    fields = {f.name: getattr(spec, f.name) for f in dataclasses.fields(spec)}
    fields["pressures_MPa"] = fields.pop("pressures")
    with pytest.warns(DeprecationWarning, match=rf"SweepSpec: {OLD}"):
        assert SweepSpec(**fields) == spec
    assert dataclasses.replace(spec, chunk_size=7).pressures == spec.pressures


def test_the_decorator_refuses_a_name_clash_and_non_names():
    with pytest.raises(ValueError, match=r"old = 'p', new = 'p': must be two distinct identifiers"):
        renamed_keyword(old="p", new="p")
    with pytest.raises(ValueError, match=r"old = 'p MPa'"):
        renamed_keyword(old="p MPa", new="p")

    @dataclasses.dataclass(frozen=True)
    class Clash:
        p: float
        p_MPa: float

    with pytest.raises(TypeError, match=r"Clash already has an attribute 'p_MPa'"):
        renamed_keyword(old="p_MPa", new="p")(Clash)


def test_renamed_names_serve_old_names_with_a_warning_and_refuse_unknown_ones():
    from softcath.core.deprecation import renamed_names

    class New:
        pass

    module_getattr = renamed_names("pkg.mod", Old=New)
    with pytest.warns(DeprecationWarning, match=r"pkg\.mod\.Old is deprecated: use New"):
        assert module_getattr("Old") is New
    with pytest.raises(AttributeError, match="module 'pkg.mod' has no attribute 'Other'"):
        module_getattr("Other")
