"""Figures of a global sensitivity study: each function takes a
:class:`~gyrolib.sensitivity.SensitivityResult` and returns a Figure."""

from __future__ import annotations

from typing import Any

import numpy as np

from gyrolib import _validation as v
from gyrolib._page_figures import SMALL_PT, for_the_page
from gyrolib.sensitivity.study import SensitivityResult

__all__ = ["plot_indices"]


def plot_indices(result: SensitivityResult, output: str, ax: Any = None) -> Any:
    """Bar chart of the first-order and total indices of ``output`` with their confidence
    intervals (error bars); returns the Figure.

    Examples
    --------
    >>> from gyrolib import rsf
    >>> from gyrolib.sensitivity import plot_indices
    >>> fig = plot_indices(rsf.sensitivity(8, seed=0), "delta_k")
    >>> len(fig.axes)
    1
    """
    import matplotlib.pyplot as plt

    v.check_instance("result", result, SensitivityResult)
    v.check_choice("output", output, result.outputs)
    own = ax is None  # a figure of its own is made for the page; a caller's axes are not
    if own:
        fig, ax = plt.subplots(figsize=(5.0, 3.4), layout="constrained")
    else:
        fig = ax.figure
    x = np.arange(len(result.inputs))
    s1 = [result.first_order[output][n] for n in result.input_names]
    st = [result.total[output][n] for n in result.input_names]
    w = 0.38
    ax.bar(x - w / 2, [i.value for i in s1], w, yerr=[i.conf for i in s1], capsize=2,
           label="first order $S_i$", color="tab:blue")
    ax.bar(x + w / 2, [i.value for i in st], w, yerr=[i.conf for i in st], capsize=2,
           label="total $S_{Ti}$", color="tab:orange")
    ax.set_xticks(x, [i.symbol for i in result.inputs], rotation=45, ha="right")
    ax.axhline(0.0, color="0.5", lw=0.6)
    ax.set_ylabel("Sobol' index")
    ax.set_ylim(min(-0.05, ax.get_ylim()[0]), max(1.0, ax.get_ylim()[1]))
    ax.legend(frameon=False, fontsize=SMALL_PT)
    return for_the_page(fig) if own else fig
