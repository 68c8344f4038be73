"""The command line prints the library's verdict and decides nothing: its text, its JSON and
the :class:`gyrolib.verdict.Verdict` that :func:`gyrolib.gc.judge_record` and
:func:`gyrolib.rsf.judge_record` return hold the same numbers and names.  For a GC record
and an RSF record with a prior-check failure, the text and the JSON name the same state
with the same value and band, and every check's band is printed one way wherever it
appears."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from gyrolib import gc, rsf
from gyrolib.cli import main
from gyrolib.verdict import compared

DATA = Path(__file__).resolve().parents[2] / "data"


def _spy(monkeypatch, module) -> list:
    """Capture the verdicts ``module.judge_record`` returns to the command line."""
    seen: list = []
    real = module.judge_record

    def spy(*args, **kw):
        ver = real(*args, **kw)
        seen.append(ver)
        return ver

    monkeypatch.setattr(module, "judge_record", spy)
    return seen


def _run(argv, capsys) -> tuple[int, str]:
    code = main([str(a) for a in argv])
    return code, capsys.readouterr().out


def _both(argv, module, monkeypatch, capsys):
    """(exit status, text, JSON, verdict of the text run, verdict of the JSON run)."""
    seen = _spy(monkeypatch, module)
    code, text = _run(argv, capsys)
    code_j, out = _run([*argv, "--json"], capsys)
    assert code == code_j and len(seen) == 2
    return code, text, json.loads(out), seen[0], seen[1]


def _printed_bands(text: str, name: str, formula: str) -> set[str]:
    """Every band printed after ``name: formula = value`` in ``text``."""
    pat = re.escape(f"{name}: {formula} = ") + r"(\S+) (?:in|NOT in) (\[[^\]]*\])"
    return {m.group(2) for m in re.finditer(pat, text)}


def _hold_the_same(text: str, data: dict, ver) -> None:
    """The text, the JSON and the verdict: the same checks (name, value, band), status,
    codes, hint and counts."""
    assert [c["name"] for c in data["checks"]] == [c.name for c in ver.checks]
    for c, js in zip(ver.checks, data["checks"]):
        assert js["statistic"] == c.value and (js["low"], js["high"]) == (c.low, c.high)
        assert js["subject"] == c.subject and js["passed"] == c.passed
        x, lo, hi = compared(js["statistic"], js["low"], js["high"])
        assert js["band"] == f"[{lo}, {hi}]" == c.band()
        line = f"{js['name']}: {js['formula']} = {x} {'in' if js['passed'] else 'NOT in'} "
        assert f"    {line}{js['band']}\n" in text
        # one band for one statistic, wherever the text prints it (the reason too)
        assert _printed_bands(text, js["name"], js["formula"]) == {js["band"]}
    assert data["status"] == ver.status and data["valid"] == ver.valid
    assert data["reason"] == ver.reason
    assert data["reason_code"] == (ver.reason_code or None if ver.method == "gc"
                                   else ver.reason_code)
    assert (data["hint"] or "") == ver.hint
    assert text.rstrip("\n").endswith(ver.hint)
    counts = data["counts"]
    assert counts == ver.counts.summary() and f"  {ver.counts.line()}" in text
    assert counts["used"] + counts["rejected"] + counts["empty"] == counts["rows"]
    assert max(counts["used"], counts["rejected"], counts["empty"]) <= data["rows"]


def test_gc_prior_failure_text_json_and_object(monkeypatch, capsys):
    """The sample GC record calibrated at 50° N (it was made at 53.9°): the drift's prior
    check fails, and the text and the JSON name it alike: ``prior of omega_gc``, its
    z = estimate/√(P0 − P) and its band, the band of every prior check the same."""
    argv = ["calibrate", "gc", DATA / "gc_record.csv.gz", "--latitude", "50"]
    code, text, data, ver, ver_j = _both(argv, gc, monkeypatch, capsys)
    assert code == 3 and ver.status == ver_j.status == "invalid"
    _hold_the_same(text, data, ver_j)
    failed = [c for c in data["checks"] if not c["passed"]]
    prior = next(c for c in failed if c["name"] == "prior of omega_gc")
    assert prior["test"] == "prior" and prior["subject"] == "omega_gc"
    # the filter's own test of that state (the JSON's model_tests) has the same numbers
    mt = next(t for t in data["model_tests"] if t.get("constant") == "omega_gc")
    assert (mt["statistic"], mt["low"], mt["high"]) == (prior["statistic"], prior["low"],
                                                        prior["high"])
    x, lo, hi = compared(prior["statistic"], prior["low"], prior["high"])
    assert f"prior of omega_gc: estimate/sqrt(P0 - P) = {x} NOT in [{lo}, {hi}]" in text
    assert abs(prior["statistic"]) > prior["high"]       # it fails by its own numbers
    assert "sqrt(P0 - P:" not in text                    # no unclosed parenthesis
    assert data["reason_code"] == "prior_latitude" and "--latitude" in data["hint"]
    assert data["omega_gc"] is None and "omega_gc =" not in text
    # the JSON's NIS bands and whiteness limit are those of the checks (one band)
    for c in data["checks"]:
        if c["test"] == "mean NIS":
            assert data["nis_band"][c["subject"]] == [c["low"], c["high"]]
        elif c["test"].startswith("whiteness"):
            assert data["whiteness_limit"] == c["high"]


def test_gc_valid_estimate_text_json_and_object(monkeypatch, capsys):
    """A valid run: the estimate and σ with its named terms are the verdict's in both."""
    argv = ["calibrate", "gc", DATA / "gc_record.csv.gz"]
    code, text, data, ver, ver_j = _both(argv, gc, monkeypatch, capsys)
    assert code == 0 and ver.status == "ok" and ver.reason_code == "" and ver.hint == ""
    _hold_the_same(text, data, ver_j)
    assert data["omega_gc"] == ver_j.estimate and data["omega_gc_std"] == ver_j.sigma
    assert data["omega_gc_std_parts"] == dict(ver_j.sigma_parts)
    assert set(ver.sigma_parts) == {"noise", "instrument_biases", "scale"}
    assert sum(x * x for x in ver.sigma_parts.values()) == pytest.approx(ver.sigma**2,
                                                                         rel=1e-12)
    assert f"= {ver.estimate:.4e} ± {ver.sigma:.2e} rad/s" in text
    # the estimate is gc.calibrate's (the verdict judges it, it does not change it)
    assert ver.estimate == ver.result.omega_gc


def test_rsf_prior_failure_text_json_and_object(monkeypatch, capsys):
    """The sample RSF record with a roll-gyro tolerance of 10 ppm: the prior of
    ``eps1_hat_mean`` fails, named with the same value and band in the text, the JSON and
    the reason."""
    argv = ["calibrate", "rsf", DATA / "rsf_record.csv.gz", "--period", "1",
            "--sf-tolerance", "10"]
    code, text, data, ver, ver_j = _both(argv, rsf, monkeypatch, capsys)
    assert code == 3 and ver.status == "invalid"
    _hold_the_same(text, data, ver_j)
    prior = next(c for c in data["checks"] if c["test"] == "prior")
    assert prior["name"] == "prior of eps1_hat_mean" and not prior["passed"]
    x, lo, hi = compared(prior["statistic"], prior["low"], prior["high"])
    shown = f"prior of eps1_hat_mean: {prior['formula']} = {x} NOT in [{lo}, {hi}]"
    assert shown in text and shown in data["reason"]
    assert data["reason_code"] == "rsf_prior" and data["hint"].startswith("try: --sf-tol")
    # the uncertainty's own numbers: z = mean / sqrt(tolerance² + σ²)
    unc = ver.details["uncertainty"]
    assert prior["statistic"] == pytest.approx(unc.mean / (10e-6**2 + unc.std**2) ** 0.5,
                                               rel=1e-12)
    # and with the default tolerance the same record passes that check (power)
    code, out = _run([*argv[:-2], "--json"], capsys)
    ok = json.loads(out)
    assert code == 0 and all(c["passed"] for c in ok["checks"]) and ok["status"] == "ok"
    assert ok["eps1_hat_mean_std"] == pytest.approx(
        sum(x * x for x in ok["eps1_hat_mean_std_parts"].values()) ** 0.5, rel=1e-12)
