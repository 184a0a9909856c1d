"""Viscous-fluid registration (Sec. 5): force eq. (18), a velocity solve, displacement update eq. (16).

Conventions. Images are (H, W) arrays; a displacement u is (2, H, W) in pixels, component 0
along array axis 0. The deformed template is T(x - u(x)) (Christensen's convention): u is the
displacement of the template, and x -> x - u(x) maps study coordinates to template coordinates.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from amdo_lab.cat_fluid.solvers import (SOLVERS, _sor_solve, cat_symbol, check_sor_grid, default_omega,
                                       finite_difference_symbol, solve_symbol)
from amdo_lab.cat_fluid.stencil import check_moduli
from amdo_lab.common import MAX_ITERATIONS
from amdo_lab.common import (
    as_bool_mask,
    as_finite_array,
    as_image_pair,
    check_bool,
    check_choice,
    check_in_range,
    check_overflow,
    check_positive,
    check_positive_int,
)

__all__ = ["FluidResult", "HISTORY_COLUMNS", "register_fluid", "warp_image", "external_force",
           "material_update", "displacement_jacobian", "jacobian_determinant",
           "grey_level_difference", "inverse_consistency_error", "displacement_rmse", "sample_bilinear",
           "check_pixel_mask"]

#: Columns of :attr:`FluidResult.history`; row 0 is the starting state.
HISTORY_COLUMNS = ("mean_abs_difference", "seconds", "min_jacobian", "step_pixels")

#: The paper's iteration counts (Sec. 5): 10 for the CAT scheme, 100 for SOR (x 250 sweeps).
DEFAULT_ITERATIONS = {"cat": 10, "fft": 10, "sor": 100}

#: Factor by which the step bound grows back after an accepted step (backtracking only).
STEP_GROWTH = 2.0

#: Largest grey level a registration accepts: the peer (dipy) computes in single precision, whose
#: largest float is about 3.4e38; one bound for both methods, so that they accept the same pairs.
MAX_GREY_LEVEL = 1e30


def _check_displacement(displacement: object, shape: tuple[int, ...], name: str = "displacement",
                        match: str = "image") -> np.ndarray:
    """A finite (2, H, W) field whose (H, W) is ``shape``, the shape of the argument ``match``: the error
    names both arguments, since either may be the one at fault."""
    return as_finite_array(displacement, f"{name} (on the pixels of {match})", shape=(2, *shape))


def _check_differentiable(array: np.ndarray, name: str) -> np.ndarray:
    """Finite differences (np.gradient) need at least two pixels along each image axis."""
    check_positive_int(min(array.shape[-2:]), f"{name}'s smaller image side (pixels)", minimum=2)
    return array


def _finite(result: np.ndarray, names: str) -> np.ndarray:
    """``result``, or a ValueError naming the arguments whose size drove it out of float range."""
    check_overflow(result, names)
    return result


def sample_bilinear(image: np.ndarray, coords: np.ndarray) -> np.ndarray:
    """image at the (2, H, W) array coordinates ``coords``, bilinear, coordinates clamped to the image
    (the same values as ``scipy.ndimage.map_coordinates(order=1, mode="nearest")``, a few times faster)."""
    n0, n1 = image.shape
    c0 = np.clip(coords[0], 0, n0 - 1)
    c1 = np.clip(coords[1], 0, n1 - 1)
    i0 = np.minimum(c0.astype(np.intp), n0 - 2)  # lower corner; the top row/column uses weight 1
    i1 = np.minimum(c1.astype(np.intp), n1 - 2)
    f0, f1 = c0 - i0, c1 - i1
    flat = image.ravel()
    base = i0 * n1 + i1
    top = flat[base] + f1 * (flat[base + 1] - flat[base])
    bottom = flat[base + n1] + f1 * (flat[base + n1 + 1] - flat[base + n1])
    return top + f0 * (bottom - top)


def _warp(image: np.ndarray, displacement: np.ndarray) -> np.ndarray:
    return sample_bilinear(image, np.indices(image.shape, dtype=float) - displacement)


def warp_image(image: object, displacement: object) -> np.ndarray:
    """The deformed image I(x - u(x)), bilinear interpolation.

    Points that fall outside the image take the value of the nearest border pixel.

    Parameters
    ----------
    image : array_like, shape (H, W)
        Finite grey levels.
    displacement : array_like, shape (2, H, W)
        u in pixels, component 0 along array axis 0.

    Returns
    -------
    numpy.ndarray of float, shape (H, W)
        The warped image.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    Sec. 5 (the deformed template T(x - u(x)) of Christensen's convention);
    G. E. Christensen, S. Joshi, M. I. Miller, "Volumetric transformation of brain anatomy",
    IEEE Trans. Med. Imaging 16(6), 864-877, 1997 (the paper's reference [2]).
    """
    image = as_finite_array(image, "image", shape=(None, None))
    return _warp(image, _check_displacement(displacement, image.shape, match="image"))


def _jacobian(displacement: np.ndarray) -> np.ndarray:
    return np.stack([np.stack(np.gradient(component), axis=0) for component in displacement], axis=0)


def displacement_jacobian(displacement: object) -> np.ndarray:
    """J[i, j] = ∂u_i/∂x_j by central differences (one-sided at the border).

    Parameters
    ----------
    displacement : array_like, shape (2, H, W)
        u in pixels; H, W ≥ 2.

    Returns
    -------
    numpy.ndarray of float, shape (2, 2, H, W)
        The Jacobian matrix of u at every pixel (dimensionless).

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    eq. (16) (our reading of its (∇u)ᵀ, see :func:`material_update`).
    """
    displacement = as_finite_array(displacement, "displacement", shape=(2, None, None))
    return _jacobian(_check_differentiable(displacement, "displacement"))


def jacobian_determinant(displacement: object) -> np.ndarray:
    """det(I - ∇u) of the map x -> x - u(x); a value ≤ 0 marks a folded pixel.

    Parameters
    ----------
    displacement : array_like, shape (2, H, W)
        u in pixels; H, W ≥ 2.

    Returns
    -------
    numpy.ndarray of float, shape (H, W)
        Local area ratio of the map (1 where u is constant).

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    Sec. 5 (regridding on the Jacobian, after Christensen et al.);
    G. E. Christensen, S. Joshi, M. I. Miller, "Volumetric transformation of brain anatomy",
    IEEE Trans. Med. Imaging 16(6), 864-877, 1997 (the paper's reference [2]).
    """
    displacement = as_finite_array(displacement, "displacement", shape=(2, None, None))
    return _finite(_determinant(_check_differentiable(displacement, "displacement")), "displacement")


def _determinant(displacement: np.ndarray) -> np.ndarray:
    jac = _jacobian(displacement)
    return (1 - jac[0, 0]) * (1 - jac[1, 1]) - jac[0, 1] * jac[1, 0]


def _force(deformed_template: np.ndarray, study: np.ndarray) -> np.ndarray:
    # eq. (18): F = -(I1 - I2) ∇I1, ∇ by central differences (one-sided at the border)
    return -(deformed_template - study)[None] * np.stack(np.gradient(deformed_template), axis=0)


def external_force(deformed_template: object, study: object) -> np.ndarray:
    """Eq. (18): F = -(I1 - I2) ∇I1 with I1 the deformed template and I2 the study.

    Parameters
    ----------
    deformed_template : array_like, shape (H, W)
        I1, finite grey levels; H, W ≥ 2.
    study : array_like, shape (H, W)
        I2, finite grey levels.

    Returns
    -------
    numpy.ndarray of float, shape (2, H, W)
        Force per pixel in grey level² per pixel; ∇ by central differences (one-sided at the border).

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    eq. (18).
    """
    deformed_template, study = as_image_pair(deformed_template, study, ("deformed_template", "study"))
    return _finite(_force(_check_differentiable(deformed_template, "deformed_template"), study),
                   "deformed_template and study")


def _update(displacement: np.ndarray, velocity: np.ndarray, dt: float) -> np.ndarray:
    jac = _jacobian(displacement)  # J[i, j] = ∂u_i/∂x_j, our reading of (∇u)ᵀ in eq. (16)
    # eq. (16): u_i <- u_i + Δt (v_i - Σ_j J[i, j] v_j), for i = 1, 2 at every pixel
    return displacement + dt * (velocity - np.einsum("ijhw,jhw->ihw", jac, velocity))


def material_update(displacement: object, velocity: object, dt: float) -> np.ndarray:
    """Eq. (16): u + Δt (I - J) v with J[i, j] = ∂u_i/∂x_j, i.e. Δt (v - (v·∇)u).

    The paper prints (I - (∇u)ᵀ) v. We read ∇u with the continuum-mechanics convention
    (∇u)[j, i] = ∂u_i/∂x_j, so its transpose is J: the update is then the material derivative
    ∂u/∂t = v - (v·∇)u of Christensen et al., the only reading under which the deformed template
    T(x - u) is carried along by v. (tests/test_cat_fluid.py pins this down against the exact
    flow of a known displacement.)

    Parameters
    ----------
    displacement : array_like, shape (2, H, W)
        u in pixels; H, W ≥ 2.
    velocity : array_like, shape (2, H, W)
        v in pixels per unit time.
    dt : float
        Time step Δt, > 0.

    Returns
    -------
    numpy.ndarray of float, shape (2, H, W)
        The updated displacement, pixels.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    eq. (16);
    G. E. Christensen, S. Joshi, M. I. Miller, "Volumetric transformation of brain anatomy",
    IEEE Trans. Med. Imaging 16(6), 864-877, 1997 (the paper's reference [2]).
    """
    displacement = as_finite_array(displacement, "displacement", shape=(2, None, None))
    _check_differentiable(displacement, "displacement")
    velocity = _check_displacement(velocity, displacement.shape[1:], "velocity", match="displacement")
    return _update(displacement, velocity, check_positive(dt, "dt"))


def _compose(first: np.ndarray, second: np.ndarray) -> np.ndarray:
    """Displacement of "warp by ``first``, then warp the result by ``second``" (regridding composes the
    segments' displacements, after Christensen et al.): warp(warp(I, first), second)(x) = I(x - w(x)) with
    w(x) = second(x) + first(x - second(x)), ``first`` sampled bilinearly, clamped at the border."""
    moved = np.indices(first.shape[1:], dtype=float) - second
    return second + np.stack([sample_bilinear(component, moved) for component in first])


def grey_level_difference(image: object, reference: object, mask: object | None = None,
                          scale: float = 1.0) -> tuple[float, float]:
    """Table 1's measure: mean and standard deviation of |image - reference| times ``scale``.

    Parameters
    ----------
    image : array_like, shape (H, W)
        Finite grey levels, e.g. the deformed template.
    reference : array_like, shape (H, W)
        Finite grey levels, e.g. the study.
    mask : array_like of bool, shape (H, W), optional
        Pixels to average over (at least one True); all pixels by default.
    scale : float, optional
        Factor on the differences, > 0 (default 1; 255 for the paper's 0-255 grey levels).

    Returns
    -------
    mean, sd : float
        Mean and standard deviation of the scaled absolute differences.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    Table 1.
    """
    image, reference = as_image_pair(image, reference, ("image", "reference"))
    scale = check_positive(scale, "scale")
    diff = _finite(scale * np.abs(image - reference), "scale, image and reference")
    if mask is not None:
        diff = diff[check_pixel_mask(mask, image.shape)]
    return float(_finite(diff.mean(), "scale, image and reference")), float(_finite(diff.std(), "scale, image and reference"))


def check_pixel_mask(mask: object, shape: tuple[int, ...], name: str = "mask") -> np.ndarray:
    """A boolean mask of ``shape`` that selects at least one pixel (an empty mean would be NaN).

    Parameters
    ----------
    mask : array_like of bool, shape ``shape``
        The user's mask.
    shape : tuple of int
        (H, W) of the images it selects pixels of.
    name : str, optional
        The argument's name, used in error messages.

    Returns
    -------
    numpy.ndarray of bool
        The mask.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85, Table 1 (residuals over a region).
    """
    mask = as_bool_mask(mask, name, shape=shape)
    if not mask.any():
        raise ValueError(f"{name} must select at least one pixel, got an all-False mask")
    return mask


def displacement_rmse(displacement: object, truth: object, mask: object | None = None) -> float:
    """Root-mean-square length of (displacement - truth) over all pixels or a boolean mask.

    Parameters
    ----------
    displacement : array_like, shape (2, H, W)
        Estimated displacement, pixels.
    truth : array_like, shape (2, H, W)
        Known displacement, pixels.
    mask : array_like of bool, shape (H, W), optional
        Pixels to average over (at least one True); all pixels by default.

    Returns
    -------
    float
        RMS error in pixels, ≥ 0.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    Sec. 5 (the paper measures grey levels only; with known warps we can measure this too).
    """
    truth = as_finite_array(truth, "truth", shape=(2, None, None))
    displacement = _check_displacement(displacement, truth.shape[1:], match="truth")
    return _rmse(displacement - truth, mask, "displacement and truth")


def _rmse(error: np.ndarray, mask: object | None, names: str) -> float:
    squared = _finite(np.sum(error ** 2, axis=0), names)
    return float(_finite(np.sqrt(squared.mean() if mask is None else squared[check_pixel_mask(mask, squared.shape)].mean()),
                         names))


def inverse_consistency_error(forward: object, backward: object, mask: object | None = None) -> float:
    """RMS of x - h_f(h_b(x)) in pixels, with h(x) = x - u(x).

    For u_f registering A to B and u_b registering B to A; 0 for a perfectly inverse-consistent pair.

    Parameters
    ----------
    forward : array_like, shape (2, H, W)
        u_f, pixels.
    backward : array_like, shape (2, H, W)
        u_b, pixels.
    mask : array_like of bool, shape (H, W), optional
        Pixels to average over (at least one True); all pixels by default.

    Returns
    -------
    float
        RMS error in pixels, ≥ 0.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    Sec. 5 (a property of the fluid model the paper does not measure);
    G. E. Christensen, S. Joshi, M. I. Miller, "Volumetric transformation of brain anatomy",
    IEEE Trans. Med. Imaging 16(6), 864-877, 1997 (the paper's reference [2]).
    """
    forward = as_finite_array(forward, "forward", shape=(2, None, None))
    backward = _check_displacement(backward, forward.shape[1:], "backward", match="forward")
    return _rmse(_compose(forward, backward), mask, "forward and backward")


@dataclass(frozen=True)
class FluidResult:
    """Result of :func:`register_fluid`.

    Parameters
    ----------
    warped : numpy.ndarray of float, shape (H, W)
        Deformed template T(x - u(x)).
    displacement : numpy.ndarray of float, shape (2, H, W)
        Total displacement u of the template, pixels.
    history : numpy.ndarray of float, shape (n + 1, 4)
        One row per iteration after the starting row 0; columns :data:`HISTORY_COLUMNS`: mean
        |warped - study|, seconds since the start, min det(I - ∇u) of the total displacement, and
        the largest displacement change of the step in pixels (0 if rejected).
    n_regrids : int
        Number of regriddings.
    method : str
        The velocity solver used: "cat", "sor" or "fft".

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    Sec. 5, eqs. (15)-(18).
    """

    warped: np.ndarray
    displacement: np.ndarray
    history: np.ndarray
    n_regrids: int
    method: str

    @property
    def residuals(self) -> np.ndarray:
        """Mean |warped - study| per iteration, starting state first (grey levels in the images' scale).
        """
        return self.history[:, 0]

    @property
    def seconds(self) -> float:
        """Wall-clock time of the whole registration, seconds.
        """
        return float(self.history[-1, 1])


def check_registration_images(template: object, study: object) -> tuple[np.ndarray, np.ndarray]:
    """The input rules of a registration of ``template`` onto ``study``, shared by :func:`register_fluid`
    and its peer :func:`~amdo_lab.cat_fluid.peer.register_dipy`.

    Parameters
    ----------
    template : array_like, shape (H, W)
        Finite grey levels within ±1e30, not constant, H, W ≥ 4.
    study : array_like, shape (H, W)
        Finite grey levels within ±1e30, not constant, same shape as ``template``.

    Returns
    -------
    template, study : numpy.ndarray of float, shape (H, W)
        Float copies of both images.

    Raises
    ------
    ValueError
        Naming the argument at fault.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85, Sec. 5 (the registration task).
    """
    template = as_finite_array(template, "template", shape=(None, None), max_abs=MAX_GREY_LEVEL)
    # a size mismatch names both images: either may be at fault
    study = as_finite_array(study, "study (same shape as template)", shape=template.shape,
                            max_abs=MAX_GREY_LEVEL)
    check_positive_int(min(template.shape), "the images' smaller side (pixels)", minimum=4)
    for image, name in ((template, "template"), (study, "study")):
        if np.ptp(image) == 0:
            raise ValueError(f"{name} is constant: without grey-level structure eq. (18) gives no force")
    return template, study


def register_fluid(template: object, study: object, method: str = "cat", lam: float = 1.0, mu: float = 5.0,
                   n_iter: int | None = None, *, max_step_px: float = 1.0, backtrack: bool = True,
                   regrid_threshold: float = 0.5, sor_n_sweeps: int = 250, sor_omega: float | None = None,
                   sor_warm_start: bool = True) -> FluidResult:
    """Deform ``template`` onto ``study`` as a viscous fluid (Secs. 4-5).

    Each iteration: the force of eq. (18) on the deformed template; the velocity from
    ``method`` ("cat": the CAT stencil, eq. 15; "sor" or "fft": the finite-difference eq. 17 by
    SOR or exactly); then eq. (16), u <- u + Δt (I - J_u) v (:func:`material_update`), with Δt set
    so that the largest displacement change is the current step bound (``max_step_px`` pixels at
    first). With ``backtrack`` a step that does not lower the sum of squared differences is
    rejected and the bound halved, and after an accepted step the bound doubles again up to
    ``max_step_px`` (the paper does not say how it chose Δt; this keeps a fixed step from
    oscillating). The same rule applies to every ``method``. When min det(I - ∇u) of the current
    segment falls below ``regrid_threshold``, a new segment starts from the deformed template
    (regridding, as Christensen et al.); the segments are composed and the original template is
    warped once by the composition, so regridding adds no blur.

    Parameters
    ----------
    template : array_like, shape (H, W)
        Finite grey levels within ±1e30, not constant, H, W ≥ 4 (even for "sor").
    study : array_like, shape (H, W)
        Finite grey levels within ±1e30, not constant, same shape as ``template``.
    method : str, optional
        Velocity solver: "cat" (default), "sor" or "fft".
    lam : float, optional
        Lamé constant λ, 0 ≤ λ ≤ 1e150 (default 1, as the paper).
    mu : float, optional
        Lamé constant μ, 0 < μ ≤ 1e150 (default 5, as the paper).
    n_iter : int, optional
        Number of velocity solves, ≥ 1; default the paper's counts, 10 for "cat" and "fft", 100
        for "sor".
    max_step_px : float, optional
        Largest displacement change per iteration, pixels, > 0 and at most the image's longer side
        (default 1).
    backtrack : bool, optional
        Reject a step that does not decrease the SSD and halve the bound (default); False keeps
        Christensen's fixed bound, every step accepted.
    regrid_threshold : float, optional
        Regrid when min det(I - ∇u) of the segment falls below it, in [0, 1) (default 0.5); 0
        never regrids (the map may then fold: det ≤ 0).
    sor_n_sweeps : int, optional
        SOR sweeps per velocity solve, ≥ 1 (default 250, as the paper); "sor" only.
        At most :data:`amdo_lab.common.MAX_ITERATIONS` (100,000).
    sor_omega : float, optional
        SOR relaxation factor in (0, 2); default
        :func:`~amdo_lab.cat_fluid.solvers.default_omega`.
    sor_warm_start : bool, optional
        Start each SOR solve from the previous iteration's velocity (default) or from zero (the
        paper does not say which it did).

    Returns
    -------
    FluidResult
        Deformed template, total displacement (pixels), per-iteration history, number of
        regriddings and the method.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    Secs. 4-5, eqs. (15)-(18);
    G. E. Christensen, S. Joshi, M. I. Miller, "Volumetric transformation of brain anatomy",
    IEEE Trans. Med. Imaging 16(6), 864-877, 1997 (the paper's reference [2]).

    Examples
    --------
    >>> import numpy as np
    >>> from amdo_lab.cat_fluid import register_fluid
    >>> rows, cols = np.indices((32, 32)) - 15.5
    >>> template = (np.hypot(rows, cols) < 8).astype(float)      # a disc
    >>> study = (np.hypot(rows - 2, cols) < 8).astype(float)     # the disc, 2 pixels down
    >>> result = register_fluid(template, study, "cat", n_iter=20)
    >>> bool(result.residuals[-1] < 0.01 * result.residuals[0])
    True
    >>> bool(result.history[:, 2].min() > 0)  # no folds
    True
    """
    template, study = check_registration_images(template, study)
    check_choice(method, "method", SOLVERS)
    lam, mu = check_moduli(lam, mu, require_positive_mu=True)
    check_bool(backtrack, "backtrack")
    check_bool(sor_warm_start, "sor_warm_start")
    n_iter = check_positive_int(DEFAULT_ITERATIONS[method] if n_iter is None else n_iter, "n_iter", maximum=MAX_ITERATIONS)
    step_bound = check_in_range(max_step_px, "max_step_px", 0, max(template.shape), closed="right")
    regrid_threshold = check_in_range(regrid_threshold, "regrid_threshold", 0, 1, closed="left")
    sor_n_sweeps = check_positive_int(sor_n_sweeps, "sor_n_sweeps", maximum=MAX_ITERATIONS)
    if sor_omega is not None:
        check_in_range(sor_omega, "sor_omega", 0, 2)  # SOR converges for 0 < omega < 2 only
    if method == "sor":
        check_sor_grid(template.shape, "template")
        omega = default_omega(template.shape) if sor_omega is None else sor_omega
    start = time.perf_counter()
    symbol = None
    if method != "sor":
        symbol = (cat_symbol if method == "cat" else finite_difference_symbol)(template.shape, lam, mu)
    previous = np.zeros((2,) + template.shape)   # composition of the finished segments
    segment = np.zeros_like(previous)            # displacement of the current segment
    total, velocity, warped = previous.copy(), np.zeros_like(previous), template
    ssd = float(np.sum((warped - study) ** 2))
    history, regrids = [(float(np.mean(np.abs(warped - study))), 0.0, 1.0, 0.0)], 0
    for _ in range(n_iter):
        force = _force(warped, study)
        force -= force.mean(axis=(1, 2), keepdims=True)
        if symbol is None:
            velocity = _sor_solve(force, lam, mu, sor_n_sweeps, omega,
                                  velocity if sor_warm_start else np.zeros_like(force))
        else:
            velocity = solve_symbol(symbol, force)
        unit = _update(segment, velocity, 1.0) - segment
        largest = float(np.max(np.hypot(unit[0], unit[1])))
        taken = 0.0
        while largest > 0:
            candidate = segment + (step_bound / largest) * unit
            candidate_total = candidate if regrids == 0 else _compose(previous, candidate)
            candidate_warped = _warp(template, candidate_total)
            candidate_ssd = float(np.sum((candidate_warped - study) ** 2))
            if not backtrack or candidate_ssd < ssd:
                segment, total, warped, ssd, taken = candidate, candidate_total, candidate_warped, candidate_ssd, step_bound
                if backtrack:  # a step that worked: let the bound grow back towards max_step_px
                    step_bound = min(STEP_GROWTH * step_bound, max_step_px)
                break
            step_bound /= 2
            if step_bound < 1e-3 * max_step_px:  # no descent left at any sensible step: stop moving
                break
        total_det = float(_determinant(total).min())
        segment_det = total_det if regrids == 0 else float(_determinant(segment).min())
        if regrid_threshold > 0 and taken and segment_det < regrid_threshold:  # 0: never regrid
            previous, segment, regrids = total, np.zeros_like(segment), regrids + 1
        history.append((float(np.mean(np.abs(warped - study))), time.perf_counter() - start, total_det, taken))
    return FluidResult(warped, total, np.array(history), regrids, method)
