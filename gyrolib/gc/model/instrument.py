"""The constant errors of a real instrument that paper GC leaves out, declared once for every
consumer of the model.

Each :class:`InstrumentTerm` is a constant ``b_e`` (``ḃ_e = 0``) with a 1σ prior taken from a
:class:`~gyrolib.gc.GyrocompassParams` field, and says how it enters the model:

* the measurements: the reading of sensor ``q`` (order :data:`gyrolib.gc.MEASUREMENT_NAMES`)
  gains ``(H0[q] + β_n · H1[q]) · b_e``, with ``β_n`` the nominal float angle of Eq. (4);
* optionally the dynamics: ``Fb`` adds ``Fb[i] · b_e`` to the derivative of state ``i`` of
  Eq. (8) (zero for the terms declared here).

:data:`TERMS` is the declaration.  :func:`instrument_model` reads it at each call and gives
the terms that are ON for given parameters (prior > 0) as arrays; :func:`state_names` the
state vector they make: the 10 states of Eq. (8) followed by the ON constants.  The
covariance analysis (:func:`gyrolib.gc.covariance_analysis`), the Monte Carlo
(:func:`gyrolib.gc.monte_carlo`) and :func:`gyrolib.gc.calibrate` all build their extra
states from it, so a new constant term is one more entry of :data:`TERMS` (and its prior's
field), not an edit of their kernels.  With every prior 0 (the defaults) no term is ON and
every consumer runs the paper's 10-state filter unchanged.

The terms (priors from the parameters; 0 by default):

* ``angle_offset`` (rad): a null offset of the angle sensor, prior ``sigma_as_offset``;
* ``inclinometer_y_bias``, ``inclinometer_z_bias`` (m/s²): a bias of each inclinometer,
  prior ``sigma_incl_bias`` (both);
* ``scale`` (dimensionless): the relative error κ of the scale common to ``H/f`` and the angle
  sensor's gain, prior ``sigma_hf_scale``; the angle sensor reads ``κ β_n`` more (the float's
  steady rate ``(H/f) Ω_h`` scaled by ``1 + κ``, read through the gain);
* ``clock`` (dimensionless): the relative error ε of the logger's time scale, prior
  ``sigma_clock``; time stamps that run fast by ε read ``ε β_n`` less (to first order; the
  same column as ``scale`` with the other sign: the record cannot tell the two apart, and
  σ(ω_gc) carries both).
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import Final

import numpy as np
from numpy.typing import NDArray

from gyrolib import _validation as v
from gyrolib._repr import compact_repr
from gyrolib.gc.model.params import (
    MEASUREMENT_NAMES,
    STATE_NAMES,
    GyrocompassParams,
    check_params,
)

__all__ = [
    "TERMS",
    "InstrumentModel",
    "InstrumentTerm",
    "instrument_model",
    "state_names",
]

_M: Final[int] = len(MEASUREMENT_NAMES)
_N: Final[int] = len(STATE_NAMES)
_GROUPS: Final[tuple[str, ...]] = ("instrument_biases", "scale")


def _vector(name: str, value: object, size: int) -> tuple[float, ...]:
    arr = v.check_array(name, value, shape=(size,))
    return tuple(float(x) for x in arr)


@dataclass(frozen=True)
class InstrumentTerm:
    """One constant error of the instrument: its ``name``, the :class:`GyrocompassParams`
    field of its 1σ prior (``prior_field``, SI), how it enters the measurements (``H0``,
    ``H1``: one entry per sensor of :data:`gyrolib.gc.MEASUREMENT_NAMES`; the reading gains
    ``(H0 + β_n H1) b``) and the dynamics (``Fb``: one entry per state of Eq. (8), default
    zero), the ``group`` of σ(ω_gc) it is reported in (``"instrument_biases"`` or
    ``"scale"``) and its ``unit`` (for display).

    Examples
    --------
    >>> from gyrolib import gc
    >>> t = gc.InstrumentTerm("angle_offset_2", "sigma_as_offset", H0=(2.0, 0.0, 0.0))
    >>> t.H1, t.group
    ((0.0, 0.0, 0.0), 'instrument_biases')
    >>> gc.InstrumentTerm("psi", "sigma_as_offset", H0=(1.0, 0.0, 0.0))
    Traceback (most recent call last):
    ...
    ValueError: name must not be a state of Eq. (8); got 'psi'
    """

    name: str
    prior_field: str
    H0: tuple[float, ...] = (0.0,) * _M
    H1: tuple[float, ...] = (0.0,) * _M
    Fb: tuple[float, ...] = (0.0,) * _N
    group: str = "instrument_biases"
    unit: str = ""

    def __post_init__(self) -> None:
        v.check_str("name", self.name)
        if self.name in STATE_NAMES:
            raise ValueError(f"name must not be a state of Eq. (8); got {self.name!r}")
        v.check_str("prior_field", self.prior_field)
        if self.prior_field not in {f.name for f in fields(GyrocompassParams)}:
            raise ValueError(f"prior_field must be a GyrocompassParams field; got "
                             f"{self.prior_field!r}")
        object.__setattr__(self, "H0", _vector("H0", self.H0, _M))
        object.__setattr__(self, "H1", _vector("H1", self.H1, _M))
        object.__setattr__(self, "Fb", _vector("Fb", self.Fb, _N))
        v.check_choice("group", self.group, _GROUPS)
        v.check_str("unit", self.unit)

    def prior(self, params: GyrocompassParams) -> float:
        """The 1σ prior (SI) of this term under ``params``.

        Examples
        --------
        >>> from gyrolib import gc
        >>> gc.TERMS[0].prior(gc.GyrocompassParams(sigma_as_offset=2e-5))
        2e-05
        """
        return _term_prior(self, check_params(params))


#: The declaration: every constant error term the model knows, in state order.  A new term is
#: one more entry here (a module attribute, read by every consumer at each call).
TERMS: tuple[InstrumentTerm, ...] = (
    InstrumentTerm("angle_offset", "sigma_as_offset", H0=(1.0, 0.0, 0.0), unit="rad"),
    InstrumentTerm("inclinometer_y_bias", "sigma_incl_bias", H0=(0.0, 1.0, 0.0),
                   unit="m/s²"),
    InstrumentTerm("inclinometer_z_bias", "sigma_incl_bias", H0=(0.0, 0.0, 1.0),
                   unit="m/s²"),
    InstrumentTerm("scale", "sigma_hf_scale", H1=(1.0, 0.0, 0.0), group="scale", unit="1"),
    InstrumentTerm("clock", "sigma_clock", H1=(-1.0, 0.0, 0.0), group="scale", unit="1"),
)


@compact_repr
@dataclass(frozen=True)
class InstrumentModel:
    """The instrument constants carried by a model, as arrays (SI): their ``names``, 1σ
    ``prior`` (nb,), measurement columns ``H0``, ``H1`` (3, nb; sensor ``q`` reads
    ``(H0[q] + β_n H1[q]) · b`` more), dynamics columns ``Fb`` (10, nb) and ``groups``.
    ``nb = 0``: the paper's model.  Made by :func:`instrument_model`."""

    names: tuple[str, ...]
    prior: NDArray[np.float64]
    H0: NDArray[np.float64]
    H1: NDArray[np.float64]
    Fb: NDArray[np.float64]
    groups: tuple[str, ...]

    def __post_init__(self) -> None:
        nb = len(self.names)
        v.check_ndarray("prior", self.prior, shape=(nb,))
        v.check_ndarray("H0", self.H0, shape=(_M, nb))
        v.check_ndarray("H1", self.H1, shape=(_M, nb))
        v.check_ndarray("Fb", self.Fb, shape=(_N, nb))
        if len(self.groups) != nb:
            raise ValueError(f"groups must hold one group per name ({nb}); got "
                             f"{len(self.groups)}")

    @property
    def nb(self) -> int:
        """Number of constants."""
        return len(self.names)

    @property
    def couples_dynamics(self) -> bool:
        """Whether any constant enters the dynamics (``Fb ≠ 0``)."""
        return bool(np.any(self.Fb != 0.0))

    def measurement_columns(self, beta_n: float) -> NDArray[np.float64]:
        """``H0 + β_n H1`` (3, nb): the readings per unit of each constant at the nominal
        float angle ``beta_n`` (rad).

        Examples
        --------
        >>> from gyrolib import gc
        >>> im = gc.instrument_model(gc.GyrocompassParams(sigma_hf_scale=1e-3))
        >>> im.names, im.measurement_columns(0.5)[:, 0].tolist()
        (('scale',), [0.5, 0.0, 0.0])
        """
        b = v.check_real("beta_n", beta_n)
        return self.H0 + b * self.H1


def _term_prior(term: InstrumentTerm, p: GyrocompassParams) -> float:
    """:meth:`InstrumentTerm.prior` of parameters already checked (at construction)."""
    return float(getattr(p, term.prior_field))


def _declared() -> dict[str, InstrumentTerm]:
    terms = TERMS
    if not isinstance(terms, tuple) or not all(isinstance(t, InstrumentTerm) for t in terms):
        raise TypeError("gyrolib.gc.model.instrument.TERMS must be a tuple of InstrumentTerm")
    out = {t.name: t for t in terms}
    if len(out) != len(terms):
        raise ValueError("gyrolib.gc.model.instrument.TERMS must not repeat a name")
    return out


def instrument_model(params: GyrocompassParams,
                     names: tuple[str, ...] | list[str] | None = None) -> InstrumentModel:
    """The instrument constants of :data:`TERMS` carried for ``params``, as arrays.

    Parameters
    ----------
    params : GyrocompassParams
        The model; each term's prior is its ``prior_field``.
    names : sequence of str, optional
        The terms to carry, in any order (given back in the order of :data:`TERMS`), whatever
        their prior (a term with prior 0 is a constant known to be 0).  Default: the terms
        that are ON, i.e. whose prior is > 0.

    Returns
    -------
    InstrumentModel
        With ``nb = 0`` (the paper's model) at the default parameters.

    Examples
    --------
    >>> from gyrolib import gc
    >>> gc.instrument_model(gc.GyrocompassParams()).nb
    0
    >>> im = gc.instrument_model(gc.GyrocompassParams(sigma_incl_bias=1e-3))
    >>> im.names, im.H0.tolist()
    (('inclinometer_y_bias', 'inclinometer_z_bias'), [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    """
    p = check_params(params)
    if names is not None:
        if isinstance(names, str) or not isinstance(names, list | tuple):
            raise TypeError(f"names must be a tuple or list of term names; got "
                            f"{type(names).__name__}")
        declared = _declared()
        for nm in names:
            if nm not in declared:
                raise ValueError(f"names must be terms of TERMS {tuple(declared)}; got {nm!r}")
    return build_instrument_model(p, names)


def build_instrument_model(p: GyrocompassParams,
                           names: tuple[str, ...] | list[str] | None = None) -> InstrumentModel:
    """:func:`instrument_model` on arguments already checked (the library's internal path:
    ``params`` is checked once, at the public door)."""
    declared = _declared()
    if names is None:
        chosen = [t for t in declared.values() if _term_prior(t, p) > 0.0]
    else:
        chosen = [t for t in declared.values() if t.name in set(names)]
    nb = len(chosen)
    return InstrumentModel(
        names=tuple(t.name for t in chosen),
        prior=np.array([_term_prior(t, p) for t in chosen], dtype=np.float64),
        H0=np.array([t.H0 for t in chosen], dtype=np.float64).reshape(nb, _M).T.copy(),
        H1=np.array([t.H1 for t in chosen], dtype=np.float64).reshape(nb, _M).T.copy(),
        Fb=np.array([t.Fb for t in chosen], dtype=np.float64).reshape(nb, _N).T.copy(),
        groups=tuple(t.group for t in chosen))


def state_names(params: GyrocompassParams) -> tuple[str, ...]:
    """The state vector of the model for ``params``: the 10 states of Eq. (8)
    (:data:`gyrolib.gc.STATE_NAMES`) followed by the instrument constants that are ON.

    Parameters
    ----------
    params : GyrocompassParams
        The model.

    Returns
    -------
    tuple of str

    Examples
    --------
    >>> from gyrolib import gc
    >>> gc.state_names(gc.GyrocompassParams()) == gc.STATE_NAMES
    True
    >>> gc.state_names(gc.GyrocompassParams(sigma_as_offset=1e-5))[10:]
    ('angle_offset',)
    """
    return STATE_NAMES + build_instrument_model(check_params(params)).names


def union_names(*params: GyrocompassParams) -> tuple[str, ...]:
    """The terms ON in any of ``params`` (checked), in the order of :data:`TERMS` (for a
    truth and a filter that carry different constants)."""
    on = set()
    for p in params:
        on.update(build_instrument_model(p).names)
    return tuple(name for name in _declared() if name in on)


def augmented_index(names: tuple[str, ...], name: str) -> int:
    """Index of ``name`` in the state vector ``names`` (10 states, then constants)."""
    if name not in names:
        raise ValueError(f"name must be one of {names}; got {name!r}")
    return names.index(name)
