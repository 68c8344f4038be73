"""Paper RSF: which input the correction's error δK and the "90 %" claim are sensitive to
(Sobol' indices, :mod:`gyrolib.sensitivity`).

Outputs, from Eq. (7) of paper RSF (:func:`gyrolib.rsf.delta_k`) as
:func:`gyrolib.rsf.compensation_share` computes them:

* ``delta_k``: δK = [(ε0,GS + ε1,GS ω_unc) Δt + Δγ_enc] / (ω_x Δt);
* ``share``: the share of the roll gyro's SF error removed, 1 − δK/ε1.

Inputs (:func:`sensitivity_inputs`): paper RSF's *uncertain* rows of the table of inputs
(:mod:`gyrolib.inputs`) that Eq. (7) and the share read — ε0,GS (the GS gyro's biases, root sum
of squares), the encoder's position error Δγ_enc, the GS gyro's scale error ε1,GS and the roll
gyro's ε1 (which only the share depends on) — each over its row's range around the given
sensors' values (a data sheet's typical value: half to twice it, log-uniform): no range is
typed here.  The operating point (the correction interval Δt, the roll rate ω_x and the
uncompensated rate ω_uncs; the worked example's by default) is the user's choice, not
uncertain: it is held fixed (the study's condition) and gets elasticities only.
:func:`sensitivity_elasticities` gives ∂ ln y/∂ ln x of both outputs at the worked example,
to read beside the indices.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Final

import numpy as np
from numpy.typing import NDArray

from gyrolib import _validation as v
from gyrolib import input_rows
from gyrolib.rsf import inputs as rsf_inputs
from gyrolib.rsf.equations import delta_k
from gyrolib.rsf.sensors import (
    AEDB9340,
    GYPRO4300,
    SIIMU02_ROLL,
    EncoderSpec,
    MemsGyroSpec,
    RollGyroSpec,
)
from gyrolib.rsf.tables import (
    WORKED_EXAMPLE_OMEGA_UNC,
    WORKED_EXAMPLE_OMEGA_X,
    WORKED_EXAMPLE_PERIOD,
)
from gyrolib.sensitivity import (
    Elasticities,
    Recheck,
    SensitivityResult,
    SobolInput,
    elasticities,
    recheck,
    run_study,
)

__all__ = [
    "SENSITIVITY_OUTPUTS",
    "recheck_sensitivity",
    "sensitivity",
    "sensitivity_elasticities",
    "sensitivity_inputs",
    "sensitivity_outputs",
]

#: The study's outputs and their units.
SENSITIVITY_OUTPUTS: Final[tuple[str, ...]] = ("delta_k", "share")
_UNITS: Final[tuple[str, ...]] = ("1", "1")

#: The worked example's operating point (paper RSF, after Eq. (7)), the table's reference.
_PERIOD: Final[float] = WORKED_EXAMPLE_PERIOD
_OMEGA_X: Final[float] = WORKED_EXAMPLE_OMEGA_X
_OMEGA_UNC: Final[float] = WORKED_EXAMPLE_OMEGA_UNC

#: The table's rows the study samples, with the argument of :func:`sensitivity_outputs`
#: each sets (its name in the study).
_ROWS: Final[dict[str, str]] = {"rsf.gs_bias": "eps0_gs", "rsf.encoder_error": "encoder_error",
                                "rsf.eps1_gs": "eps1_gs", "rsf.eps1": "eps1"}
#: The operating point's arguments (held fixed).
_OPERATING: Final[tuple[str, ...]] = ("period", "omega_x", "omega_unc")

#: Sample points per chunk: Eq. (7) costs microseconds, so a chunk holds many thousands of
#: points (a tenth of a second of work) for a worker's hand-over to cost under 5 %.
_CHUNK: Final[int] = 8192


def sensitivity_inputs(gs_gyro: MemsGyroSpec = GYPRO4300, encoder: EncoderSpec = AEDB9340,
                       roll_gyro: RollGyroSpec = SIIMU02_ROLL) -> tuple[SobolInput, ...]:
    """The study's uncertain inputs: paper RSF's uncertain rows of the table of inputs that
    Eq. (7) and the share read, each over its row's range around the given sensors' values.

    Examples
    --------
    >>> from gyrolib import rsf
    >>> [(x.name, x.distribution) for x in rsf.sensitivity_inputs()][:2]
    [('eps1', 'loguniform'), ('eps0_gs', 'loguniform')]
    >>> x = rsf.sensitivity_inputs()[0]
    >>> round(x.low / x.nominal, 3), round(x.high / x.nominal, 3)
    (0.5, 2.0)
    """
    v.check_instance("gs_gyro", gs_gyro, MemsGyroSpec)
    v.check_instance("encoder", encoder, EncoderSpec)
    v.check_instance("roll_gyro", roll_gyro, RollGyroSpec)
    objs = {"MemsGyroSpec": gs_gyro, "EncoderSpec": encoder, "RollGyroSpec": roll_gyro}
    return tuple(r.sobol_input(float(input_rows.value_of(objs, r)), name=_ROWS[r.name])
                 for r in rsf_inputs.ROWS if r.name in _ROWS)


def _operating(period: float, omega_x: float, omega_unc: float) -> dict[str, float]:
    return {"period": v.check_positive("period", period),
            "omega_x": v.check_positive("omega_x", omega_x),
            "omega_unc": v.check_positive("omega_unc", omega_unc)}


def sensitivity_outputs(eps0_gs: float, encoder_error: float, period: float, omega_x: float,
                        omega_unc: float, *, eps1_gs: float = GYPRO4300.sf_error,
                        eps1: float = SIIMU02_ROLL.sf_error) -> tuple[float, float]:
    """δK (Eq. (7) of paper RSF) and the share 1 − δK/ε1 for one set of inputs (SI).

    Examples
    --------
    >>> import math
    >>> from gyrolib import rsf
    >>> dk, share = rsf.sensitivity_outputs(rsf.GYPRO4300.bias_total, math.radians(0.33), 5.0,
    ...                                     math.radians(900.0), math.radians(300.0))
    >>> f"{dk:.3e} {share:.3f}"
    '1.704e-04 0.716'
    """
    eps1 = v.check_positive("eps1", eps1)
    dk = delta_k(eps0_gs, encoder_error, omega_x, period, eps1_gs, omega_unc)
    return dk, 1.0 - dk / eps1


def _evaluate(points: NDArray[np.float64], context: tuple) -> NDArray[np.float64]:
    """The outputs at each row of ``points`` (a chunk; module level: it is pickled); the
    operating point from the context."""
    names, fixed = context
    return np.array([sensitivity_outputs(**dict(zip(names, map(float, row), strict=True)),
                                         **fixed)
                     for row in points]).reshape(-1, 2)


def sensitivity_elasticities(roll_gyro: RollGyroSpec = SIIMU02_ROLL,
                             gs_gyro: MemsGyroSpec = GYPRO4300,
                             encoder: EncoderSpec = AEDB9340, *, period: float = _PERIOD,
                             omega_x: float = _OMEGA_X,
                             omega_unc: float = _OMEGA_UNC) -> Elasticities:
    """∂ ln y/∂ ln x of δK and of the share at the operating point (default: the worked
    example's), for every input of :func:`sensitivity_inputs` and the operating point's
    Δt, ω_x and ω_unc (central differences of ±1 %).

    Returns
    -------
    gyrolib.sensitivity.Elasticities

    Examples
    --------
    >>> from gyrolib import rsf
    >>> e = rsf.sensitivity_elasticities()
    >>> f"{e.of('delta_k', 'omega_x'):.3f}", f"{e.of('delta_k', 'encoder_error'):.2f}"
    ('-1.000', '0.43')
    """
    v.check_instance("roll_gyro", roll_gyro, RollGyroSpec)
    inputs = sensitivity_inputs(gs_gyro, encoder, roll_gyro=roll_gyro)
    nominal = {x.name: x.nominal for x in inputs} | _operating(period, omega_x, omega_unc)
    return elasticities(nominal, sensitivity_outputs, SENSITIVITY_OUTPUTS)


def sensitivity(n: int, seed: int = 0, executor: object = None, *,
                roll_gyro: RollGyroSpec = SIIMU02_ROLL, gs_gyro: MemsGyroSpec = GYPRO4300,
                encoder: EncoderSpec = AEDB9340, period: float = _PERIOD,
                omega_x: float = _OMEGA_X, omega_unc: float = _OMEGA_UNC,
                chunk_size: int = _CHUNK,
                progress: Callable[[int], None] | None = None,
                second_order: bool = True,
                previous: SensitivityResult | None = None) -> SensitivityResult:
    """Sobol' indices of δK and of the share of the SF error removed (paper RSF, Eq. (7)
    and its "90 %") with respect to the four inputs of :func:`sensitivity_inputs`, at
    one operating point.

    Parameters
    ----------
    n : int
        Base sample size, a power of 2 (``10 n`` evaluations of Eq. (7)).
    seed : int, default 0
        Seed of the sample's scrambling and of the bootstrap intervals.
    executor : concurrent.futures.Executor, optional
        Where the chunks run (``None``: in this process).
    roll_gyro, gs_gyro, encoder : sensor records, optional
        The paper's sensors by default (the centres of the ranges).
    period, omega_x, omega_unc : float, optional
        The operating point (s, rad/s, rad/s; default: the worked example's 5 s, 900 °/s,
        300 °/s), held fixed.
    chunk_size : int, default 8192
        Sample points per chunk.
    progress : callable, optional
        Called with the number of points of each finished chunk.
    second_order : bool, default True
        Also estimate the second-order indices (the sample grows from ``n (D + 2)`` to
        ``n (2D + 2)`` points).
    previous : SensitivityResult, optional
        The same study with a smaller ``n``, whose points are reused (see
        :func:`gyrolib.sensitivity.run_study`).

    Returns
    -------
    SensitivityResult
        Outputs ``"delta_k"`` and ``"share"`` (dimensionless).

    Examples
    --------
    >>> from gyrolib import rsf
    >>> r = rsf.sensitivity(1024, seed=0)
    >>> top = r.ranked("delta_k")[0]
    >>> top[0], f"{top[1].value:.2f}"
    ('eps1_gs', '0.62')
    """
    v.check_instance("roll_gyro", roll_gyro, RollGyroSpec)
    inputs = sensitivity_inputs(gs_gyro, encoder, roll_gyro=roll_gyro)
    names = tuple(x.name for x in inputs)
    fixed = _operating(period, omega_x, omega_unc)
    return run_study("rsf", inputs, SENSITIVITY_OUTPUTS, _UNITS, _evaluate,
                     (names, fixed), n, seed,
                     executor=executor, chunk_size=chunk_size, progress=progress,
                     second_order=second_order, previous=previous, conditions=fixed,
                     settings={"equation": "Eq. (7)"})


def recheck_sensitivity(result: SensitivityResult, k: int = 5, seed: int = 0) -> Recheck:
    """Compute ``k`` points of a stored RSF study again (rows drawn with ``seed``).

    Examples
    --------
    >>> from gyrolib import rsf
    >>> rsf.recheck_sensitivity(rsf.sensitivity(8, seed=0), k=3).max_rel_diff < 1e-12
    True
    """
    v.check_instance("result", result, SensitivityResult)
    if result.model != "rsf":
        raise ValueError(f"result must be an RSF study (model 'rsf'); got {result.model!r}")
    c = result.conditions
    return recheck(result, _evaluate, (result.input_names,
                                       {k_: float(c[k_]) for k_ in _OPERATING}), k=k, seed=seed)
