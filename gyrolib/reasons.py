"""Why a run was refused, as a stable code, and the option the evidence points to.

Every refusal of a calibration (:func:`gyrolib.gc.judge_record`,
:func:`gyrolib.rsf.judge_record`: no valid estimate; the ``calibrate`` command's bad input,
exit 2) carries a ``reason_code`` from :data:`REASONS` and its ``hint``, both held by the
:class:`gyrolib.verdict.Verdict` and shown by the command in the JSON (``"reason_code"``,
``"hint"``), in ``--summary``'s columns of those names, and as the text's last line,
``try: ...``.  The codes are stable (scripts may test them); a new check adds its row here,
and ``tests/cli/test_hints.py`` checks that each row names an option of the command's
parser (the option is the command's name for the parameter of the same meaning).

A leaf module: it imports nothing of gyrolib, so the library and the command line read it.

Examples
--------
>>> REASONS["no_latitude"].option
'--latitude'
>>> hint("misfit")[:50]
'try: --fit-noise (fit the sensor noises to the rec'
>>> primary(["misfit", "no_latitude"])
'no_latitude'
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable
from typing import Final

__all__ = ["REASONS", "Reason", "hint", "primary"]


@dataclasses.dataclass(frozen=True)
class Reason:
    """One kind of refusal: the ``option`` its evidence points to and ``why`` that option
    (a phrase, shown after it); ``rank``: the lower, the earlier it is named when a run has
    several (a cause before its symptoms: a wrong latitude makes the model misfit too)."""

    option: str
    why: str
    rank: int


#: reason_code -> the option to try.  Extend it for a new check (keep the codes stable).
REASONS: Final[dict[str, Reason]] = {
    # the site: the Earth rate reads as drift
    "no_latitude": Reason("--latitude", "state the test site's latitude in degrees, south "
                          "negative (or a 'latitude' key in --params; '--latitude paper' assumes "
                          "paper GC's site)", 10),
    "latitude_mismatch": Reason("--latitude", "the Earth rate given disagrees with the "
                                "record's '# latitude_deg:' line: state the site's latitude "
                                "once", 11),
    # the record's start: rows before the feedback was switched off
    "early_release": Reason("--t0", "the rows the model rejects lie at the record's start "
                            "(logged before the feedback switch-off?): start later", 20),
    # the noise fit
    "fit_not_converged": Reason("--fit", "the noise fit did not converge: fit fewer "
                                "parameters (e.g. --fit C_as,C_in)", 40),
    "fit_not_identified": Reason("--fit", "the record cannot pin a fitted parameter down: "
                                 "leave it out of --fit (or give it in --params)", 41),
    # the filter and the model checks
    "lost_lock": Reason("--params", "the gate rejected too many samples or the NIS is far "
                        "off: check the units and the instrument's noise in --params", 50),
    "misfit": Reason("--fit-noise", "fit the sensor noises to the record; the model checks "
                     "failed with the params given", 60),
    "drift_changes": Reason("--t0", "the split-record test says the drift estimate moves "
                            "within the record: calibrate a later part of it", 61),
    # the library's own codes (gyrolib.gc.CalibrationResult.reason_codes, the noise fit's
    # checks, gyrolib.rsf's uncertainty checks), each with the option its evidence points to
    "latitude": Reason("--latitude", "the Earth rate given is not the one at the record's "
                       "stated latitude", 11),
    "prior_latitude": Reason("--latitude", "the drift estimate is what a site at another "
                             "latitude would give: check the latitude", 13),
    "prior_drift": Reason("--drift-prior", "the drift estimate lies far outside its prior: "
                          "widen the prior if the gyro really drifts this much", 30),
    "prior_scale": Reason("--scale-tolerance", "H/f or the angle sensor's gain is off by more "
                          "than its tolerance: check H/f, or state a wider tolerance", 31),
    "prior_offset": Reason("--offset-prior", "the angle sensor's offset lies far outside its "
                           "prior", 32),
    "prior_incl_bias": Reason("--inclinometer-bias-prior", "an inclinometer's bias lies far "
                              "outside its prior", 33),
    "prior_clock": Reason("--clock-tolerance", "the logger's time scale is off by more than "
                          "its tolerance", 34),
    "prior_tilt": Reason("--params", "a tilt or the azimuth lies far outside its prior: "
                         "state the priors of the stand in --params", 35),
    "fit_absorbs_misfit": Reason("--params", "the fit moved the noise levels by one common "
                                 "factor, a time base's signature: check the logger's rate "
                                 "(--clock-tolerance) rather than fitting it away", 42),
    "fit_implausible": Reason("--params", "a fitted noise level lies outside its plausible "
                              "range in the table of inputs", 43),
    "lost_lock_gate": Reason("--params", "the gate rejected too many samples: check the "
                             "units and the instrument's noise in --params", 50),
    "lost_lock_nis": Reason("--params", "a sensor's mean NIS is far off: check the units "
                            "and the instrument's noise in --params", 51),
    "misfit_nis": Reason("--fit-noise", "a mean-NIS test failed: fit the sensor noises to "
                         "the record", 60),
    "misfit_whiteness": Reason("--fit-noise", "a whiteness test failed: fit the noise "
                               "model to the record", 60),
    "misfit_split": Reason("--t0", "the split-record test says the drift estimate moves "
                           "within the record: calibrate a later part of it", 61),
    # paper RSF's checks
    "rsf_scatter": Reason("--params", "the intervals scatter more than the error model "
                          "predicts: check the sensor models in --params", 70),
    "rsf_bias": Reason("--sins-bias-tolerance", "the SINS and GS biases over the roll rate "
                       "exceed their tolerances: state them, or fly a reversing roll", 71),
    "rsf_prior": Reason("--sf-tolerance", "the SF error estimate lies far outside its prior",
                        72),
    # bad input (exit 2)
    "bad_option": Reason("--help", "an option's value is out of its range", 90),
    "bad_input": Reason("--columns", "the file cannot be read as a record: check its "
                        "columns and units", 91),
    "units": Reason("--params", "a column's values are implausible in SI", 92),
}


def hint(code: str, value: str = "") -> str:
    """The ``try:`` line of ``code`` (a key of :data:`REASONS`), with the option's ``value``
    when the evidence suggests one (``--t0 2.5``)."""
    r = REASONS[code]
    option = f"{r.option} {value}" if value else r.option
    return f"try: {option} ({r.why})"


def primary(codes: Iterable[str]) -> str:
    """The code the evidence points to first, among ``codes`` (keys of :data:`REASONS`):
    the lowest rank; ``""`` when there is none."""
    known = [c for c in codes if c in REASONS]
    return min(known, key=lambda c: REASONS[c].rank) if known else ""
