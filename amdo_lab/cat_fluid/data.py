"""Template/study pairs from images that ship inside dipy, deformed by known smooth warps.

The paper's CT slices are not available. dipy installs a 256x256 T1 coronal brain slice and the
circle and C shapes of its registration tutorial; nothing is downloaded. Each pair's study is the
template deformed by a known smooth displacement (so the registration error can be measured
against ground truth), plus, for pairs A and B, differences that no warp can explain: the paper
stresses that its pairs A and B do not contain the same grey/white-matter configuration.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.ndimage import binary_fill_holes, gaussian_filter

from amdo_lab.cat_fluid.registration import warp_image
from amdo_lab.common import as_finite_array, check_choice, check_positive, make_rng

__all__ = ["PAIR_NAMES", "DIPY_IMAGES", "RegistrationPair", "load_dipy_image", "smooth_warp", "foreground_mask",
           "make_pair"]

PAIR_NAMES = ("A", "B", "C")
DIPY_IMAGES = ("t1_coronal_slice", "reg_o", "reg_c")

# Decided from the paper's description of its pairs before any registration was run:
# (image, warp amplitude in pixels, extra structure in the study, noise sd, intensity drift)
_PAIR_SETTINGS = {
    "A": ("t1_coronal_slice", 4.0, True, 0.02, 0.0),   # not equivalent: a structure only in the study
    "B": ("t1_coronal_slice", 6.0, False, 0.02, 0.1),  # not equivalent: noise and a grey-level drift
    "C": ("reg_c", 5.0, False, 0.0, 0.0),              # equivalent: the same shape, warped
}


def load_dipy_image(name: str) -> np.ndarray:
    """One of :data:`DIPY_IMAGES` (each 256x256), as float grey levels scaled to [0, 1].

    They ship inside the dipy package (``dipy.data.get_fnames``); nothing is downloaded.
    """
    check_choice(name, "name", DIPY_IMAGES)
    from dipy.data import get_fnames  # lazy: dipy is slow to import

    image = np.load(get_fnames(name=name)).astype(float)
    return (image - image.min()) / (image.max() - image.min())


def smooth_warp(shape: tuple[int, int], rng: np.random.Generator | int, *, amplitude: float = 4.0,
                smoothness: float = 20.0, support: np.ndarray | None = None) -> np.ndarray:
    """A random smooth displacement (2, H, W) in pixels whose largest length is ``amplitude``.

    Gaussian-filtered white noise (standard deviation ``smoothness`` pixels, periodic); with a
    boolean ``support`` it fades out away from the object, so the border stays still.
    """
    rng = make_rng(rng)
    amplitude = check_positive(amplitude, "amplitude")
    smoothness = check_positive(smoothness, "smoothness")
    field = np.stack([gaussian_filter(rng.normal(size=shape), smoothness, mode="wrap") for _ in range(2)])
    if support is not None:
        field *= gaussian_filter(np.asarray(support, float), smoothness / 2)[None]
    return amplitude * field / np.max(np.hypot(field[0], field[1]))


def foreground_mask(image: object, threshold: float = 0.05) -> np.ndarray:
    """Boolean mask of the object (the head on a brain slice): grey level above ``threshold``,
    holes filled so dark structures inside (ventricles, sulci) count as foreground."""
    image = as_finite_array(image, "image", shape=(None, None))
    return binary_fill_holes(image > threshold)


@dataclass(frozen=True)
class RegistrationPair:
    """A template, its study and the known displacement: study ≈ template(x - true_displacement(x))."""

    name: str
    template: np.ndarray
    study: np.ndarray
    true_displacement: np.ndarray
    mask: np.ndarray


def _extra_structure(shape: tuple[int, int]) -> np.ndarray:
    """A bright blob (sd 5 pixels, +0.3) in the right hemisphere: present in the study only."""
    rows, cols = np.indices(shape, dtype=float)
    return 0.3 * np.exp(-((rows - 0.37 * shape[0]) ** 2 + (cols - 0.57 * shape[1]) ** 2) / (2 * 5.0 ** 2))


def make_pair(name: str, seed: int = 0) -> RegistrationPair:
    """Pairs in the spirit of the paper's Fig. 3 (grey levels in [0, 1], 256x256).

    A: the brain slice, a smooth warp of at most 4 pixels; the study also has a bright blob that
    the template lacks, and noise (sd 0.02). B: the brain slice, a different warp of at most 6
    pixels, noise and a ±10 % left-right grey-level drift. C: the C shape, a 5-pixel warp, no
    other change. ``mask`` is the foreground of the template or of the noise-free warped template.
    """
    check_choice(name, "name", PAIR_NAMES)
    image_name, amplitude, blob, noise, drift = _PAIR_SETTINGS[name]
    rng = make_rng(seed + PAIR_NAMES.index(name))
    template = load_dipy_image(image_name)
    true = smooth_warp(template.shape, rng, amplitude=amplitude, support=foreground_mask(template))
    study = warp_image(template, true)
    mask = foreground_mask(template) | foreground_mask(study)  # before the noise, which would speckle it
    if blob:
        study = study + _extra_structure(study.shape)
    if drift:
        study = study * (1.0 + drift * np.linspace(-1, 1, study.shape[1])[None, :])
    if noise:
        study = study + rng.normal(scale=noise, size=study.shape)
    return RegistrationPair(name, template, study, true, mask)
