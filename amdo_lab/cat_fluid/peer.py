"""The peer a user would pick: DIPY's symmetric diffeomorphic registration (SyN), same conventions."""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass

import numpy as np

from amdo_lab.cat_fluid.registration import check_registration_images
from amdo_lab.common import MAX_ITERATIONS
from amdo_lab.common import as_finite_array, check_choice

__all__ = ["DipyResult", "register_dipy"]


@dataclass(frozen=True)
class DipyResult:
    """Result of :func:`register_dipy`, in this chapter's conventions.

    Parameters
    ----------
    warped : numpy.ndarray of float, shape (H, W)
        The deformed template.
    displacement : numpy.ndarray of float, shape (2, H, W)
        Displacement u of the template in pixels, warped = template(x - u(x)).
    backward : numpy.ndarray of float, shape (2, H, W)
        Displacement of the study onto the template from the same symmetric run, pixels.
    seconds : float
        Wall-clock time of the registration.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    Sec. 5 (the task SyN is compared on); B. B. Avants, C. L. Epstein, M. Grossman, J. C. Gee,
    "Symmetric diffeomorphic image registration with cross-correlation: evaluating automated
    labeling of elderly and neurodegenerative brain", Medical Image Analysis 12(1), 26-41, 2008 (SyN).
    """

    warped: np.ndarray
    displacement: np.ndarray
    backward: np.ndarray
    seconds: float


def register_dipy(template: object, study: object, metric: str = "cc",
                  level_iters: tuple[int, ...] = (100, 100, 25)) -> DipyResult:
    """Register ``template`` onto ``study`` with dipy's ``SymmetricDiffeomorphicRegistration`` (SyN).

    dipy warps the moving image as moving(x + f(x)) with its forward field f, so our displacement
    is -f.

    Parameters
    ----------
    template : array_like, shape (H, W)
        Finite grey levels within ±1e30 (dipy computes in single precision), not constant, H, W ≥ 4.
    study : array_like, shape (H, W)
        Finite grey levels within ±1e30, not constant, same shape.
    metric : str, optional
        "cc" (local cross-correlation, dipy's choice for brain images; default) or "ssd".
    level_iters : tuple of int, optional
        dipy's iterations per pyramid level, coarsest last, each ≥ 0 (default (100, 100, 25),
        dipy's own default). At most :data:`amdo_lab.common.MAX_ITERATIONS` (100,000).

    Returns
    -------
    DipyResult
        Deformed template, forward and backward displacements (pixels) and seconds.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    Sec. 5 (the task SyN is compared on); B. B. Avants, C. L. Epstein, M. Grossman, J. C. Gee,
    "Symmetric diffeomorphic image registration with cross-correlation: evaluating automated
    labeling of elderly and neurodegenerative brain", Medical Image Analysis 12(1), 26-41, 2008 (SyN).
    """
    template, study = check_registration_images(template, study)
    check_choice(metric, "metric", ("cc", "ssd"))
    level_iters = as_finite_array(level_iters, "level_iters", ndim=1, dtype=int, bounds=(0, MAX_ITERATIONS))
    from dipy.align.imwarp import SymmetricDiffeomorphicRegistration  # lazy: dipy is slow to import
    from dipy.align.metrics import CCMetric, SSDMetric

    logging.getLogger("dipy").setLevel(logging.WARNING)  # its per-level INFO lines are noise here
    start = time.perf_counter()
    registration = SymmetricDiffeomorphicRegistration(CCMetric(2) if metric == "cc" else SSDMetric(2),
                                                      level_iters=level_iters.tolist())
    mapping = registration.optimize(study, template)
    seconds = time.perf_counter() - start
    forward = -np.moveaxis(np.asarray(mapping.get_forward_field(), float), -1, 0)
    backward = -np.moveaxis(np.asarray(mapping.get_backward_field(), float), -1, 0)
    return DipyResult(np.asarray(mapping.transform(template), float), forward, backward, seconds)
