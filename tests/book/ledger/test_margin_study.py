"""The sensitivity study of the claims' margins over the table of inputs:
its inputs are the table's uncertain rows over the table's ranges, its stored files are
refused when computed over another table, and the stored indices have the structure the
margins' formulas impose (an input a margin does not read has a total index of exactly 0;
one it reads, a positive one), which the estimator cannot fake."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from gyrolib import inputs
from gyrolib.book.ledger import claims
from gyrolib.book.ledger import margin_study as ms


@pytest.mark.parametrize("model", sorted(ms.STUDIES))
def test_inputs_are_the_tables_uncertain_rows_over_its_ranges(model):
    xs = ms.study_inputs(model)
    read = {n for c in ms.STUDIES[model].claims for n in claims.CLAIMS[c].inputs}
    assert {x.name for x in xs} == {n for n in read if inputs.row(n).kind == "uncertain"}
    for x in xs:
        r = inputs.row(x.name)
        assert (x.low, x.high) == r.bounds() and x.nominal == r.reference
        assert x.distribution == ("loguniform" if r.scale == "log" else "uniform")
    # operating points and readings are never drawn
    assert not any(inputs.row(x.name).kind in ("operating", "reading") for x in xs)
    if model == "gc-claims":   # the race's rival is in the study
        assert any(x.name.startswith("race.") for x in xs)


@pytest.mark.parametrize("model", sorted(ms.STUDIES))
def test_stored_study_is_keyed_to_the_table(model, tmp_path):
    study, data = ms.stored_study(model)
    assert study.settings["table"] == inputs.table_fingerprint(study.input_names)
    assert data["run"]["version"] and len(data["at"]) == len(study.outputs)
    # power: a study computed over another table (a range moved) is refused, loudly
    bad = dict(data, settings={**data["settings"], "table": "0" * 16})
    path = tmp_path / "stale.json"
    path.write_text(json.dumps(bad), encoding="utf-8")
    with pytest.raises(ValueError, match="another table of inputs"):
        ms.stored_study(model, path)


def test_unread_inputs_have_zero_total_index_and_read_ones_do_not():
    """From the margins' formulas, not the estimator: δK (Eq. (7)) does not read ε1, the
    cubic growth and the kilometres read only ε1, 'hundreds of times' does not read ε1,GS.
    Jansen's S_T of an input the output does not read is exactly 0 (f(A) = f(AB_i) at every
    point); every input the formula reads has S_T above 0.  Power: the same check on a
    column whose values are shuffled (a model that reads nothing) fails."""
    study, _ = ms.stored_study("rsf-claims")
    reads = {"delta_k": {"rsf.gs_bias", "rsf.eps1_gs", "rsf.encoder_error"},
             "rsf.example.compensated": {"rsf.eps1", "rsf.gs_bias", "rsf.eps1_gs",
                                         "rsf.encoder_error"},
             "rsf.claim.gs_vs_sins": {"rsf.eps1", "rsf.gs_bias", "rsf.encoder_error"},
             "rsf.claim.drz_cubic": {"rsf.eps1"}, "rsf.claim.drz_kilometres": {"rsf.eps1"}}
    for out, read in reads.items():
        for name in study.input_names:
            st = study.total[out][name].value
            assert (st > 0.0) if name in read else (st == 0.0), (out, name, st)
    gc_study, _ = ms.stored_study("gc-claims")
    for out in ("sigma_gc_100s", "gc.time_to_sigma_c", "gc.claim.trend_holds",
                "gc.claim.psi_separable"):
        for name in gc_study.input_names:
            if name.startswith("race."):        # the rival's rows move only the race
                assert gc_study.total[out][name].value == 0.0, (out, name)
    assert all(gc_study.total["gc.faster_percent"][n].value > 0.0      # the race reads them
               for n in gc_study.input_names if n.startswith("race."))
    from gyrolib.sensitivity import analyze

    y = study.values[:, study.outputs.index("rsf.claim.drz_cubic")].copy()
    np.random.default_rng(0).shuffle(y)
    # the check reads the point estimates, which SALib computes on the whole sample; the
    # bootstrap resamples make only the intervals (10, not the default 1000: 0.65 CPU-s)
    s = analyze(list(study.input_names), y, seed=0, second_order=study.second_order_computed,
                num_resamples=10)
    assert any(s["ST"][n].value != 0.0 for n in study.input_names if n != "rsf.eps1")


def test_compensation_margin_against_eq7_by_hand():
    """At a sampled point of the stored RSF study, the compensation margin equals
    1 − δK/ε1 − 0.90 with δK = [(ε0,GS + ε1,GS ω_unc) Δt + Δγ_enc]/(ω_x Δt) written here."""
    study, _ = ms.stored_study("rsf-claims")
    row = 5
    x = dict(zip(study.input_names, study.points()[row], strict=True))
    ex = inputs.reference_objects()["WorkedExample"]
    dk = ((x["rsf.gs_bias"] + x["rsf.eps1_gs"] * ex.omega_unc) * ex.period
          + x["rsf.encoder_error"]) / (ex.omega_x * ex.period)
    got = study.values[row, study.outputs.index("rsf.example.compensated")]
    assert got == pytest.approx(1.0 - dk / x["rsf.eps1"] - 0.90, rel=1e-9)
    assert study.values[row, 0] == pytest.approx(dk, rel=1e-12)
    assert math.isfinite(got)


def test_bad_model_is_refused_by_name():
    with pytest.raises(ValueError, match="model must be one of"):
        ms.study_inputs("gc")
    with pytest.raises(ValueError, match="rel_step"):
        ms.margin_slopes("rsf-claims", rel_step=0.0)
