"""Global (variance-based) sensitivity analysis: Sobol' indices of a model's outputs with
respect to its uncertain inputs, on any ``concurrent.futures.Executor``.

Paper-agnostic; the studies of the two papers are :func:`gyrolib.gc.sensitivity`
(:mod:`gyrolib.gc.analysis.sensitivity_study`) and :func:`gyrolib.rsf.sensitivity`
(:mod:`gyrolib.rsf.sensitivity_study`); the command line is ``python -m gyrolib
sensitivity``.

============  ====================================================================
module        what
============  ====================================================================
``study``     the sample, the runs on an executor, the indices (SALib):
              :class:`SobolInput`, :func:`run_study`, :func:`analyze`,
              :class:`SensitivityResult`, :func:`recheck`; :func:`elasticities`
              (∂ ln y/∂ ln x at the defaults, beside the indices)
``plots``     :func:`plot_indices` (loaded on first use: matplotlib)
============  ====================================================================
"""

from gyrolib.sensitivity.study import (
    CONF_LEVEL,
    DISTRIBUTIONS,
    NUM_RESAMPLES,
    Elasticities,
    Recheck,
    SensitivityResult,
    SobolIndex,
    SobolInput,
    analyze,
    elasticities,
    recheck,
    result_from_dict,
    run_study,
    unit_sample,
)

__all__ = [
    "CONF_LEVEL",
    "DISTRIBUTIONS",
    "NUM_RESAMPLES",
    "Elasticities",
    "Recheck",
    "SensitivityResult",
    "SobolIndex",
    "SobolInput",
    "analyze",
    "elasticities",
    "plot_indices",
    "recheck",
    "result_from_dict",
    "run_study",
    "unit_sample",
]


def __getattr__(name: str):
    """``plot_indices`` (matplotlib), imported on first access."""
    if name == "plot_indices":
        from gyrolib.sensitivity.plots import plot_indices  # start-up: matplotlib

        return plot_indices
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
