"""Paper GC: the parameters of the gyrocompass model and the state vector of Eq. (8).

State vector (1-D, SI units), in this order (:data:`STATE_NAMES`)::

    dbeta      Δβ = β − β_n, float angle increment             rad
    dbeta_dot  Δβ'                                             rad/s
    psi        ψ, azimuth misalignment of the input axis       rad
    omega_gc   ω_gc, systematic drift (constant in a run)      rad/s
    delta      δ, platform tilt (about the input axis y)       rad
    gamma      γ, platform tilt (about the output axis z)      rad
    N1, N2     vibration shaping filter, Eq. (6)               m/s², m/s³
    N3, N4     random-drift shaping filter, Eq. (7)            rad/s, rad/s²

The paper prints ``X1 = Δβ'`` and ``X2 = Δβ``, but its F and D (``F(1,2) = 1``,
``F(2,2) = −f/I``, ``D(1,1) = 1``) only make sense with ``X1 = Δβ``, ``X2 = Δβ'``: this module
uses the latter.  ``F(8,7)`` is ``−α1²`` as Eq. (6) requires (printed without the minus).
The vertical-rate coupling follows Eq. (5) (γ carries cos β_n, δ carries −sin β_n) by
default; ``vertical_coupling="printed_F"`` gives the paper's F listing instead.  The sign of
the gyroscopic torque, Eq. (1) of paper GC, is ``+`` as in Eqs. (3)–(5) by default;
``eq1_sign="-"`` gives the model linearized with the literal minus sign of the extracted
Eq. (1), and a negative ``omega_ub`` the unbalance of the other sign.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from typing import Final

from gyrolib import _validation as v
from gyrolib.gc.model.shaping_filters import ShapingFilter, random_drift_filter, vibration_filter
from gyrolib.units import ARCSEC_PAPER, G0

#: The Earth's rotation rate relative to the stars (rad/s), WGS 84.
EARTH_RATE: Final[float] = 7.292115e-5

#: The latitude (rad) at which :data:`EARTH_RATE` has paper GC's components
#: ``Omega_h = 4.3·10⁻⁵`` and ``Omega_v = 5.9·10⁻⁵`` rad/s (their ratio; their norm is
#: 7.30·10⁻⁵ rad/s, the Earth's rate within 0.1 %).
PAPER_LATITUDE: Final[float] = math.atan2(5.9e-5, 4.3e-5)

__all__ = [
    "MEASUREMENT_NAMES",
    "NOISE_NAMES",
    "STATE_NAMES",
    "GyrocompassParams",
    "latitude_text",
    "normal_gravity",
    "state_index",
]


STATE_NAMES: Final[tuple[str, ...]] = (
    "dbeta", "dbeta_dot", "psi", "omega_gc", "delta", "gamma", "N1", "N2", "N3", "N4",
)


MEASUREMENT_NAMES: Final[tuple[str, ...]] = ("angle_sensor", "inclinometer_y", "inclinometer_z")


NOISE_NAMES: Final[tuple[str, ...]] = ("w1", "w2")


N_STATES: Final[int] = len(STATE_NAMES)


def state_index(name: str) -> int:
    """Index of a state by its name (see :data:`STATE_NAMES`).

    Parameters
    ----------
    name : str
        One of :data:`STATE_NAMES`.

    Returns
    -------
    int
        Its index in the state vector of Eq. (8).

    Examples
    --------
    >>> from gyrolib import gc
    >>> gc.state_index("omega_gc")
    3
    """
    if name not in STATE_NAMES:
        raise ValueError(f"name must be one of {STATE_NAMES}; got {name!r}")
    return STATE_NAMES.index(name)


_POSITIVE = ("I", "H", "f", "Omega_h", "g", "alpha1", "sigma1_sq", "alpha2",
             "sigma2_sq", "C_as", "C_incl_y", "C_incl_z", "dt")


#: ``Omega_v = Ω_E sin φ`` is negative south of the equator and 0 on it.
_REAL = ("omega_ub", "Omega_v")


_NONNEGATIVE = ("sigma_dbeta0", "sigma_dbeta_dot0", "sigma_psi0", "sigma_gc0",
                "sigma_delta0", "sigma_gamma0", "shaping_p0_scale", "sigma_hf_scale",
                "sigma_as_offset", "sigma_incl_bias", "sigma_clock")


_DAMPING = ("xi1", "xi2")


#: Checked by the shaping filters they build (:func:`vibration_filter`,
#: :func:`random_drift_filter`), with the same messages.
_SHAPING = ("alpha1", "xi1", "sigma1_sq", "alpha2", "xi2", "sigma2_sq")


#: Not model inputs, so not in a stored study's key (:func:`gyrolib.store.model_key`): the
#: groups above only say which range the door accepts for each field (positive, real,
#: non-negative, a damping, a shaping filter's); no margin computes with them, and a study
#: computed at valid values reads the same numbers whatever else the door would accept.
__key_ignore__ = ("_POSITIVE", "_REAL", "_NONNEGATIVE", "_DAMPING", "_SHAPING")


_CHOICES = {
    "shaping_p0": ("stationary", "zero"),
    "measurement_noise": ("intensity_over_dt", "variance"),
    "vertical_coupling": ("eq5", "printed_F"),
    "eq1_sign": ("+", "-"),
}


@dataclass(frozen=True)
class GyrocompassParams:
    """Parameters of paper GC's simulation, SI units, the paper's values as defaults.

    Paper values (its parameter list after Eq. (8), and the text around Eqs. (6), (7)):
    ``I``, ``H``, ``f``, ``Omega_v``, ``Omega_h``, ``omega_ub``, the shaping-filter
    parameters, the sensor noise intensities ``C_as`` (angle sensor, rad²·s) and
    ``C_incl_y``, ``C_incl_z`` (inclinometers, m²/s³), ``dt`` and the initial standard
    deviations of ψ, ω_gc, δ and γ (in the paper's arcsecond, 1″ = 0.485·10⁻⁵ rad).

    Not given by the paper (assumptions, studied in the book):

    * ``g``: standard gravity;
    * ``sigma_dbeta0``, ``sigma_dbeta_dot0``: the float starts at the angle sensor's null,
      held there by the feedback loop until it is switched off;
    * ``shaping_p0``: initial covariance of N1…N4, ``"stationary"`` (the processes are already
      running when the calibration starts) or ``"zero"`` (the literal reading);
      ``shaping_p0_scale`` (κ, default 1) multiplies the stationary covariance (a partly known
      initial state; κ = 0 is the zero reading);
    * ``measurement_noise``: how the continuous intensities become discrete variances,
      ``"intensity_over_dt"`` (``R = C/Δt``, sampling of continuous white noise) or
      ``"variance"`` (``R = C``, the printed numbers read as variances);
    * ``vertical_coupling``: ``"eq5"`` (Eq. (5)) or ``"printed_F"`` (the F listing);
    * ``eq1_sign``: the sign of the gyroscopic torque of Eq. (1), ``"+"`` (as Eqs. (3)–(5)
      and the printed F use it) or ``"-"`` (the extracted Eq. (1) taken literally).  With
      ``"-"`` the float turns the other way, ``β → −β``; :func:`gyrolib.gc.system_matrix`
      gives that model in the mirrored angle, where it differs from the ``"+"`` model only in
      the sign of the tilt term that carries ``sin β_n``;
    * the sign of ``omega_ub``: the paper gives the magnitude of the unbalance drift; a
      negative value reverses the unbalance torque.

    Errors of a real instrument that the paper leaves out (0 by default, so that every
    reproduced number is the paper's model):

    * ``sigma_hf_scale``: the relative standard uncertainty κ of the scale common to ``H/f`` and
      the angle sensor's gain (dimensionless; 10⁻⁴ to 10⁻² for real instruments).  GC reads
      the drift through the float's steady rate ``(H/f)(Ω_h cos β + ω_gc)``, so a relative
      error κ reads as a drift of about κ·Ω_h, which 100 s of data cannot tell from ω_gc.
    * ``sigma_as_offset``: the 1σ prior (rad) of a constant null offset of the angle sensor
      (arc seconds in practice; a logger that starts a time τ late reads like an offset of
      about ``(H/f) Ω_h τ``);
    * ``sigma_incl_bias``: the 1σ prior (m/s²) of a constant bias of each inclinometer
      (0.1–1 mg for real ones); a bias reads like a tilt of ``b/g``, which the data cannot
      tell from one, so this prior enters σ(ω_gc) through the tilt's coupling ``Ω_v``;
    * ``sigma_clock``: the 1σ relative error ε of the logger's time scale (dimensionless; a
      crystal's 10⁻⁵ to 10⁻⁴, a logger rate labelled wrong 2.4 %: 1024 Hz read as 1 kHz).
      Time stamps that run fast by ε read the float's motion ``β_n`` at ``t/(1 + ε)``, i.e.
      ``(1 − ε) β_n`` to first order (``β_n`` grows in proportion to t after the first few
      ms): the scale term's column with the opposite sign, carried like the scale.

    These constants are declared once, in :mod:`gyrolib.gc.model.instrument`
    (:data:`gyrolib.gc.TERMS`); a prior > 0 switches one ON, and then the covariance analysis
    and the Monte Carlo carry it as a state (:func:`gyrolib.gc.state_names`) and
    :func:`gyrolib.gc.calibrate` estimates it jointly with the state (bias-separated filter),
    so σ(ω_gc) carries its uncertainty.

    The Earth-rate components at a given latitude: :meth:`at_latitude`.

    Examples
    --------
    >>> from dataclasses import replace
    >>> from gyrolib.gc import GyrocompassParams
    >>> p = GyrocompassParams()
    >>> f"{p.time_constant * 1e3:.2f} ms"
    '1.60 ms'
    >>> replace(p, eq1_sign="-").eq1_sign
    '-'
    >>> replace(p, xi1=1.5)
    Traceback (most recent call last):
    ...
    ValueError: xi1 must be in (0.0, 1.0]; got 1.5
    """

    I: float = 4.0e-5
    H: float = 0.05
    f: float = 0.025
    Omega_v: float = 5.9e-5
    Omega_h: float = 4.3e-5
    g: float = G0
    omega_ub: float = 4.84e-8
    alpha1: float = 1.33e-2
    xi1: float = 0.7
    sigma1_sq: float = 1.86e-6
    alpha2: float = 6.28
    xi2: float = 0.4
    sigma2_sq: float = 2.35e-15
    C_as: float = 2.0e-13
    C_incl_y: float = 5.0e-15
    C_incl_z: float = 5.0e-15
    dt: float = 1.0e-3
    sigma_dbeta0: float = 0.0
    sigma_dbeta_dot0: float = 0.0
    sigma_psi0: float = 180.0 * ARCSEC_PAPER
    sigma_gc0: float = 0.15 * ARCSEC_PAPER
    sigma_delta0: float = 120.0 * ARCSEC_PAPER
    sigma_gamma0: float = 120.0 * ARCSEC_PAPER
    shaping_p0: str = "stationary"
    shaping_p0_scale: float = 1.0
    measurement_noise: str = "intensity_over_dt"
    vertical_coupling: str = "eq5"
    eq1_sign: str = "+"
    sigma_hf_scale: float = 0.0
    sigma_as_offset: float = 0.0
    sigma_incl_bias: float = 0.0
    sigma_clock: float = 0.0

    def __post_init__(self) -> None:
        for f_ in fields(self):
            name = f_.name
            if name in _SHAPING:
                # the shaping filters check their own parameters (once, here: the filters
                # are built at the door and reused by every model function)
                if name == "alpha1":
                    vib = vibration_filter(self.alpha1, self.xi1, self.sigma1_sq)
                elif name == "alpha2":
                    drift = random_drift_filter(self.alpha2, self.xi2, self.sigma2_sq)
            elif name in _POSITIVE:
                v.check_positive(name, getattr(self, name))
            elif name in _REAL:
                v.check_real(name, getattr(self, name))
            elif name in _NONNEGATIVE:
                v.check_nonnegative(name, getattr(self, name))
            elif name in _DAMPING:
                v.check_in_range(name, getattr(self, name), 0.0, 1.0, low_open=True)
            elif name in _CHOICES:
                v.check_choice(name, getattr(self, name), _CHOICES[name])
        # Store plain floats so that numpy scalars and ints behave identically.
        for name in (*_POSITIVE, *_REAL, *_NONNEGATIVE, *_DAMPING):
            object.__setattr__(self, name, float(getattr(self, name)))
        for filt in (vib, drift):
            for arr in (filt.A, filt.B, filt.C):
                arr.flags.writeable = False
        object.__setattr__(self, "_vibration", vib)
        object.__setattr__(self, "_random_drift", drift)

    # Alternative constructors -------------------------------------------------------------
    @classmethod
    def at_latitude(cls, latitude: float, **overrides: object) -> GyrocompassParams:
        """The parameters with ``Omega_h = Ω_E cos φ`` and ``Omega_v = Ω_E sin φ`` at the
        geodetic latitude ``φ`` (rad, in (−π/2, π/2): south of the equator ``Omega_v`` is
        negative, on it 0; at a pole ``Omega_h`` vanishes and the gyrocompass has nothing
        to sense), ``Ω_E`` = :data:`EARTH_RATE`; other fields from ``overrides``.

        The paper's ``Omega_h = 4.3·10⁻⁵``, ``Omega_v = 5.9·10⁻⁵`` rad/s correspond to
        :data:`PAPER_LATITUDE`, about 53.9° N.  Only the sign of ``Omega_v`` tells the
        hemispheres apart in paper GC's model (Eqs. (2), (3): the tilts couple through
        ``Ω_v``); on the equator the tilts do not torque the float at all.

        Examples
        --------
        >>> import math
        >>> from gyrolib.gc import GyrocompassParams
        >>> p = GyrocompassParams.at_latitude(math.radians(45.0))
        >>> f"{p.Omega_h:.4e} {p.Omega_v:.4e}"
        '5.1563e-05 5.1563e-05'
        >>> f"{GyrocompassParams.at_latitude(math.radians(-35.0)).Omega_v:.4e}"
        '-4.1826e-05'
        >>> f"{math.degrees(PAPER_LATITUDE):.1f}"
        '53.9'
        """
        lat = v.check_in_range("latitude", latitude, -math.pi / 2, math.pi / 2, low_open=True,
                               high_open=True)
        return cls(**{"Omega_h": EARTH_RATE * math.cos(lat),
                      "Omega_v": EARTH_RATE * math.sin(lat), **overrides})

    @property
    def latitude(self) -> float:
        """The geodetic latitude (rad) whose Earth-rate components have the ratio of
        ``Omega_v`` to ``Omega_h``: ``atan2(Ω_v, Ω_h)``, negative south of the equator.

        Examples
        --------
        >>> import math
        >>> from gyrolib.gc import GyrocompassParams
        >>> f"{math.degrees(GyrocompassParams.at_latitude(math.radians(-35.0)).latitude):.6g}"
        '-35'
        """
        return math.atan2(self.Omega_v, self.Omega_h)

    # Derived quantities -------------------------------------------------------------------
    @property
    def scale_drift_sigma(self) -> float:
        """The drift (rad/s) that the scale uncertainty ``sigma_hf_scale`` reads as, to first
        order: ``sigma_hf_scale · Ω_h`` (a relative error κ of ``H/f`` or of the angle sensor's
        gain scales the float's steady rate ``(H/f) Ω_h``).

        Examples
        --------
        >>> from gyrolib.gc import GyrocompassParams
        >>> from gyrolib.units import from_si
        >>> p = GyrocompassParams(sigma_hf_scale=1e-3)
        >>> f"{from_si(p.scale_drift_sigma, 'arcsec_paper/s'):.4f}"
        '0.0089'
        """
        return self.sigma_hf_scale * self.Omega_h

    @property
    def time_constant(self) -> float:
        """Float time constant ``I/f`` (s)."""
        return self.I / self.f

    @property
    def Q1(self) -> float:
        """Vibration white-noise intensity ``Q1 = 2 ξ1 α1 σ1²`` (paper GC, after Eq. (6))."""
        return 2.0 * self.xi1 * self.alpha1 * self.sigma1_sq

    @property
    def Q2(self) -> float:
        """Random-drift white-noise intensity ``Q2 = 4 ξ2 α2³ σ2²`` (after Eq. (7))."""
        return 4.0 * self.xi2 * self.alpha2**3 * self.sigma2_sq

    def vibration_filter(self) -> ShapingFilter:
        """The vibration shaping filter, Eq. (6) (built once, at construction; read-only)."""
        return self._vibration

    def random_drift_filter(self) -> ShapingFilter:
        """The random-drift shaping filter, Eq. (7) (built once, at construction; read-only)."""
        return self._random_drift


def latitude_text(degrees: float, digits: int = 6) -> str:
    """A latitude in degrees as the outputs print it: ``"53.9 deg N"``, ``"35 deg S"``, and
    ``"0 deg"`` on the equator, with ``digits`` significant digits.

    Examples
    --------
    >>> latitude_text(53.9), latitude_text(-35.0), latitude_text(0.0)
    ('53.9 deg N', '35 deg S', '0 deg')
    """
    d = float(degrees)
    text = f"{abs(d):.{int(digits)}g} deg"
    if text == f"{0.0:.{int(digits)}g} deg":
        return text
    return text + (" N" if d > 0 else " S")


def normal_gravity(latitude: float) -> float:
    """Sea-level gravity (m/s²) at ``latitude`` (rad) by the international gravity formula
    of 1967, to bound how far the unstated ``g`` of paper GC can be from standard gravity.

    Parameters
    ----------
    latitude : float
        Geodetic latitude (rad), in [−π/2, π/2].

    Returns
    -------
    float
        ``9.780318 (1 + 5.3024e-3 sin²φ − 5.9e-6 sin²2φ)`` m/s².

    Examples
    --------
    >>> import math
    >>> f"{normal_gravity(0.0):.4f} {normal_gravity(math.pi / 2):.4f}"
    '9.7803 9.8322'
    """
    lat = v.check_in_range("latitude", latitude, -math.pi / 2, math.pi / 2)
    return 9.780318 * (1 + 5.3024e-3 * math.sin(lat) ** 2 - 5.9e-6 * math.sin(2 * lat) ** 2)


def check_params(params: object) -> GyrocompassParams:
    return v.check_instance("params", params, GyrocompassParams)
