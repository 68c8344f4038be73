"""Every reason code of paper GC's verdict (:data:`gyrolib.reasons.REASONS`) is triggered by a
record made to show its fault, and the hint of a fault that masks another never names an
option that would hide it.

The records are 20 s of paper GC's model (seed 3401) with one fault put on by this file's
own arithmetic: noise added to a column (its variance known), a drift that steps or is far
beyond its prior, a record at another latitude, an angle offset or an inclinometer bias
beyond its prior, a clock that runs fast.  Each is judged with the command line's default
priors (:func:`tests.support.gc_faults.cli_params`), and the code must be among the verdict's
``reason_codes`` and its hint name the code's option.  The codes of the command's own
refusals and of paper RSF and of the noise fit are triggered by the test files named in
:data:`ELSEWHERE`."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

from gyrolib import gc
from gyrolib.reasons import REASONS, hint
from gyrolib.units import ARCSEC_PAPER
from tests.support import gc_faults as F

P = F.P
T_END = 20.0
TAU = P.I / P.f
ROOT = Path(__file__).resolve().parents[1]

#: Codes triggered by records of other test files (the command line, paper RSF, the fit).
ELSEWHERE: dict[str, str] = {
    "early_release": "cli/test_hints.py", "no_latitude": "cli/test_hints.py",
    "misfit": "cli/test_hints.py", "fit_not_converged": "cli/test_hints.py",
    "fit_not_identified": "cli/test_hints.py", "fit_absorbs_misfit": "gc/test_priors.py",
    "rsf_scatter": "rsf/test_uncertainty.py",
    "rsf_bias": "rsf/test_uncertainty.py", "rsf_prior": "rsf/test_judgement.py",
    "bad_option": "cli/test_hints.py", "bad_input": "cli/test_hints.py",
    "units": "cli/test_calibrate_io.py"}

#: Codes no test record triggers yet, with why (the check's table is kept honest by
#: :func:`test_every_code_has_a_record_that_triggers_it`).
NOT_YET: dict[str, str] = {
    "fit_implausible": "needs a noise fit (--fit-noise) whose fitted level's interval lies "
                       "outside its plausible range; no record of the tests makes one",
    "prior_tilt": "the inclinometers read the tilts directly, so a tilt far beyond its prior "
                  "is rejected by the gate from the first sample (a lost lock, whose reason "
                  "names the tilt); with the record's tilt at 3.65 to 7 prior sigma the "
                  "test's z stays at 2.5 to 3.1 (the vibration N1 common to both "
                  "inclinometers shrinks the estimate) and the gate takes over beyond"}


@pytest.fixture(scope="module")
def sim():
    return gc.simulate_record(P, T_END, seed=3401)


def _record(sim, **cols) -> gc.GCRecord:
    r = sim.record
    base = {"t": r.t, "angle_sensor": r.angle_sensor, "inclinometer_y": r.inclinometer_y,
            "inclinometer_z": r.inclinometer_z}
    return gc.GCRecord(**{**base, **cols})


def _noisy(sim, factor: float, seed: int) -> gc.GCRecord:
    """The angle sensor with white noise of ``factor`` times its variance added."""
    sd = math.sqrt(gc.measurement_noise_covariance(P)[0, 0] * factor)
    r = sim.record
    return _record(sim, angle_sensor=r.angle_sensor
                   + np.random.default_rng(seed).normal(0.0, sd, r.n))


def _drift_ramp(sim, dw: float, t0: float) -> gc.GCRecord:
    """A drift ``dw`` (rad/s) more from ``t0``: the float turns (H/f) dw faster after its
    time constant (closed form of Eq. (3) without the restoring torque)."""
    s = np.clip(sim.record.t - t0, 0.0, None)
    return _record(sim, angle_sensor=sim.record.angle_sensor
                   + (P.H / P.f) * dw * (s - TAU * (1.0 - np.exp(-s / TAU))))


def _cases(sim) -> dict[str, tuple[gc.GCRecord, gc.GyrocompassParams]]:
    cp = F.cli_params()
    r = sim.record
    at45 = F.make("latitude", 45.0, 3401, T_END).record
    return {
        "misfit_nis": (_noisy(sim, 0.3, 1), cp),
        "lost_lock_nis": (_noisy(sim, 1.9, 2), cp),
        "lost_lock_gate": (_noisy(sim, 900.0, 3), cp),
        "lost_lock": (_noisy(sim, 900.0, 3), cp),
        "drift_changes": (_drift_ramp(sim, 0.5 * ARCSEC_PAPER, 0.5 * T_END), cp),
        "misfit_split": (_drift_ramp(sim, 0.5 * ARCSEC_PAPER, 0.5 * T_END), cp),
        "misfit_whiteness": (_drift_ramp(sim, 0.5 * ARCSEC_PAPER, 0.5 * T_END), cp),
        "prior_latitude": (at45, cp),
        "prior_scale": (at45, cp),
        "prior_clock": (at45, dataclasses.replace(cp, sigma_hf_scale=0.0, sigma_clock=1e-3)),
        "prior_drift": (_drift_ramp(sim, 3.5e-5, 0.0), cp),
        "prior_offset": (_record(sim, angle_sensor=r.angle_sensor + 90.0 * ARCSEC_PAPER), cp),
        "prior_incl_bias": (_record(sim, inclinometer_z=r.inclinometer_z - 1.5e-3 * P.g), cp),
        "latitude": (dataclasses.replace(r, latitude=math.radians(45.0)), cp),
        "latitude_mismatch": (dataclasses.replace(r, latitude=math.radians(45.0)), cp),
    }


def test_every_code_has_a_record_that_triggers_it(sim):
    here = set(_cases(sim))
    known = here | set(ELSEWHERE) | set(NOT_YET)
    assert set(REASONS) == known, set(REASONS) ^ known
    assert not here & set(ELSEWHERE) and not (here | set(ELSEWHERE)) & set(NOT_YET)
    for code, where in ELSEWHERE.items():
        assert code in (ROOT / where).read_text("utf-8"), (code, where)


@pytest.mark.parametrize("code", sorted(set(REASONS) - set(ELSEWHERE) - set(NOT_YET)))
def test_the_record_triggers_its_code_and_hint(sim, code):
    rec, params = _cases(sim)[code]
    ver = gc.judge_record(rec, params)
    assert not ver.valid and code in ver.reason_codes, (code, ver.reason_codes)
    # counts never exceed the record; one statistic, one band, printed the same in the
    # reason, the check's line and its JSON
    n = rec.n
    assert ver.counts.rows == n and 0 <= ver.counts.missing <= 3 * n
    assert max(ver.counts.used, ver.counts.rejected, ver.counts.empty) <= n
    for c in ver.checks:
        assert c.summary()["band"] == c.band() and c.band() in c.line()
        if c.test == "mean NIS" and not c.passed:
            assert f"NOT in {c.band()}" in ver.reason, (c.line(), ver.reason)
    assert ver.hint.startswith("try: ") and ver.hint == hint(ver.reason_code, (
        ver.hint.split(" ")[2] if ver.reason_code == "early_release" else ""))
    if code.startswith("prior_") and code != "prior_latitude":
        # the failed prior check names its state, and its cause names the code's option
        failed = [c for c in ver.failed if c.test == "prior" and c.reason_code == code]
        assert failed and all(c.line().startswith(f"prior of {c.subject}:") for c in failed)
        if REASONS[code].option != "--params":
            assert any(REASONS[code].option in c.cause for c in failed), code


def test_a_lost_lock_is_never_hinted_at_a_prior(sim):
    """99.9 % of the angle sensor's samples rejected (noise 30 times the model's σ): the
    verdict names the lost lock, and no hint names a prior or tolerance, which would widen
    the prior and mask the fault (the failed prior checks are its symptoms)."""
    ver = gc.judge_record(_noisy(sim, 900.0, 3), F.cli_params())
    assert ver.result.rejected_share[0] > 0.5
    assert ver.reason_code == "lost_lock" and REASONS["lost_lock"].option == "--params"
    assert any(c.startswith("prior_") for c in ver.reason_codes)     # the symptoms are there
    for opt in ("--inclinometer-bias-prior", "--scale-tolerance", "--drift-prior",
                "--offset-prior", "--clock-tolerance"):
        assert opt not in ver.hint
    counts = ver.counts
    assert counts.used + counts.rejected + counts.empty == counts.rows == sim.record.n


def test_a_gyro_misaligned_out_of_the_horizontal_is_covered_or_named(sim):
    """The gyro's input axis tilted 10′ out of the horizontal senses Ω_v ε: the record is a
    clean one whose γ inclinometer does not see that tilt (it reads ``g (γ − ε)`` while the
    float feels γ).  With the default priors it is refused naming the γ inclinometer's
    bias, its option and the tilt in arcmin (≈ 10′), or covered within 3σ; with the prior
    the hint names widened to 3 mg (> g ε = 2.9 mg) it is covered."""
    eps = math.radians(10.0 / 60.0)
    sim100 = gc.simulate_record(P, 100.0, seed=3402)
    r = sim100.record
    rec = dataclasses.replace(r, inclinometer_z=r.inclinometer_z - P.g * math.sin(eps))
    ver = gc.judge_record(rec, F.cli_params())
    if ver.valid:
        assert abs(ver.estimate - sim100.omega_gc) <= 3.0 * ver.sigma
    elif ver.reason_code == "lost_lock":
        # the gate rejects the γ inclinometer from its first sample on: the reason names the
        # state and its option (the hint stays the lost lock's, which masks nothing)
        assert ver.result.rejected_share[2] >= 0.99
        assert ("the state inclinometer_z_bias beyond its prior (--inclinometer-bias-prior), "
                "or the gyro's input axis tilted out of the horizontal, which reads as that "
                "bias, the tilt gamma beyond its prior") in ver.reason
    else:
        assert ver.reason_code == "prior_incl_bias"
        assert "--inclinometer-bias-prior" in ver.hint
        bias = next(c for c in ver.failed if c.subject == "inclinometer_z_bias")
        tilt = float(bias.cause.split("horizontal by about ")[1].split(" arcmin")[0])
        assert tilt == pytest.approx(10.0, rel=0.3)
    wide = gc.judge_record(rec, F.cli_params(sigma_incl_bias=3e-3 * P.g))
    assert wide.valid and abs(wide.estimate - sim100.omega_gc) <= 3.0 * wide.sigma


def test_an_hf_error_reads_as_drift_and_is_covered_by_its_tolerance():
    """H/f 0.5 % off (the simulated gyro's H 1.005 times the model's), 100 s: the record
    cannot tell a scale error from drift (the float's steady rate is (H/f)(Ω_h + ω_gc)), so
    at the default tolerance 10⁻³ no check can fire: the scale state's prior check passes
    because the record removes < 1 % of its prior variance, and ω̂_gc is off by κ Ω_h
    (within 20 %), several σ.  Stated as 5·10⁻³ (``--scale-tolerance``), the scale term
    covers it within 3σ."""
    kappa = 5e-3
    fr = F.make("hf_scale", kappa, 3403, 100.0)
    ver = gc.judge_record(fr.record, F.cli_params())
    res = ver.result
    c = res.bias_names.index("scale")
    removed = 1.0 - res.bias_cov[c, c] / res.bias_prior[c] ** 2
    assert 0.0 <= removed < 0.01
    assert ver.valid and all(ch.passed for ch in ver.checks if ch.test == "prior")
    assert ver.estimate - fr.omega_gc == pytest.approx(kappa * P.Omega_h, rel=0.2)
    assert (ver.estimate - fr.omega_gc) / ver.sigma > 3.0          # the default misses it
    stated = gc.judge_record(fr.record, F.cli_params(sigma_hf_scale=kappa))
    assert stated.valid and abs(stated.estimate - fr.omega_gc) <= 3.0 * stated.sigma


def test_a_tilt_far_beyond_its_prior_is_a_lost_lock_that_names_it(sim):
    """The simulated γ at 8 prior σ (the filter's sigma_gamma0 an eighth of it, no bias
    prior): the gate rejects inclinometer_z from its first sample, and the reason names the
    tilt and where its prior is set; the angle sensor keeps lock (power: the same record
    with the paper's prior is valid)."""
    g = abs(float(sim.truth[0, gc.state_index("gamma")]))
    cp = F.cli_params(sigma_incl_bias=0.0)
    ver = gc.judge_record(sim.record, dataclasses.replace(cp, sigma_gamma0=g / 8.0))
    assert ver.reason_code == "lost_lock" and ver.result.rejected_share[2] >= 0.99
    assert ver.result.rejected_share[0] < 0.01
    assert "the tilt gamma beyond its prior (sigma_gamma0 in --params)" in ver.reason
    assert gc.judge_record(sim.record, cp).valid
