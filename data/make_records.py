"""Make the sample records of ``data/`` with gyrolib's simulators (seeded) and write
``data/truth.json`` and ``data/README.md`` (the truth beside them).

    .venv/bin/python data/make_records.py            # the records, truth.json, README.md
    .venv/bin/python data/make_records.py --readme   # README.md only (from truth.json)

Deterministic: the same seeds give the same files (gzip without a time stamp).
"""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np

from gyrolib import gc, rsf
from gyrolib.records import write_csv
from gyrolib.units import from_si

HERE = Path(__file__).resolve().parent
PACKAGE_DATA = HERE.parent / "gyrolib" / "data"

GC_SEED = 2026
GC_WRONG_SEED = 2027
RSF_SEED = 2028
GC_T_END = 100.0
GAP = (60.0, 61.0)               # s: rows removed (a 1 s gap)
OUTLIER_T0, OUTLIER_N, OUTLIER_SIZE = 30.0, 20, 5e-4   # angle-sensor burst: 20 rows, ±0.5 mrad
N_NAN = 30                       # NaN cells spread over the three sensors
WRONG_ALPHA1_FACTOR = 10.0       # the "wrong" record: vibration bandwidth α1 ten times larger
#: Where the GC sample records are made: paper GC's printed Omega_h = 4.3e-5, Omega_v = 5.9e-5
#: rad/s are the Earth's rate at about 53.9° N rounded to two digits; the records are simulated
#: with the Earth's rate at exactly this latitude (GyrocompassParams.at_latitude), so that the
#: first line of every GC file, which the reader turns into GCRecord.latitude, is the truth.
LATITUDE_DEG = 53.9
LATITUDE_LINE = f"latitude_deg: {LATITUDE_DEG}"
RSF_DURATION, RSF_RATE, RSF_PERIOD = 60.0, 1000.0, 1.0


def _degrade(rec: gc.GCRecord, seed: int) -> tuple[gc.GCRecord, dict]:
    """A gap, NaN cells and an angle-sensor outlier burst, as a real log might have."""
    rng = np.random.default_rng(seed)
    a, y, z = (np.array(c) for c in (rec.angle_sensor, rec.inclinometer_y, rec.inclinometer_z))
    burst = np.nonzero(rec.t > OUTLIER_T0)[0][:OUTLIER_N]
    a[burst] += OUTLIER_SIZE * rng.choice([-1.0, 1.0], burst.size)
    cells = rng.choice(rec.n, N_NAN, replace=False)
    for k, col in enumerate((a, y, z)):
        col[cells[k::3]] = np.nan
    keep = ~((rec.t > GAP[0]) & (rec.t <= GAP[1]))
    out = gc.GCRecord(t=rec.t[keep], angle_sensor=a[keep], inclinometer_y=y[keep],
                      inclinometer_z=z[keep])
    return out, {"gap_s": list(GAP), "outlier_times_s": [float(x) for x in rec.t[burst]],
                 "nan_cells": N_NAN}


def _gc_file(name: str, rec: gc.GCRecord, comments: list[str]) -> None:
    write_csv(HERE / name, {"t": rec.t, "angle_sensor": rec.angle_sensor,
                            "inclinometer_y": rec.inclinometer_y,
                            "inclinometer_z": rec.inclinometer_z},
              comments=[LATITUDE_LINE, *comments], fmt=["%.3f", "%.9g", "%.9g", "%.9g"])


def main() -> dict:
    p = gc.GyrocompassParams.at_latitude(math.radians(LATITUDE_DEG))
    truth: dict = {}

    sim = gc.simulate_record(p, GC_T_END, seed=GC_SEED)
    rec, damage = _degrade(sim.record, GC_SEED)
    _gc_file("gc_record.csv.gz", rec, [
        "paper GC record simulated by gyrolib.gc.simulate_record (truth model, paper's "
        f"parameters, Earth's rate at {LATITUDE_DEG}° N), seed {GC_SEED}, {GC_T_END:g} s at 1 kHz",
        f"with a gap {GAP[0]:g}-{GAP[1]:g} s, {N_NAN} NaN cells and a burst of {OUTLIER_N} "
        "angle-sensor outliers; truth in data/truth.json",
        "SI units: t s, angle_sensor rad, inclinometers m/s^2"])
    truth["gc_record.csv.gz"] = {
        "method": "gc", "seed": GC_SEED, "t_end_s": GC_T_END,
        "params": f"paper's, Earth-rate components at {LATITUDE_DEG}° N",
        "omega_gc_rad_s": sim.omega_gc,
        "omega_gc_arcsec_paper_s": float(from_si(sim.omega_gc, "arcsec_paper/s")),
        **damage,
        "call": (f"gc.simulate_record(gc.GyrocompassParams.at_latitude(math.radians("
                 f"{LATITUDE_DEG})), {GC_T_END}, seed={GC_SEED})")}

    p_wrong = dataclasses.replace(p, alpha1=p.alpha1 * WRONG_ALPHA1_FACTOR)
    sim_w = gc.simulate_record(p_wrong, GC_T_END, seed=GC_WRONG_SEED)
    _gc_file("gc_record_wrong_spectrum.csv.gz", sim_w.record, [
        "paper GC record whose vibration spectrum differs from the paper's model: alpha1 "
        f"x{WRONG_ALPHA1_FACTOR:g}, seed {GC_WRONG_SEED}, {GC_T_END:g} s at 1 kHz",
        "SI units: t s, angle_sensor rad, inclinometers m/s^2"])
    truth["gc_record_wrong_spectrum.csv.gz"] = {
        "method": "gc", "seed": GC_WRONG_SEED, "t_end_s": GC_T_END,
        "params": f"paper, alpha1 x {WRONG_ALPHA1_FACTOR:g} = {p_wrong.alpha1} rad/s",
        "alpha1": p_wrong.alpha1,
        "omega_gc_rad_s": sim_w.omega_gc,
        "omega_gc_arcsec_paper_s": float(from_si(sim_w.omega_gc, "arcsec_paper/s")),
        "call": (f"gc.simulate_record(gc.GyrocompassParams.at_latitude(math.radians("
                 f"{LATITUDE_DEG}), alpha1={p_wrong.alpha1}), {GC_T_END}, "
                 f"seed={GC_WRONG_SEED})")}

    cfg = rsf.SimulationConfig(duration=RSF_DURATION, sample_rate=RSF_RATE)
    flight = rsf.simulate_flight(cfg, seed=RSF_SEED)
    r = rsf.record_from_simulation(flight)
    write_csv(HERE / "rsf_record.csv.gz",
              {"t": r.t, "sins_increment": r.sins_increment, "gs_angle": r.gs_angle},
              comments=[f"paper RSF record simulated by gyrolib.rsf.simulate_flight, seed "
                        f"{RSF_SEED}, {RSF_DURATION:g} s at {RSF_RATE:g} Hz, 900 deg/s, "
                        "paper's sensors; truth in data/truth.json",
                        "SI units: t s, sins_increment rad, gs_angle rad"],
              fmt=["%.3f", "%.12g", "%.15g"])
    e = rsf.record_from_simulation(flight, encoder=True)
    write_csv(HERE / "rsf_record_encoder.csv.gz",
              {"t": e.t, "sins_increment": e.sins_increment,
               "encoder_counts": e.encoder_counts, "gs_gyro_angle": e.gs_gyro_angle},
              comments=[f"the flight of rsf_record.csv.gz (seed {RSF_SEED}) with the raw GS "
                        f"readings: wrapped encoder counts ({cfg.encoder.counts_per_rev} per "
                        "revolution) and the integrated GS gyro angle (rad)"],
              fmt=["%.3f", "%.12g", "%d", "%.15g"])
    pred = rsf.predict_delta_k(cfg, RSF_PERIOD)
    for name in ("rsf_record.csv.gz", "rsf_record_encoder.csv.gz"):
        truth[name] = {
            "method": "rsf", "seed": RSF_SEED, "duration_s": RSF_DURATION,
            "sample_rate_hz": RSF_RATE, "roll_rate_rad_s": cfg.roll.rate_start,
            "eps1_sins": float(flight.eps1_sins[0]), "eps0_sins_rad_s": float(flight.eps0_sins[0]),
            "eps1_gs": float(flight.eps1_gs[0]), "eps0_gs_rad_s": float(flight.eps0_gs[0]),
            "counts_per_rev": cfg.encoder.counts_per_rev,
            "period_s": RSF_PERIOD,
            "delta_k_predicted": {"mean": pred.mean, "std": pred.std},
            "call": (f"rsf.simulate_flight(rsf.SimulationConfig(duration={RSF_DURATION}, "
                     f"sample_rate={RSF_RATE}), seed={RSF_SEED})")}
    (HERE / "truth.json").write_text(json.dumps(truth, indent=2) + "\n")
    _readme(truth)
    return truth


def _sensitivity_section() -> str:
    """What ``gyrolib/data/`` holds of the sensitivity studies, read from the files themselves
    (their model, size, inputs, outputs and the command that wrote them)."""
    lines = ["## Sensitivity studies", "",
             "The chapter *What the verdicts are sensitive to* reads two Sobol' studies of the "
             "claims'",
             "margins; they are not written by `make_records.py` but by the `sensitivity` "
             "command, once,",
             "offline, and ship with the package beside the claims' maps (the README's section",
             "*Sensitivity studies* tells how to spread them over workers).  Their inputs are "
             "the table of",
             "inputs' uncertain rows that a paper's claims read, over the table's ranges "
             "(`gyrolib.inputs`);",
             "each file names the table's fingerprint, and the chapter recomputes a few of its "
             "points:", ""]
    for name in ("gc", "rsf"):
        path = PACKAGE_DATA / f"sensitivity_{name}.json"
        d = json.loads(path.read_text())
        run = d["run"]
        outs = ", ".join(f"`{o}`" for o in d["outputs"])
        order = ("first-order and total indices" if d.get("second_order") in (None, {}) or
                 not any(d["second_order"].values()) else "with the second-order indices")
        lines += [f"* `gyrolib/data/{path.name}`: {d['model']}, N = {d['n']} (seed "
                  f"{d['seed']}), {len(d['inputs'])} inputs, {run['model_runs']} model runs, "
                  f"{order};", f"  outputs {outs};",
                  f"  written by gyrolib {run['version']}: `{run['command']}`"]
    lines += ["", "Until version 0.4.0 this folder held the studies of σ_gc(100 s), t_c, δK "
              "and the share over",
              "ranges of their own (±10 % of a printed value, operating points drawn as "
              "uncertain, no rival);",
              "they were replaced by the studies over the table of inputs.", ""]
    return "\n".join(lines)


def _readme(truth: dict) -> None:
    (HERE / "README.md").write_text(readme_text(truth))


def readme_text(truth: dict) -> str:
    """``data/README.md`` for ``truth`` (the records' sizes read from the files)."""
    rows = []
    for name, tr in truth.items():
        size = (HERE / name).stat().st_size
        if tr["method"] == "gc":
            what = (f"ω_gc = {tr['omega_gc_rad_s']:.6e} rad/s "
                    f"({tr['omega_gc_arcsec_paper_s']:.5f} ″/s); model: {tr['params']}")
        else:
            what = (f"ε1 (SINS) = {tr['eps1_sins']:.6g}, ε1/(1+ε1) = "
                    f"{tr['eps1_sins'] / (1 + tr['eps1_sins']):.6g}; predicted δK per "
                    f"{tr['period_s']:g} s interval {tr['delta_k_predicted']['mean']:.3g} ± "
                    f"{tr['delta_k_predicted']['std']:.3g}")
        rows.append(f"| `{name}` | {tr['seed']} | {what} | {size / 1e6:.2f} MB |")
    text = f"""# Sample records

Made by `data/make_records.py` (run `.venv/bin/python data/make_records.py`; this file and
`truth.json` are written by it) with gyrolib's own simulators and fixed seeds.  They are the
inputs of the chapter "Calibrating your own gyro" and of `python -m gyrolib calibrate`.
The acceptance tests do **not** use them: they simulate their own records with other seeds.

| file | seed | truth | size |
| --- | --- | --- | --- |
{chr(10).join(rows)}

* `gc_record.csv.gz`: the paper's model, 100 s at 1 kHz (`gc.simulate_record`, rows at
  t = 1 ms … 100 s), then damaged as a real log might be: rows of the gap
  {GAP[0]:g}–{GAP[1]:g} s removed, {N_NAN} NaN cells, a burst of {OUTLIER_N} angle-sensor
  outliers of ±{OUTLIER_SIZE * 1e3:g} mrad after t = {OUTLIER_T0:g} s (their times are in
  `truth.json`).
* `gc_record_wrong_spectrum.csv.gz`: simulated with the vibration shaping filter's α1
  {WRONG_ALPHA1_FACTOR:g} times the paper's (a different vibration spectrum) and calibrated
  with the paper's model: the diagnostics must say the model does not fit.
* `rsf_record.csv.gz`: `rsf.simulate_flight` with the paper's sensors ("fixed" errors, the
  +1σ values), 900 °/s, 60 s at 1 kHz; columns `t`, `sins_increment`, `gs_angle`.
* `rsf_record_encoder.csv.gz`: the same flight with the GS's raw readings: wrapped
  `encoder_counts` (use `--counts-per-rev {truth['rsf_record_encoder.csv.gz']['counts_per_rev']}`)
  and `gs_gyro_angle`, the integrated GS gyro (the GS angle is their sum).

All columns are SI (s, rad, m/s²).  Truth values in full precision: `truth.json`.  Each GC
file's first line is `# latitude_deg: {LATITUDE_DEG}`, where it was made: the records are
simulated with the Earth's rate at {LATITUDE_DEG}° N (`gc.GyrocompassParams.at_latitude`), the
latitude whose components paper GC prints rounded (Ω_h = 4.3·10⁻⁵, Ω_v = 5.9·10⁻⁵ rad/s), so
the command, which reads that line, uses the Earth-rate components the records were made with.

{_sensitivity_section()}"""
    return text


if __name__ == "__main__":
    import sys

    if sys.argv[1:] == ["--readme"]:     # the README only, from the records and truth.json
        _readme(json.loads((HERE / "truth.json").read_text()))
    else:
        main()
