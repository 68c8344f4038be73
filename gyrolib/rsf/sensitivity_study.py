"""Paper RSF: which input the correction's error δK and the "90 %" claim are sensitive to
(Sobol' indices, :mod:`gyrolib.sensitivity`).

Outputs, from Eq. (7) of paper RSF (:func:`gyrolib.rsf.delta_k`) as
:func:`gyrolib.rsf.compensation_share` computes them:

* ``delta_k``: δK = [(ε0,GS + ε1,GS ω_unc) Δt + Δγ_enc] / (ω_x Δt);
* ``share``: the share of the roll gyro's SF error removed, 1 − δK/ε1.

Inputs (:func:`sensitivity_inputs`), all printed, so all by the one rule ±10 % uniform:
ε0,GS, the encoder's position error Δγ_enc (printed in the worked example's Eq. (7)), the
correction period Δt, the roll rate ω_x, the uncompensated rate ω_unc, the GS gyro's scale
error ε1,GS and the roll gyro's ε1 (which only the share depends on).
:func:`sensitivity_elasticities` gives ∂ ln y/∂ ln x of both outputs at the worked example,
to read beside the indices.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Final

import numpy as np
from numpy.typing import NDArray

from gyrolib import _validation as v
from gyrolib.rsf.equations import delta_k
from gyrolib.rsf.sensors import (
    AEDB9340,
    GYPRO4300,
    SIIMU02_ROLL,
    EncoderSpec,
    MemsGyroSpec,
    RollGyroSpec,
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
from gyrolib.units import to_si

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

#: The worked example's conditions (paper RSF, after Eq. (7)): Δt = 5 s, ω_x = 900 °/s,
#: ω_unc = 300 °/s.
_PERIOD: Final[float] = 5.0
_OMEGA_X: Final[float] = float(to_si(900.0, "deg/s"))
_OMEGA_UNC: Final[float] = float(to_si(300.0, "deg/s"))

#: Sample points per chunk: Eq. (7) costs microseconds, so a chunk holds many thousands of
#: points (a tenth of a second of work) for a worker's hand-over to cost under 5 %.
_CHUNK: Final[int] = 8192


def sensitivity_inputs(gs_gyro: MemsGyroSpec = GYPRO4300, encoder: EncoderSpec = AEDB9340,
                       period: float = _PERIOD, omega_x: float = _OMEGA_X,
                       omega_unc: float = _OMEGA_UNC,
                       roll_gyro: RollGyroSpec = SIIMU02_ROLL) -> tuple[SobolInput, ...]:
    """The study's uncertain inputs with their ranges, centred on the paper's values.

    The book's one range rule: a printed value varies ±10 % (uniform), an unstated one over
    a defended wide range.  Every input here is printed: ε0,GS = √(σ_rep² + σ_stab²) and
    ε1,GS from the GS gyro's table, ε1 from Table 1, and the worked example's Δγ_enc = 0.33°
    (its Eq. (7); lost only in the encoder's data line), Δt = 5 s, ω_x = 900 °/s and
    ω_unc = 300 °/s.

    Examples
    --------
    >>> from gyrolib import rsf
    >>> [(x.name, x.distribution) for x in rsf.sensitivity_inputs()][:2]
    [('eps0_gs', 'uniform'), ('encoder_error', 'uniform')]
    >>> len(rsf.sensitivity_inputs())
    7
    """
    v.check_instance("gs_gyro", gs_gyro, MemsGyroSpec)
    v.check_instance("encoder", encoder, EncoderSpec)
    v.check_instance("roll_gyro", roll_gyro, RollGyroSpec)
    pr = SobolInput.printed
    example = "printed (the worked example after Eq. (7))"
    return (
        pr("eps0_gs", "ε0,GS", gs_gyro.bias_total,
           reading="printed: √(σ_rep² + σ_stab²) from the GS gyro's table"),
        pr("encoder_error", "Δγ_enc", encoder.position_error,
           reading="printed in the worked example's Eq. (7) (0.33°; lost only in the "
           "encoder's data line)"),
        pr("period", "Δt", v.check_positive("period", period), reading=example),
        pr("omega_x", "ω_x", v.check_positive("omega_x", omega_x), reading=example),
        pr("omega_unc", "ω_unc", v.check_positive("omega_unc", omega_unc), reading=example),
        pr("eps1_gs", "ε1,GS", gs_gyro.sf_error,
           reading="printed: the GS gyro's scale-factor error (280 ppm)"),
        pr("eps1", "ε1", roll_gyro.sf_error,
           reading="printed: the roll gyro's scale-factor error (Table 1, 600 ppm)"),
    )


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
    """The outputs at each row of ``points`` (a chunk; module level: it is pickled); ε1,GS
    and ε1 from the context unless sampled."""
    names, eps1_gs, eps1 = context
    fixed = {k: x for k, x in (("eps1_gs", eps1_gs), ("eps1", eps1)) if k not in names}
    return np.array([sensitivity_outputs(**dict(zip(names, map(float, row), strict=True)),
                                         **fixed)
                     for row in points]).reshape(-1, 2)


def sensitivity_elasticities(roll_gyro: RollGyroSpec = SIIMU02_ROLL,
                             gs_gyro: MemsGyroSpec = GYPRO4300,
                             encoder: EncoderSpec = AEDB9340) -> Elasticities:
    """∂ ln y/∂ ln x of δK and of the share at the worked example, for every input of
    :func:`sensitivity_inputs` (central differences of ±1 %).

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
    return elasticities({x.name: x.nominal for x in inputs}, sensitivity_outputs,
                        SENSITIVITY_OUTPUTS)


def sensitivity(n: int, seed: int = 0, executor: object = None, *,
                roll_gyro: RollGyroSpec = SIIMU02_ROLL, gs_gyro: MemsGyroSpec = GYPRO4300,
                encoder: EncoderSpec = AEDB9340, chunk_size: int = _CHUNK,
                progress: Callable[[int], None] | None = None,
                second_order: bool = True,
                previous: SensitivityResult | None = None) -> SensitivityResult:
    """Sobol' indices of δK and of the share of the SF error removed (paper RSF, Eq. (7)
    and its "90 %") with respect to the five inputs of :func:`sensitivity_inputs`.

    Parameters
    ----------
    n : int
        Base sample size, a power of 2 (``12 n`` evaluations of Eq. (7)).
    seed : int, default 0
        Seed of the sample's scrambling and of the bootstrap intervals.
    executor : concurrent.futures.Executor, optional
        Where the chunks run (``None``: in this process).
    roll_gyro, gs_gyro, encoder : sensor records, optional
        The paper's sensors by default (the centres of the ranges).
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
    ('omega_x', '0.51')
    """
    v.check_instance("roll_gyro", roll_gyro, RollGyroSpec)
    inputs = sensitivity_inputs(gs_gyro, encoder, roll_gyro=roll_gyro)
    names = tuple(x.name for x in inputs)
    return run_study("rsf", inputs, SENSITIVITY_OUTPUTS, _UNITS, _evaluate,
                     (names, gs_gyro.sf_error, roll_gyro.sf_error), n, seed,
                     executor=executor, chunk_size=chunk_size, progress=progress,
                     second_order=second_order, previous=previous,
                     conditions={"eps1_gs": gs_gyro.sf_error, "eps1": roll_gyro.sf_error},
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
    return recheck(result, _evaluate, (result.input_names, float(c["eps1_gs"]),
                                       float(c["eps1"])), k=k, seed=seed)
