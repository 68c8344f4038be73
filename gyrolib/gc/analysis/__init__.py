"""What paper GC's Figures 3 and 4 and its claims rest on: covariance analysis, Monte Carlo,
error budget, observability, linearization, the speed-claim map and the Sobol' study.

Every name is re-exported by :mod:`gyrolib.gc`; the table there maps the paper's equations
and figures to these modules.
"""
from gyrolib.gc.analysis.budget import (
    BUDGET_SOURCES,
    ErrorBudget,
    error_budget,
)
from gyrolib.gc.analysis.covariance import (
    CovarianceAnalysis,
    CovarianceSweep,
    covariance_analysis,
    parameter_grid,
    sweep_covariance,
    sweep_sigma_gc,
    time_to_sigma,
)
from gyrolib.gc.analysis.linearization import (
    LinearizationEffect,
    linearization_effect,
    psi_for_drift,
    remainder_drift,
)
from gyrolib.gc.analysis.montecarlo import (
    MonteCarloResult,
    MonteCarloSummary,
    monte_carlo,
    run_streams,
    simulate_truth,
    truth_prior_factor,
)
from gyrolib.gc.analysis.observability import (
    InformationPsiOmega,
    information_psi_omega,
)
from gyrolib.gc.analysis.sensitivity_study import (
    SENSITIVITY_OUTPUTS,
    recheck_sensitivity,
    sensitivity,
    sensitivity_elasticities,
    sensitivity_inputs,
    sensitivity_outputs,
)
from gyrolib.gc.analysis.speed_claim import (
    SHAPING_FIELDS,
    ClaimBoundary,
    ShapingSweep,
    SpeedClaimMap,
    claim_boundary,
    shaping_sweep,
    speed_claim_map,
    time_to_level,
)

__all__ = [
    "BUDGET_SOURCES",
    "SENSITIVITY_OUTPUTS",
    "SHAPING_FIELDS",
    "ClaimBoundary",
    "CovarianceAnalysis",
    "CovarianceSweep",
    "ErrorBudget",
    "InformationPsiOmega",
    "LinearizationEffect",
    "MonteCarloResult",
    "MonteCarloSummary",
    "ShapingSweep",
    "SpeedClaimMap",
    "claim_boundary",
    "covariance_analysis",
    "error_budget",
    "information_psi_omega",
    "linearization_effect",
    "monte_carlo",
    "parameter_grid",
    "psi_for_drift",
    "recheck_sensitivity",
    "remainder_drift",
    "run_streams",
    "sensitivity",
    "sensitivity_elasticities",
    "sensitivity_inputs",
    "sensitivity_outputs",
    "shaping_sweep",
    "simulate_truth",
    "speed_claim_map",
    "sweep_covariance",
    "sweep_sigma_gc",
    "time_to_level",
    "time_to_sigma",
    "truth_prior_factor",
]
