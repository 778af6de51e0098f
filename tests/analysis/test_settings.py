"""One settings object per run (cadartifact.analysis.settings.RunSettings): validated once at the edge, frozen,
and the public keyword API and the settings API reach the same numbers."""

from __future__ import annotations

import dataclasses
import math
import pickle

import numpy as np
import pytest
from hypothesis import given, settings as hsettings, strategies as st

from cadartifact.analysis.settings import (COMPONENTS, METHODS, METRICS, READINGS, REGIONS, RunSettings,
                                           check_tolerance, resolve_scheme)
from cadartifact.errors import OptionError, SchemeError
from cadartifact.net import ControlNet

from cadartifact.testing.known_shapes import family

CHOICES = {"metric": METRICS, "method": METHODS, "component": COMPONENTS, "region": REGIONS, "intent": READINGS}


@pytest.mark.parametrize("option", sorted(CHOICES))
def test_a_bad_choice_is_one_option_error_listing_the_valid_ones(option):
    with pytest.raises(OptionError) as err:
        RunSettings(**{option: "nonsense"})
    assert err.value.parameter == option
    assert all(repr(c) in str(err.value) or c in str(err.value) for c in CHOICES[option])


@given(st.one_of(st.floats(max_value=0.0), st.just(math.nan), st.just(math.inf), st.just(-math.inf),
                 st.sampled_from(["", "abc", "1mm", "-0.1", "0"])))
def test_a_tolerance_that_is_not_a_positive_number_is_refused(bad):
    with pytest.raises(OptionError) as err:
        RunSettings(tolerance=bad)
    assert err.value.parameter == "tolerance"


@given(st.floats(min_value=1e-12, max_value=1e12), st.sampled_from(METRICS), st.sampled_from(READINGS),
       st.booleans(), st.integers(1, 5), st.sampled_from(COMPONENTS))
def test_valid_settings_are_kept_normalised_frozen_and_picklable(t, metric, intent, signal, levels, component):
    s = RunSettings(tolerance=int(t) if t == int(t) else t, metric=metric, intent=intent,
                    include_signal_error=int(signal), levels=levels, component=component)
    assert type(s.tolerance) is float and s.tolerance == t
    assert s.include_signal_error is signal
    assert s.reading == ("net" if signal else intent)
    assert s.compared == ("deviation" if signal else "total")
    with pytest.raises(dataclasses.FrozenInstanceError):
        s.metric = "rms"
    assert pickle.loads(pickle.dumps(s)) == s  # the reader child and Dask workers get it whole
    assert s.replace(levels=levels) == s and s.replace(metric="rms").metric == "rms"
    with pytest.raises(OptionError):
        s.replace(component="sideways")  # a copy is validated again


def test_a_scheme_name_is_checked_when_the_settings_are_made():
    with pytest.raises(SchemeError):
        RunSettings(scheme="no-such-scheme")
    assert RunSettings(scheme="bicubic").scheme == "bicubic"  # kept as given (it travels to other processes)


def test_check_tolerance_names_the_parameter():
    with pytest.raises(OptionError) as err:
        check_tolerance(-1, "tol")
    assert err.value.parameter == "tol" and check_tolerance("0.5") == 0.5


def test_resolve_scheme_defaults_to_the_nets_own_degrees_and_catmull_clark_for_cages():
    net, _, _ = family(5, 1, nmin=8, nmax=10)[0]
    assert resolve_scheme(net).name == f"bspline({net.degrees[0]},{net.degrees[1]})"
    cage = ControlNet(points=np.asarray(net.points), unit="mm")
    assert resolve_scheme(cage).name == resolve_scheme(cage, "catmull-clark").name
    assert resolve_scheme(net, "4-8").name == "4-8"


@hsettings(max_examples=6, deadline=None)
@given(st.integers(0, 10_000), st.sampled_from(METRICS), st.sampled_from(READINGS),
       st.sampled_from(COMPONENTS), st.sampled_from(("auto", "both")), st.sampled_from(("auto", "interior")))
def test_the_keyword_api_and_the_settings_api_give_the_same_budget(seed, metric, intent, component, method, region):
    """Two roads to one budget: ``budget(net, **options)`` (the public API) and ``budget_for(net, RunSettings)``
    on faces sampled from known shapes (several degrees, sizes, frequencies)."""
    from cadartifact.analysis.budget import budget, budget_for

    net, _, _ = family(seed, 1, nmin=6, nmax=12)[0]
    options = dict(metric=metric, intent=intent, component=component, method=method, region=region)
    a = budget(net, None, 0.05, **options)
    b = budget_for(net, RunSettings(tolerance=0.05, **options))
    assert a.stats == b.stats and a.options == b.options == (method, region)
    assert (a.scheme, a.method, a.tolerance, a.metric, a.intent) == (b.scheme, b.method, 0.05, metric, intent)


def test_the_gate_policys_file_settings_hand_down_one_run_settings():
    from cadartifact.gate.policy import FileSettings

    fs = FileSettings(tolerance=0.1, metric="rms", include_signal_error=True, scheme="bicubic", intent="net")
    run = fs.run
    assert run == RunSettings(tolerance=0.1, metric="rms", scheme="bicubic", intent="net", include_signal_error=True)
    assert fs.run is run  # made once per file's settings
    assert pickle.loads(pickle.dumps(fs)).run == run
    with pytest.raises(OptionError):
        FileSettings(tolerance=0.1, metric="loudest").run
