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
from amdo_lab.common import check_choice, make_rng

__all__ = ["PAIR_NAMES", "DIPY_IMAGES", "BLOB_CENTRE_FRACTION", "BLOB_SD", "BLOB_HEIGHT", "RegistrationPair",
           "load_dipy_image", "make_pair"]

PAIR_NAMES = ("A", "B", "C")
WARP_SMOOTHNESS_PX = 20.0  # _smooth_warp's filter width (s.d., pixels): warps smooth over tens of pixels
DIPY_IMAGES = ("t1_coronal_slice", "reg_o", "reg_c")
FOREGROUND_LEVEL = 0.05  # grey level above which a pixel is object (the images are in [0, 1])

# Decided from the paper's description of its pairs before any registration was run:
# (image, warp amplitude in pixels, extra structure in the study, noise sd, intensity drift)
_PAIR_SETTINGS = {
    "A": ("t1_coronal_slice", 4.0, True, 0.02, 0.0),   # not equivalent: a structure only in the study
    "B": ("t1_coronal_slice", 6.0, False, 0.02, 0.1),  # not equivalent: noise and a grey-level drift
    "C": ("reg_c", 5.0, False, 0.0, 0.0),              # equivalent: the same shape, warped
}


def load_dipy_image(name: str) -> np.ndarray:
    """One of :data:`DIPY_IMAGES` (each 256x256), as float grey levels scaled to [0, 1].

    They ship inside the dipy package (``dipy.data.get_fnames``); nothing is downloaded. They stand
    in for the paper's CT slices, which are not available.

    Parameters
    ----------
    name : str
        "t1_coronal_slice" (a T1 brain slice), "reg_o" (a circle) or "reg_c" (a C shape).

    Returns
    -------
    numpy.ndarray of float, shape (256, 256)
        Grey levels, minimum 0 and maximum 1.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    Sec. 5 and Fig. 3 (the CT slices these images replace).
    """
    check_choice(name, "name", DIPY_IMAGES)
    from dipy.data import get_fnames  # lazy: dipy is slow to import

    image = np.load(get_fnames(name=name)).astype(float)
    return (image - image.min()) / (image.max() - image.min())


def _smooth_warp(shape: tuple[int, int], rng: np.random.Generator, amplitude_px: float,
                 support: np.ndarray | None = None) -> np.ndarray:
    """A random smooth (2, H, W) displacement in pixels whose largest length is ``amplitude_px``: white
    noise from ``rng`` filtered by a periodic Gaussian of s.d. :data:`WARP_SMOOTHNESS_PX` (20 pixels); with
    a boolean ``support`` it fades out away from the object, so the border stays still. Check-free: the
    known warps of :func:`make_pair`."""
    field = np.stack([gaussian_filter(rng.normal(size=shape), WARP_SMOOTHNESS_PX, mode="wrap") for _ in range(2)])
    if support is not None:
        field *= gaussian_filter(support.astype(float), WARP_SMOOTHNESS_PX / 2)[None]
    return amplitude_px * field / np.max(np.hypot(field[0], field[1]))


def _foreground_mask(image: np.ndarray) -> np.ndarray:
    """The object (the head on a brain slice): grey level above :data:`FOREGROUND_LEVEL`, holes filled, so
    dark structures inside (ventricles, sulci) count as foreground. Check-free: :func:`make_pair`'s mask."""
    return binary_fill_holes(image > FOREGROUND_LEVEL)


@dataclass(frozen=True)
class RegistrationPair:
    """A template, its study and the known displacement: study ≈ template(x - true_displacement(x)).

    Parameters
    ----------
    name : str
        "A", "B" or "C" (:data:`PAIR_NAMES`).
    template : numpy.ndarray of float, shape (H, W)
        The image deformed by registration, grey levels in [0, 1].
    study : numpy.ndarray of float, shape (H, W)
        The warped template, plus for pairs A and B changes no warp explains.
    true_displacement : numpy.ndarray of float, shape (2, H, W)
        The warp that made the study, pixels.
    mask : numpy.ndarray of bool, shape (H, W)
        Foreground of the template or of the noise-free warped template.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    Sec. 5 and Fig. 3 (its pairs A, B and C).
    """

    name: str
    template: np.ndarray
    study: np.ndarray
    true_displacement: np.ndarray
    mask: np.ndarray


#: Pair A's extra structure: centre as fractions of (H, W), standard deviation in pixels, height.
BLOB_CENTRE_FRACTION, BLOB_SD, BLOB_HEIGHT = (0.37, 0.57), 5.0, 0.3


def _extra_structure(shape: tuple[int, int]) -> np.ndarray:
    """A bright Gaussian blob in the right hemisphere (see ``BLOB_*``): present in the study only."""
    rows, cols = np.indices(shape, dtype=float)
    centre = (BLOB_CENTRE_FRACTION[0] * shape[0], BLOB_CENTRE_FRACTION[1] * shape[1])
    return BLOB_HEIGHT * np.exp(-((rows - centre[0]) ** 2 + (cols - centre[1]) ** 2) / (2 * BLOB_SD ** 2))


def make_pair(name: str, *, rng: int | np.random.Generator) -> RegistrationPair:
    """Pairs in the spirit of the paper's Fig. 3 (grey levels in [0, 1], 256x256).

    A: the brain slice, a smooth warp of at most 4 pixels; the study also has a bright blob that
    the template lacks, and noise (sd 0.02). B: the brain slice, a different warp of at most 6
    pixels, noise and a ±10 % left-right grey-level drift. C: the C shape, a 5-pixel warp, no
    other change. ``mask`` is the foreground of the template or of the noise-free warped template.

    Parameters
    ----------
    name : str
        "A", "B" or "C".
    rng : int or numpy.random.Generator
        Keyword-only, no default. An int seed s draws from seed s + the pair's index in
        :data:`PAIR_NAMES` (so the three pairs at one seed differ); a generator is used as it is.

    Returns
    -------
    RegistrationPair
        Template, study, true displacement (pixels) and foreground mask.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    Sec. 5 and Fig. 3.

    Examples
    --------
    >>> import numpy as np
    >>> from amdo_lab.cat_fluid import make_pair
    >>> pair = make_pair("C", rng=0)
    >>> pair.study.shape, pair.true_displacement.shape
    ((256, 256), (2, 256, 256))
    >>> round(float(np.hypot(*pair.true_displacement).max()), 6)  # pair C's warp: at most 5 pixels
    5.0
    """
    check_choice(name, "name", PAIR_NAMES)
    generator = make_rng(rng, "rng")
    if not isinstance(rng, np.random.Generator):
        # an int seed s draws from seed s + the pair's index, so pairs A, B and C at one seed differ
        generator = make_rng(int(rng) + PAIR_NAMES.index(name), "rng")
    image_name, amplitude, blob, noise, drift = _PAIR_SETTINGS[name]
    template = load_dipy_image(image_name)
    true = _smooth_warp(template.shape, generator, amplitude, support=_foreground_mask(template))
    study = warp_image(template, true)
    mask = _foreground_mask(template) | _foreground_mask(study)  # before the noise, which would speckle it
    if blob:
        study = study + _extra_structure(study.shape)
    if drift:
        study = study * (1.0 + drift * np.linspace(-1, 1, study.shape[1])[None, :])
    if noise:
        study = study + generator.normal(scale=noise, size=study.shape)
    return RegistrationPair(name, template, study, true, mask)
