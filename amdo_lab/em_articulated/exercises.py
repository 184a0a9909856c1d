"""Chapter 1's exercises: the hints and the wrong answers each check must reject.

The targets are not here: each check cell of the chapter's source registers its own (a literal in a
hidden test, ``EXERCISES.expect``), so the package the reader installs does not hold them (see
:mod:`amdo_lab.common.exercises`). Exercise 7 ("implement it") is checked against
:func:`_volume_e_step`, eq. (15) written with the working volume V, on cases drawn by
:func:`_e_step_case`.

References
----------
G. Dewaele, F. Devernay, R. Horaud, F. Forbes. The Alignment Between 3-D Data and Articulated Shapes
with Bending Surfaces. ECCV 2006, LNCS 3953, pp. 578-591 (eqs. 3-7, 15-18 and Sec. 3.3).
"""

from __future__ import annotations

import numpy as np

from amdo_lab.common.exercises import Exercise, ExerciseSet, WrongAnswer
from amdo_lab.em_articulated.estep import PAPER_C, e_step_reference

__all__ = ["EXERCISES"]


def _ball_volume(sigma: float) -> float:
    """v of eq. (4): the ball of radius σ, (4/3)πσ³."""
    return 4.0 / 3.0 * np.pi * sigma**3


def _volume_e_step(moved: np.ndarray, data: np.ndarray, sigma: float, volume: float) -> np.ndarray:
    """α_ij of eq. (15) for a working space of volume V, through eq. (17) with its exact c.

    Dividing eq. (15) by Π_i (2πσ²)^(-3/2) leaves eq. (17) with c = (1 - nv/V)(2πσ²)^(3/2)/v, the
    constant of eq. (18) before ``nv << V`` is assumed.

    Parameters
    ----------
    moved : (n, 3) numpy.ndarray
        Moved texture points T(X_i), mm.
    data : (m, 3) numpy.ndarray
        Data points Y_j, mm.
    sigma : float
        σ of eq. (6), mm; the ball of eq. (4) has radius σ.
    volume : float
        V, mm³, larger than the n balls.

    Returns
    -------
    (n, m) numpy.ndarray
        α_ij; column j sums to the inlier probability of Y_j.
    """
    ball = _ball_volume(sigma)
    c = (1.0 - len(moved) * ball / volume) * (2.0 * np.pi * sigma**2) ** 1.5 / ball  # eqs. (4)-(7), (15)
    return e_step_reference(moved, data, sigma, c=c)


def _e_step_case(seed: int) -> dict:
    """One input of Exercise 7: texture points, their noisy copies mixed with clutter, σ and V.

    The working volume leaves the n balls 20 to 50 % of V, so the factor (V - nv)/V of eq. (5)
    matters and the paper's constant ``c = 3√(π/2)`` (which drops it) gives other posteriors.
    """
    rng = np.random.default_rng(seed)
    n = int(rng.integers(4, 9))
    sigma = float(rng.uniform(2.0, 6.0))
    moved = rng.uniform(-20.0, 20.0, (n, 3))
    copies = moved[rng.integers(0, n, n)] + rng.normal(0.0, sigma, (n, 3))
    clutter = rng.uniform(-30.0, 30.0, (int(rng.integers(2, 6)), 3))
    volume = n * _ball_volume(sigma) / float(rng.uniform(0.2, 0.5))
    return dict(moved=moved, data=np.vstack([copies, clutter]), sigma=sigma, volume=volume)


def _kernel(moved: np.ndarray, data: np.ndarray, sigma: float) -> np.ndarray:
    return np.exp(-np.sum((moved[:, None] - data[None]) ** 2, axis=2) / (2.0 * sigma**2))


def _no_outlier_class(moved, data, sigma, volume):
    kernel = _kernel(moved, data, sigma)
    return kernel / kernel.sum(axis=0)


def _paper_constant(moved, data, sigma, volume):
    return e_step_reference(moved, data, sigma, c=PAPER_C)


def _normalised_over_data(moved, data, sigma, volume):
    ball = _ball_volume(sigma)
    c = (1.0 - len(moved) * ball / volume) * (2.0 * np.pi * sigma**2) ** 1.5 / ball
    kernel = _kernel(moved, data, sigma)
    return kernel / (kernel.sum(axis=1, keepdims=True) + c)


def _gaussian_without_normalisation(moved, data, sigma, volume):
    ball = _ball_volume(sigma)
    return e_step_reference(moved, data, sigma, c=(1.0 - len(moved) * ball / volume) / ball)


EXERCISES = ExerciseSet(chapter=1, exercises=[
    Exercise(
        1, None,
        hint="divide the outlier term by Π_i (2πσ²)^(-1) and put in v = πσ²; σ² cancels",
        wrong_answers=(
            WrongAnswer(3.76, "the 3-D value of eq. (18)",
                        hint="that is the 3-D constant: in the plane the Gaussian is (2πσ²)^(-1) and v = πσ²"),
            WrongAnswer(0.5, "the ratio upside down, v / (2πσ²)",
                        hint="c is the outlier term over the texture term: (2πσ²)^(+1) / v, not v / (2πσ²)"),
            WrongAnswer(6.28, "the disc's area without its π",
                        hint="the disc of radius σ has area πσ², not σ²")),
        atol=0.005, rtol=0.0,
    ),
    Exercise(
        2, None,
        hint="each of the three kernels is e^0 = 1; add the three α of eq. (17), which share one denominator",
        wrong_answers=(
            WrongAnswer(0.21, "one texture point only",
                        hint="that is 1/(1 + c), one texture point; here three share the data point"),
            WrongAnswer(0.63, "three one-point probabilities added",
                        hint="the three kernels sit in one denominator: it holds all three and c"),
            WrongAnswer(0.56, "the outlier probability",
                        hint="that is c over the denominator, the outlier class's share; the question asks "
                             "for the texture points' total"),
            WrongAnswer(1.0, "the text's 'close to 1'",
                        hint="compute it from eq. (17) with c = 3√(π/2): the text of Sec. 3.2 and the "
                             "equations disagree")),
        atol=0.005, rtol=0.0,
    ),
    Exercise(
        3, None,
        hint="set outlier_c = 1e-9, run the cell, and take the median of the ten worst-joint errors (degrees)",
        wrong_answers=(
            WrongAnswer(3.11, "the unchanged run (c of eq. 18)", unchanged_experiment=True,
                        variable="no_outlier_median",
                        hint="that is the run with the outlier class: set outlier_c = 1e-9 and run again"),
            WrongAnswer(0.25, "the right median, in radians",
                        hint="give the median in degrees"),
            WrongAnswer(33.44, "the mean instead of the median",
                        hint="one draw ends far off and drags the mean: take the median"),
            WrongAnswer(20.0, "the start's error",
                        hint="20° is where every joint starts; run the experiment")),
        atol=0.005, rtol=0.0, experiment=True, why_points=1,
    ),
    Exercise(
        4, None,
        hint="run one σ level of 2 mm with 50 iterations and take the largest |joint - truth| of the last pose, "
             "in degrees",
        wrong_answers=(
            WrongAnswer(0.7, "the unchanged, annealed run", unchanged_experiment=True, variable="single_worst",
                        hint="that is the annealed run: set the levels to [2.0] and the iterations to 50"),
            WrongAnswer(0.49, "the right run, in radians", hint="give the error in degrees"),
            WrongAnswer(20.0, "the start's error", hint="20° is where every joint starts; run the experiment")),
        atol=0.05, rtol=0.0, experiment=True, why_points=1,
    ),
    Exercise(
        5, None,
        hint="set a = 50 and take the mean of the boolean array (a share between 0 and 1)",
        wrong_answers=(
            WrongAnswer(0.85, "the unchanged a = 10", unchanged_experiment=True, variable="rigid_share",
                        hint="that is a = 10, the unchanged cell: set exponent = 50.0"),
            WrongAnswer(0.61, "the paper's a = 2", hint="that is a = 2; the exercise asks for a = 50"),
            WrongAnswer(96.0, "a percentage", hint="give a fraction between 0 and 1, not a percentage"),
            WrongAnswer(1.0, "every point rigid",
                        hint="even at a = 50 a thin strip at each crease is blended: measure it")),
        atol=0.005, rtol=0.0, experiment=True, why_points=1,
    ),
    Exercise(
        6, None,
        hint="set share_c = 1e-9, run the cell, and give the mean over the ten draws (a fraction, two decimals)",
        wrong_answers=(
            WrongAnswer(0.04, "the unchanged run (c of eq. 18)", unchanged_experiment=True,
                        variable="clutter_share",
                        hint="that is the run with the outlier class: set share_c = 1e-9 and run again"),
            WrongAnswer(0.5, "the clutter's share of the data",
                        hint="half of the data is clutter, but the question asks for its share of the weight "
                             "Σ α at the final pose: run the cell"),
            WrongAnswer(17.0, "a percentage", hint="give a fraction between 0 and 1, not a percentage")),
        atol=0.005, rtol=0.0, experiment=True, why_points=2,
    ),
    Exercise(
        7, None,
        hint="Π_i = v/V and Π_outlier = (V - nv)/V (eqs. 4-5) with v = (4/3)πσ³; the Gaussian of eq. (6) in "
             "3-D is (2πσ²)^(-3/2) exp(-d²/2σ²), the outlier density 1/V (eq. 7); normalise each data point's "
             "column over the n texture points plus the outlier class (eq. 15)",
        kind="function", reference=_volume_e_step, make_case=_e_step_case, example_seed=0,
        wrong_answers=(
            WrongAnswer(_no_outlier_class, "the E-step without the outlier class",
                        hint="your columns sum to 1: every data point, clutter too, is forced onto the texture; "
                             "add the outlier class's term Π_outlier / V to the denominator"),
            WrongAnswer(_paper_constant, "the paper's c = 3√(π/2), which assumes nv << V",
                        hint="here the n balls fill 20-50 % of V: keep the factor (V - nv)/V of eq. (5)"),
            WrongAnswer(_normalised_over_data, "normalised over the data points",
                        hint="eq. (15) normalises over the texture points i for each data point j (a column), "
                             "not over the data for each texture point"),
            WrongAnswer(_gaussian_without_normalisation, "the Gaussian without (2πσ²)^(-3/2)",
                        hint="the Gaussian of eq. (6) carries its normalisation (2πσ²)^(-3/2); the outlier "
                             "density 1/V has none to cancel it")),
        rtol=1e-6, atol=1e-12,
    ),
])
