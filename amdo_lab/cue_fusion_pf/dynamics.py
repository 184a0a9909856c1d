"""Second-order auto-regressive dynamics (eqs. 4-5), with the printed order of the two lags kept as an option.

The coefficients printed under eq. (4) are those of a discretised damped oscillator,

    a1 = -exp(-2 β τ),   a0 = 2 exp(-β τ) cos(ω τ),
    b0 = sqrt(1 - a1² - a0² - 2 a1 a0² / (1 - a1)),

and b0 is exactly the gain that gives unit stationary variance to ``x_k = a0 x_{k-1} + a1 x_{k-2} +
b0 ν``: so a0 multiplies the last state and a1 the one before. Eq. (4) as printed swaps them
(``x_k = a1 x_{k-1} + a0 x_{k-2}``); at β = 2, τ = 1/25 s that recursion has a root of modulus 1.85
and explodes. :class:`ARDynamics` uses the corrected order and refuses an unstable model unless asked.
"""

from __future__ import annotations

import numpy as np

from amdo_lab.common import as_finite_array, check_bool, check_in_range, check_positive, make_rng

__all__ = ["ARDynamics", "MAX_STATE", "ar2_coefficients"]

#: Largest magnitude of a state entry (pixels or relative scale): far beyond any image (an unstable
#: model's trajectory may grow far out of it), and far below where the recursion's sums overflow (its lag
#: weights are at most 2 in magnitude for β ≥ 0).
MAX_STATE = 1e150


def ar2_coefficients(beta: float, omega: float, tau: float) -> tuple[float, float, float]:
    """The coefficients ``(a1, a0, b0)`` printed under eq. (4).

    Parameters
    ----------
    beta : float
        Damping coefficient β in 1/s, β >= 0 (the paper: 2 for translation, 10 for deformation).
    omega : float
        Oscillation frequency ω in rad/s (the paper: 0).
    tau : float
        Sampling period τ in s, > 0 (ours: 1/25 s, a 25 fps camera; the paper does not give it).

    Returns
    -------
    tuple of float
        (a1, a0, b0) as printed: a1 = -exp(-2βτ), a0 = 2 exp(-βτ) cos(ωτ), b0 the unit-variance gain.

    References
    ----------
    Li & Chaumette, AMDO 2004, eq. (4); Blake & Isard, Active Contours (1998), ch. 9.
    """
    beta = check_positive(beta, "beta", allow_zero=True)
    omega = check_in_range(omega, "omega", -np.inf, np.inf)  # any finite real number
    tau = check_positive(tau, "tau")
    a1 = -np.exp(-2.0 * beta * tau)
    a0 = 2.0 * np.exp(-beta * tau) * np.cos(omega * tau)
    b0_squared = 1.0 - a1**2 - a0**2 - 2.0 * a1 * a0**2 / (1.0 - a1) if a1 != 1.0 else 0.0
    return float(a1), float(a0), float(np.sqrt(max(b0_squared, 0.0)))


def _ar2_stationary_variance(first_lag: float, second_lag: float, gain: float) -> float:
    """Stationary variance of ``x_k = first_lag x_{k-1} + second_lag x_{k-2} + gain ν``.

    Check-free: the tests use it to show that b0 gives unit variance in the corrected order only.

    Parameters
    ----------
    first_lag, second_lag : float
        Weights of x_{k-1} and x_{k-2}.
    gain : float
        Gain of the unit-variance noise ν.

    Returns
    -------
    float
        The variance (Yule-Walker), or inf when a root has modulus >= 1 (an unstable model).

    References
    ----------
    Li & Chaumette, AMDO 2004, eq. (4): with the corrected order, b0 gives unit variance.
    """
    roots = np.roots([1.0, -first_lag, -second_lag])
    if np.max(np.abs(roots)) >= 1.0:
        return float("inf")
    # Yule-Walker: γ0 = (1 - φ2) g² / ((1 + φ2)((1 - φ2)² - φ1²))
    return float((1.0 - second_lag) * gain**2 / ((1.0 + second_lag) * ((1.0 - second_lag) ** 2 - first_lag**2)))


class ARDynamics:
    """Eq. (5): ``X_k - X̄ = A0 (X_{k-1} - X̄) + A1 (X_{k-2} - X̄) + B0 ν``, one AR(2) per state component.

    Parameters
    ----------
    beta : array_like
        (d,) damping per component, 1/s, >= 0 (head: 2, 2 for translation and 10 for scale).
    omega : array_like
        (d,) oscillation frequency per component, rad/s (the paper: 0).
    tau : float
        Sampling period in s, > 0.
    stationary_std : array_like
        (d,) stationary standard deviation of each component (pixels, or relative scale), > 0;
        the paper does not state it. The per-frame noise is ``b0 * stationary_std``.
    mean : array_like
        (d,) the state X̄ the process returns to, entries within ±:data:`MAX_STATE`.
    printed_order : bool
        Use eq. (4) exactly as printed (a1 on x_{k-1}, a0 on x_{k-2}).
    allow_unstable : bool
        Accept a model whose recursion has a root of modulus >= 1 (else ValueError).

    References
    ----------
    Li & Chaumette, AMDO 2004, eqs. (4)-(5).
    """

    def __init__(self, beta, omega, tau: float, stationary_std, mean, *, printed_order: bool = False,
                 allow_unstable: bool = False):
        self.beta = as_finite_array(beta, "beta", ndim=1, bounds=(0.0, np.inf))
        self.omega = as_finite_array(omega, "omega", ndim=1)
        self.tau = check_positive(tau, "tau")
        self.stationary_std = as_finite_array(stationary_std, "stationary_std", ndim=1, bounds=(0.0, np.inf), closed="neither")
        self.mean = as_finite_array(mean, "mean", ndim=1, max_abs=MAX_STATE)
        lengths = (self.beta.size, self.omega.size, self.stationary_std.size, self.mean.size)
        if len(set(lengths)) > 1:
            raise ValueError(f"beta, omega, stationary_std and mean must have one entry per state component, got lengths {lengths}")
        self.printed_order = check_bool(printed_order, "printed_order")
        allow_unstable = check_bool(allow_unstable, "allow_unstable")
        coefficients = np.array([ar2_coefficients(b, w, self.tau) for b, w in zip(self.beta, self.omega)])
        self.a1, self.a0, self.b0 = coefficients.T
        # the weights of x_{k-1} and x_{k-2}
        self.first_lag, self.second_lag = (self.a1, self.a0) if printed_order else (self.a0, self.a1)
        if not allow_unstable and self.spectral_radius() >= 1.0:
            raise ValueError(f"AR(2) model is unstable (spectral radius {self.spectral_radius():.3f}): beta too small "
                             "(no damping) or printed_order; pass allow_unstable=True to use it anyway")

    @property
    def step_std(self) -> np.ndarray:
        """Per-frame noise standard deviation ``b0 * stationary_std`` of each component."""
        return self.b0 * self.stationary_std

    def spectral_radius(self) -> float:
        """Largest modulus of the roots of ``z² - first_lag z - second_lag`` over the components.

        Returns
        -------
        float
            Below 1 for a stable model (1.85 for eq. 4 as printed at β = 2, τ = 1/25 s).
        """
        return float(max(np.max(np.abs(np.roots([1.0, -f, -s]))) for f, s in zip(self.first_lag, self.second_lag)))

    def propagate(self, previous: np.ndarray, before: np.ndarray, noise: np.ndarray) -> np.ndarray:
        """Eq. (5) for given standard-normal noise.

        Parameters
        ----------
        previous, before : numpy.ndarray
            (N, d) states X_{k-1} and X_{k-2}, entries within ±:data:`MAX_STATE`.
        noise : numpy.ndarray
            (N, d) standard-normal draws ν, entries within ±:data:`MAX_STATE`.

        Returns
        -------
        numpy.ndarray
            (N, d) states X_k.
        """
        previous, before = self._check_lags(previous, before)
        noise = as_finite_array(noise, "noise", shape=previous.shape, max_abs=MAX_STATE)
        return self._propagate(previous, before, noise)

    def step(self, previous: np.ndarray, before: np.ndarray, *, rng: int | np.random.Generator) -> np.ndarray:
        """Sample ``X_k`` given ``X_{k-1}`` and ``X_{k-2}``: the prediction step of the filter.

        Applied to particles that sample the posterior ``p(X_{k-1} | Y_{1:k-1})``, the draws sample
        the prediction ``p(X_k | Y_{1:k-1})`` of eq. (16) (the integral done by Monte Carlo).

        Parameters
        ----------
        previous, before : numpy.ndarray
            (N, d) states X_{k-1} and X_{k-2}, entries within ±:data:`MAX_STATE`.
        rng : int or numpy.random.Generator
            Source of the noise.

        Returns
        -------
        numpy.ndarray
            (N, d) sampled states X_k.

        References
        ----------
        Li & Chaumette, AMDO 2004, eqs. (5) and (16).
        """
        previous, before = self._check_lags(previous, before)
        return self._step(previous, before, make_rng(rng, "rng"))

    def _check_lags(self, previous: object, before: object) -> tuple[np.ndarray, np.ndarray]:
        """The two lagged states as (N, d) float arrays within ±:data:`MAX_STATE` (errors name them)."""
        previous = as_finite_array(previous, "previous", shape=(None, self.mean.size), max_abs=MAX_STATE)
        return previous, as_finite_array(before, "before", shape=previous.shape, max_abs=MAX_STATE)

    def _step(self, previous: np.ndarray, before: np.ndarray, generator: np.random.Generator) -> np.ndarray:
        """:meth:`step` on checked arrays (the filter's loop calls it every frame)."""
        # eq. (5): one draw from the transition prior p(X_k | X_{k-1}, X_{k-2}), ν standard normal; drawn for
        # every particle of the posterior at k-1, the draws sample the prediction of eq. (16) (Monte Carlo)
        return self._propagate(previous, before, generator.standard_normal(previous.shape))

    def _propagate(self, previous: np.ndarray, before: np.ndarray, noise: np.ndarray) -> np.ndarray:
        """:meth:`propagate` on checked arrays."""
        # eq. (4) for every component (eq. 5 for the state), about the mean: X_k = a_0 X_{k-1} + a_1 X_{k-2} + b_0 ν
        # in our order of the lags (printed_order=True: the printed a_1 X_{k-1} + a_0 X_{k-2}, which explodes)
        return (self.mean + self.first_lag * (previous - self.mean) + self.second_lag * (before - self.mean)
                + self.step_std * noise)
