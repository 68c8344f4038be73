"""Bad input to :mod:`gyrolib.units`, the ledger, the report formats and the command line is rejected by name.

The reference is the contract of CONTRIBUTING.md: bad input raises ``ValueError`` or
``TypeError`` whose message starts with the name of the offending parameter (and, where the
range is a number, states it), never an error from deep inside, a silent NaN or a wrong figure.
The table's coverage is computed from the subpackage's ``__all__`` and its classes' public
methods; hypothesis properties cover continuous ranges.
"""

from __future__ import annotations

from dataclasses import replace
from types import SimpleNamespace

import pytest
from hypothesis import given
from hypothesis import strategies as st

from gyrolib import gc, stats
from gyrolib.book.ledger import margin_study as ms
from gyrolib.book.ledger import remaining
from tests.support.validation_table import *

TABLE = Table()
case = TABLE.case

# units
case("units.to_si", lambda: units.to_si(NAN, "deg"), ValueError, "value", "NaN")
case("units.to_si", lambda: units.to_si("1", "deg"), TypeError, "value", "real")
case("units.to_si", lambda: units.to_si(1j, "deg"), TypeError, "value", "real")
case("units.drift_in_units", lambda: units.drift_in_units("1"), TypeError, "value", "real")
case("units.drift_in_units", lambda: units.drift_in_units(NAN), ValueError, "value", "NaN")
case("units.to_si", lambda: units.to_si(True, "deg"), TypeError, "value", "bool")
case("units.to_si", lambda: units.to_si([[1.0], [1.0, 2.0]], "deg"), TypeError, "value")
case("units.to_si", lambda: units.to_si(1.0, "furlong"), ValueError, "unit", "one of")
case("units.from_si", lambda: units.from_si([1.0, NAN], "deg"), ValueError, "value", "NaN")
case("units.from_si", lambda: units.from_si(1.0, None), TypeError, "unit", "str")

# ledger
case("ledger.LedgerItem", lambda: item(id=None), TypeError, "id", "str")
case("ledger.LedgerItem", lambda: item(note=1.0), TypeError, "note", "str")
case("ledger.LedgerItem", lambda: item(reproduced_value="1"), TypeError, "reproduced_value")
case("ledger.LedgerItem", lambda: item(reproduced_value=True), TypeError, "reproduced_value")
case("ledger.LedgerItem", lambda: item(reproduced_value=INF), ValueError, "reproduced_value",
     FINITE)
case("ledger.LedgerItem", lambda: item(paper_value=NAN), ValueError, "paper_value", FINITE)
case("ledger.LedgerItem", lambda: item(paper_value=[1]), TypeError, "paper_value")
case("ledger.LedgerItem", lambda: item(status="close enough"), ValueError, "status", "one of")
case("ledger.LedgerItem", lambda: item(paper="XYZ"), ValueError, "paper", "'GC' or 'RSF'")
case("ledger.LedgerItem", lambda: item(kind="guess"), ValueError, "kind", "one of")
case("ledger.LedgerItem", lambda: item(kind="input"), ValueError, "status", "one of")
case("ledger.LedgerItem", lambda: item(evidence=""), ValueError, "evidence", "non-empty")
case("ledger.LedgerItem", lambda: item(precision=0), ValueError, "precision", "[1, 15]")
case("ledger.LedgerItem", lambda: item(kind="claim", status="holds under conditions"),
     ValueError, "conditions", "non-empty")
case("ledger.to_json", lambda: ledger.to_json(None), TypeError, "items", "LedgerItem")
case("ledger.to_csv", lambda: ledger.to_csv([1]), TypeError, "items", "LedgerItem")
case("ledger.rounded", lambda: ledger.rounded(NAN, 3), ValueError, "value", FINITE)
case("ledger.to_json", lambda: ledger.to_json([1]), TypeError, "items")
case("ledger.to_table", lambda: ledger.to_table("abc"), TypeError, "items")
case("ledger.summary", lambda: ledger.summary([item(), 1]), TypeError, "items")
case("ledger.table_markdown", lambda: ledger.table_markdown([item()], "XYZ"), ValueError, "paper",
     "'GC' or 'RSF'")
case("ledger.table_markdown", lambda: ledger.table_markdown(None, "GC"), TypeError, "items")
case("ledger.entries_markdown", lambda: ledger.entries_markdown([item()], "XYZ"), ValueError,
     "paper", "'GC' or 'RSF'")
case("ledger.entries_markdown", lambda: ledger.entries_markdown([1], "GC"), TypeError, "items")
case("ledger.citation", lambda: ledger.citation("gc.x"), TypeError, "item", "LedgerItem")
case("ledger.anchor", lambda: ledger.anchor(3), TypeError, "item_id", "str")
case("ledger.kinds_markdown", lambda: ledger.kinds_markdown([1]), TypeError, "items")
case("ledger.gc.items", lambda: lgc.items("x"), TypeError, "params", "GyrocompassParams")
case("ledger.gc.study_evidence", lambda: lgc.study_evidence("x"), TypeError, "params",
     "GyrocompassParams")
case("ledger.rsf.items", lambda: lrsf.items(roll_gyro=None), TypeError, "roll_gyro",
     "RollGyroSpec")
case("ledger.rsf.items", lambda: lrsf.items(gs_gyro="x"), TypeError, "gs_gyro", "MemsGyroSpec")
case("ledger.rsf.encoder_revolution", lambda: lrsf.encoder_revolution(rsf.AEDB9340), TypeError,
     "gs_gyro", "MemsGyroSpec")
case("ledger.rsf.items", lambda: lrsf.items(encoder=rsf.EncoderModel()), TypeError, "encoder",
     "EncoderSpec")
case("ledger.agrees", lambda: ledger.agrees(1.0, "about 0.5"), ValueError, "printed")
case("ledger.agrees", lambda: ledger.agrees(1.0, 1.0, tolerance=0.1), ValueError, "reason")
case("ledger.agrees", lambda: ledger.agrees("1", 1.0), TypeError, "value", "real")
case("ledger.half_unit", lambda: ledger.half_unit(None), TypeError, "printed")
case("ledger.half_unit", lambda: ledger.half_unit(NAN), ValueError, "printed", FINITE)
case("ledger.printed_verdict", lambda: ledger.printed_verdict(1.0, 1.0, [1.0]), TypeError,
     "candidates", "Candidate")
case("ledger.Candidate", lambda: ledger.Candidate("x", NAN), ValueError, "value", FINITE)
case("ledger.format_value", lambda: ledger.format_value([1.0]), TypeError, "value", "real")
case("ledger.format_value", lambda: ledger.format_value(NAN), ValueError, "value", FINITE)

# report
case("report.page_png", lambda: report.page_png("not a figure"), TypeError, "fig", "Figure")
case("report.sci", lambda: report.sci(NAN), ValueError, "x", FINITE)
case("report.sci", lambda: report.sci("1e-4"), TypeError, "x", "real")
case("report.sci", lambda: report.sci(1.0, 0), ValueError, "digits", ">= 1")
case("report.below", lambda: report.below(NAN, 1e-14, "the recheck"), ValueError,
     "the recheck", FINITE)
case("report.below", lambda: report.below(1e-15, 0.0), ValueError, "bound", "> 0")
case("report.below", lambda: report.below(2e-14, 1e-14, "agreement"), ValueError,
     "agreement", "below 1e-14")
case("report.grouped", lambda: report.grouped(INF), ValueError, "x", FINITE)
case("report.grouped", lambda: report.grouped(1.0, 2.5), TypeError, "digits")
case("report.format_number", lambda: report.format_number(1.0, 3), TypeError, "fmt", "str")
case("report.format_number", lambda: report.format_number(NAN, ".3f"), ValueError, "value",
     FINITE)
case("report.format_number", lambda: report.format_number("x", ".3f"), TypeError, "value")
case("report.markdown_table", lambda: report.markdown_table([], []), ValueError, "header")
case("report.markdown_table", lambda: report.markdown_table(["a", "b"], [[1]]), ValueError,
     "rows[0]", "2 cells")
case("report.gluer", lambda: report.gluer(None), TypeError, "prefix", "str")

# stats
_EST = stats.Estimate(1.0, 0.5, 1.5, 0.95, 10, "bootstrap", 0)
case("stats.Estimate", lambda: stats.Estimate(1.0, 2.0, 0.0, 0.95, 10, "x"), ValueError, "lo")
case("stats.Estimate", lambda: stats.Estimate(NAN, 0.0, 1.0, 0.95, 10, "x"), ValueError,
     "value", FINITE)
case("stats.Estimate", lambda: stats.Estimate(1.0, 0.0, 2.0, 1.5, 10, "x"), ValueError,
     "confidence")
case("stats.Estimate.scaled", lambda: _EST.scaled(0.0), ValueError, "factor", POS)
case("stats.Estimate.text", lambda: _EST.text(5), TypeError, "unit", "str")
case("stats.Estimate.interval_text", lambda: _EST.interval_text(5), TypeError, "unit", "str")
case("stats.bootstrap", lambda: stats.bootstrap([1.0], np.mean, seed=0), ValueError,
     "sample", "2 runs")
case("stats.bootstrap", lambda: stats.bootstrap([1.0, 2.0], np.mean, seed=0, n_boot=10),
     ValueError, "n_boot")
case("stats.percentile", lambda: stats.percentile([1.0, 2.0], -1.0), ValueError, "q")
case("stats.mean", lambda: stats.mean([1.0, 2.0], seed=-1), ValueError, "seed")
case("stats.proportion", lambda: stats.proportion(3, 2), ValueError, "successes")

# ledger.remaining
case("ledger.remaining.west_gyro", lambda: remaining.west_gyro("x"), TypeError, "params")
case("ledger.remaining.west_gyro",
     lambda: remaining.west_gyro(gc.GyrocompassParams(), 0.0), ValueError, "t_end", POS)
case("ledger.remaining.flight_lateral", lambda: remaining.flight_lateral(-1), ValueError,
     "seed")
case("ledger.remaining.flight_lateral", lambda: remaining.flight_lateral(1, 1), ValueError,
     "n_runs")
case("ledger.remaining.flight_lateral",
     lambda: remaining.flight_lateral(1, 2, gs_gyro="GYPRO4300"), TypeError, "gs_gyro")
case("ledger.remaining.flight_lateral", lambda: remaining.flight_lateral(1, 2, omega_x=0.0),
     ValueError, "omega_x", POS)
case("ledger.remaining.items_gc", lambda: remaining.items_gc("x"), TypeError, "params")
case("ledger.remaining.items_rsf", lambda: remaining.items_rsf(seed=-1), ValueError, "seed")
_WEST = remaining.WestGyro(t=np.array([0.0, 1.0]), sigma=np.ones(2), floor=1.0, psi_max=1.0,
                           beta_n=1.0)
case("ledger.remaining.WestGyro.sigma_at", lambda: _WEST.sigma_at(2.0), ValueError, "t")
_LAT = remaining.FlightLateral(raw=np.ones(3), corrected=np.ones(3), reset=np.ones(3), seed=0,
                               duration=1.0)
case("ledger.remaining.FlightLateral.ratio", lambda: _LAT.ratio("x"), ValueError, "which")
case("ledger.remaining.FlightLateral.worse", lambda: _LAT.worse("x"), ValueError, "which")

# the quoted range of a censored time and the RSF 90 % item's condition
case("ledger.gc.censored_range_text", lambda: lgc.censored_range_text("x"), TypeError, "t_c")
case("ledger.gc.censored_range_text", lambda: lgc.censored_range_text([1.0], 0.0), ValueError,
     "bound", "> 0")
case("ledger.rsf.omega_unc_condition", lambda: lrsf.omega_unc_condition("x"), TypeError,
     "roll_gyro", "RollGyroSpec")
case("ledger.rsf.omega_unc_condition", lambda: lrsf.omega_unc_condition(period=0.0),
     ValueError, "period", "> 0")
case("ledger.rsf.omega_unc_condition", lambda: lrsf.omega_unc_condition(target=1.5),
     ValueError, "target", r"in \[0\.0, 1\.0\]")

# cli
case("cli.main", lambda: cli.main("ledger"), TypeError, "argv", "list of str")
case("cli.main", lambda: cli.main([1]), TypeError, "argv")


@pytest.mark.parametrize(("call", "exc", "pattern"), TABLE.cases)
def test_bad_input_is_rejected_by_name(call, exc, pattern):
    run_case(call, exc, pattern)


#: Public callables without a bad-input case, and why.
EXEMPT: dict[str, str] = {"report.MarkdownText": "a str subclass: any text is valid",
                          "ledger.margin_study.Study": "a record of the module's two studies "
                          "(STUDIES), not built from a caller's input",
                          "ledger.remaining.FlightLateral": "result object, built by "
                          "flight_lateral (checked there)",
                          "ledger.remaining.WestGyro": "result object, built by west_gyro "
                          "(checked there)",
                          "ledger.rsf.OmegaUncCondition": "result object, built by "
                          "omega_unc_condition (checked there)"}


# a ledger item's quoted numbers and claims side by side
_ITEM = ledger.LedgerItem(id="gc.test", paper="GC", location="Fig. 3", quantity="q", unit="m",
                          paper_value=0.5, reproduced_value=0.49, status="reproduced",
                          note="", chapter="chapters/gc_model", anchor="",
                          kind="printed number",
                          evidence="a computation")
case("ledger.LedgerItem.quote_threshold", lambda: _ITEM.quote_threshold("gc.C_as"), ValueError,
     "gc.test has no threshold of 'gc.C_as'")
case("ledger.LedgerItem.quote_share", lambda: _ITEM.quote_share(), ValueError,
     "gc.test has no share")
case("ledger.side_by_side_markdown",
     lambda: ledger.side_by_side_markdown({"gc.test": ("x", _ITEM)}), ValueError, "claims",
     "at least two")


# the studies of the claims' margins
case("ledger.margin_study.study_inputs", lambda: ms.study_inputs("gc"), ValueError, "model",
     "one of")
case("ledger.margin_study.study_outputs", lambda: ms.study_outputs(None), ValueError, "model")
case("ledger.margin_study.reference_outputs", lambda: ms.reference_outputs("rsf"), ValueError,
     "model")
case("ledger.margin_study.study_file", lambda: ms.study_file("gc-claim"), ValueError, "model")
case("ledger.margin_study.margin_study", lambda: ms.margin_study("x", 4), ValueError, "model")
case("ledger.margin_study.margin_study", lambda: ms.margin_study("rsf-claims", 6), ValueError,
     "n must be a power of 2")
case("ledger.margin_study.margin_study",
     lambda: ms.margin_study("rsf-claims", 4, executor="dask"), TypeError, "executor")
case("ledger.margin_study.margin_study",
     lambda: ms.margin_study("rsf-claims", 4, chunk_size=0), ValueError, "chunk_size")
case("ledger.margin_study.margin_slopes", lambda: ms.margin_slopes("rsf-claims", 0.5),
     ValueError, "rel_step")
case("ledger.margin_study.margin_slopes", lambda: ms.margin_slopes("rsf-claims", "0.01"),
     TypeError, "rel_step")
case("ledger.margin_study.margin_slopes", lambda: ms.margin_slopes("rsf-claims", NAN),
     ValueError, "rel_step")
case("ledger.margin_study.stored_study", lambda: ms.stored_study("rsf-claims", 3.0),
     TypeError, "path", "file path")
case("ledger.margin_study.stored_study",
     lambda: ms.stored_study("rsf-claims", "/nonexistent/s.json"), ValueError, "path",
     "existing file")
case("ledger.margin_study.recheck_study", lambda: ms.recheck_study({"model": "gc-claims"}),
     TypeError, "result")
case("ledger.margin_study.recheck_study",
     lambda: ms.recheck_study(replace(ms.stored_study("rsf-claims")[0], model="rsf")),
     ValueError, "result",
     "study of")


def test_table_covers_every_public_callable():
    TABLE.check_coverage({"cli": SimpleNamespace(__all__=["main"], main=cli.main), "units": units, "ledger": ledger, "ledger.gc": lgc, "ledger.rsf": lrsf, "ledger.remaining": remaining, "ledger.margin_study": ms, "report": report, "stats": stats}, EXEMPT)


def test_cli_rejects_an_unknown_command_with_usage(capsys):
    with pytest.raises(SystemExit) as info:
        cli.main(["nope"])
    assert info.value.code == 2
    assert "invalid choice: 'nope'" in capsys.readouterr().err


@SETTINGS
@given(values=st.lists(st.floats(-1e6, 1e6), min_size=1, max_size=8), where=st.integers(0, 7))
def test_a_nan_anywhere_in_a_unit_conversion_is_rejected(values, where):
    values[where % len(values)] = NAN
    with pytest.raises(ValueError, match=r"^value must be a number or ±inf, not NaN"):
        units.to_si(values, "deg/h")


@SETTINGS
@given(x=st.floats(-1e6, 1e6), unit=st.sampled_from(sorted(units.UNITS)))
def test_finite_and_infinite_values_still_convert_exactly(x, unit):
    assert units.to_si(x, unit) == x * units.UNITS[unit]
    assert units.from_si(INF, unit) == INF

case("ledger.claim_map_markdown", lambda: ledger.claim_map_markdown("gc.faster_percent"),
     TypeError, "item", "LedgerItem")
