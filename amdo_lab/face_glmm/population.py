"""A seeded synthetic face population and the FERET-style preprocessing of Sec. 2.

FERET cannot be shipped, so each subject is drawn from a small generative model:
identity = face geometry (eye, nose, mouth positions and sizes) + a low-frequency,
mostly left-right symmetric texture + a mostly symmetric random texture whose power
spectrum falls as a power of the spatial frequency, as real faces' does; each image adds
nuisance = sub-pixel misregistration, a linear illumination gradient, an expression change,
a weaker random texture of the same spectrum and pixel noise.
A per-subject ``difficulty`` multiplies that subject's nuisance, so some people are
much harder to recognise than others (the source of the probe random effect).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from amdo_lab.common import MAX_SAMPLES, as_finite_array, check_image_shape, check_in_range, check_positive_int, make_rng

__all__ = [
    "FacePopulation",
    "STANDARD_SHAPE",
    "SMALL_SHAPE",
    "make_face_population",
    "preprocess_images",
    "downsample_by_two",
    "TEXTURE_SLOPE",
    "TEXTURE_AMPLITUDE",
]

#: Our "standard" image (rows, cols): FERET's 150 x 130 scaled by 1/2.5 so the whole
#: factorial design runs in about a minute; the small size halves each side, i.e. has a
#: quarter of the pixels, exactly as FERET's 75 x 65 relates to 150 x 130.
STANDARD_SHAPE = (60, 52)
SMALL_SHAPE = (30, 26)

_N_TEXTURE = 6  # low-frequency cosine basis per axis for the identity texture

#: Default slope s of the random texture's power spectrum f^-s. With it the faces' measured spectrum
#: falls about as f^-3.1 (real faces of ``lfw_subset``: f^-2.3; the cosine texture alone: f^-4.5).
#: A flatter texture brings the spectrum closer to the real faces' but, at the calibrated recognition
#: rate, spreads the PCA energy of the supplemented training sets beyond the paper's E90 range; the
#: chapter measures both.
TEXTURE_SLOPE = 2.8
#: Default standard deviation of the subject's random texture (face contrast is about 1).
TEXTURE_AMPLITUDE = 1.5


@dataclass(frozen=True)
class FacePopulation:
    """Raw (unpreprocessed) face images with identity labels.

    Parameters
    ----------
    images : ndarray, shape (n_subjects * images_per_subject, rows, cols)
        Grey values (arbitrary units, face contrast about 1); image ``i`` belongs to subject
        ``labels[i]``.
    labels : ndarray of int, shape (n_images,)
        Subject index; images of one subject are contiguous.
    difficulty : ndarray, shape (n_subjects,)
        The per-subject nuisance multiplier (positive; larger = harder to recognise).
    images_per_subject : int
        Images of each subject (4 in the paper).

    References
    ----------
    Givens et al. (2004), AMDO, LNCS 3179, Sec. 2 (FERET, for which this synthetic population stands in).
    """

    images: np.ndarray
    labels: np.ndarray
    difficulty: np.ndarray
    images_per_subject: int

    @property
    def n_subjects(self) -> int:
        """Number of subjects (people) in the population."""
        return int(self.difficulty.size)


def _blob(x, y, cx, cy, sx, sy):
    return np.exp(-0.5 * (((x - cx) / sx) ** 2 + ((y - cy) / sy) ** 2))


#: Standard deviation of log difficulty across subjects.
DIFFICULTY_SPREAD = 0.25
#: Pixel noise standard deviation (grey values; face contrast is about 1).
NOISE_SD = 0.05


def make_face_population(
    n_subjects: int,
    images_per_subject: int,
    *,
    rng: int | np.random.Generator,
    shape: tuple[int, int] = STANDARD_SHAPE,
    nuisance: float = 1.0,
    texture_slope: float | None = TEXTURE_SLOPE,
    texture_amplitude: float = TEXTURE_AMPLITUDE,
) -> FacePopulation:
    """Draw a seeded synthetic face population.

    Parameters
    ----------
    n_subjects : int
        Number of subjects, 2 to :data:`amdo_lab.common.MAX_SAMPLES` (1,000,000) (paper: 256).
    images_per_subject : int
        Images per subject, 2 to 1,000,000 (paper: 4).
    rng : int or numpy.random.Generator
        Seed or generator (via :func:`amdo_lab.common.make_rng`).
    shape : tuple of int, default STANDARD_SHAPE
        Image size (rows, cols) in pixels, each at least 8.
    nuisance : float, default 1.0
        Global scale of the per-image variation, in [0, 100]; the calibration knob that sets the
        overall rank-1 rate (the chapter's experiment calibrates it to about 76 %).
    texture_slope : float or None, default TEXTURE_SLOPE (2.8)
        A number s in (0, 20] adds a Gaussian random texture with power spectrum f^-s at every
        frequency: one per subject (mostly left-right symmetric) plus a weaker one per image. None
        leaves the 6 x 6 low-frequency cosine texture alone, whose faces' power spectrum falls about
        as f^-4.5, far steeper than real faces' (scikit-image's ``lfw_subset``: about f^-2.3).
    texture_amplitude : float, default TEXTURE_AMPLITUDE (1.5)
        Standard deviation of that subject texture, in [0, 1e6] (the per-image one is half of it, times
        the image's nuisance scale); used only when ``texture_slope`` is given.

    Returns
    -------
    FacePopulation
        ``n_subjects * images_per_subject`` raw images with their labels and difficulties.

    References
    ----------
    Givens, Beveridge, Draper & Bolme (2004), "Using a Generalized Linear Mixed Model to Study the
    Configuration Space of a PCA+LDA Human Face Recognition Algorithm", AMDO 2004, LNCS 3179,
    pp. 1-11, Sec. 2 (the FERET images this population stands in for).

    Examples
    --------
    >>> from amdo_lab.face_glmm import make_face_population
    >>> population = make_face_population(3, 4, rng=0, shape=(16, 14))
    >>> population.images.shape
    (12, 16, 14)
    >>> population.labels.tolist()
    [0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2]
    """
    n_subjects = check_positive_int(n_subjects, "n_subjects", minimum=2, maximum=MAX_SAMPLES)
    images_per_subject = check_positive_int(images_per_subject, "images_per_subject", minimum=2, maximum=MAX_SAMPLES)
    # upper ends: beyond them the images overflow to inf or NaN (see the docstring's ranges)
    nuisance = check_in_range(nuisance, "nuisance", 0.0, 100.0, closed="both")
    check_image_shape(shape, minimum=8)
    gen = make_rng(rng, "rng")
    rows, cols = int(shape[0]), int(shape[1])
    n_img = n_subjects * images_per_subject
    labels = np.repeat(np.arange(n_subjects), images_per_subject)

    # Identity: geometry and texture (normalised coordinates, face centred at 0).
    eye_dx = 0.36 + 0.04 * gen.standard_normal(n_subjects)
    eye_y = -0.25 + 0.04 * gen.standard_normal(n_subjects)
    eye_size = 0.09 + 0.015 * gen.standard_normal(n_subjects)
    nose_len = 0.18 + 0.04 * gen.standard_normal(n_subjects)
    mouth_y = 0.42 + 0.04 * gen.standard_normal(n_subjects)
    mouth_w = 0.24 + 0.04 * gen.standard_normal(n_subjects)
    face_w = 0.80 + 0.05 * gen.standard_normal(n_subjects)
    tex = gen.standard_normal((n_subjects, _N_TEXTURE, _N_TEXTURE)) / (
        1.0 + np.add.outer(np.arange(_N_TEXTURE), np.arange(_N_TEXTURE))
    )
    # Mostly symmetric: odd-in-x cosine terms (sin-like after the shift below) damped.
    symmetric = 0.8
    difficulty = np.exp(DIFFICULTY_SPREAD * gen.standard_normal(n_subjects))

    # Nuisance per image, scaled by the subject's difficulty.
    scale = nuisance * difficulty[labels]
    shift = 0.03 * scale[:, None] * gen.standard_normal((n_img, 2))
    illum = 0.35 * scale[:, None] * gen.standard_normal((n_img, 2))
    smile = 0.35 * scale * gen.standard_normal(n_img)
    blink = 0.25 * scale * gen.standard_normal(n_img)
    tex_jitter = 0.25 * scale[:, None, None] * gen.standard_normal((n_img, _N_TEXTURE, _N_TEXTURE)) / (
        1.0 + np.add.outer(np.arange(_N_TEXTURE), np.arange(_N_TEXTURE))
    ) ** 1.5

    ys = np.linspace(-1.0, 1.0, rows)
    xs = np.linspace(-1.0, 1.0, cols)
    y = ys[None, :, None] - shift[:, 1, None, None]
    x = xs[None, None, :] - shift[:, 0, None, None]
    s = labels
    col = lambda a: a[:, None, None]  # noqa: E731  (broadcast per-image scalars)

    face = 1.0 / (1.0 + np.exp(((x / col(face_w[s])) ** 2 + (y / 0.95) ** 2 - 1.0) / 0.06))
    eye_open = col(eye_size[s] * np.exp(-0.3 * blink))
    eyes = _blob(x, y, -col(eye_dx[s]), col(eye_y[s]), col(eye_size[s]) * 1.4, eye_open) + _blob(
        x, y, col(eye_dx[s]), col(eye_y[s]), col(eye_size[s]) * 1.4, eye_open
    )
    nose = _blob(x, y, 0.0, col(eye_y[s] + nose_len[s]), 0.06, col(nose_len[s]) * 0.6)
    mouth = _blob(x, y, 0.0, col(mouth_y[s]), col(mouth_w[s] * (1 + 0.3 * smile)), 0.05)
    # Low-frequency identity texture on cosine basis; symmetric part uses |x|.
    coeff = tex[s] + tex_jitter
    kx = np.arange(_N_TEXTURE) * np.pi / 2
    basis_y = np.cos(kx[None, :, None] * (y[:, :, 0:1].transpose(0, 2, 1) + 1.0))  # (n, k, rows)
    xs_sym = symmetric * np.abs(x[:, 0, :]) + (1 - symmetric) * x[:, 0, :]
    basis_x = np.cos(kx[None, :, None] * (xs_sym[:, None, :] + 1.0))  # (n, k, cols)
    texture = np.einsum("nkr,nkl,nlc->nrc", basis_y, coeff, basis_x)
    illumination = illum[:, 0, None, None] * x + illum[:, 1, None, None] * y
    images = face * (1.0 + 0.5 * texture + illumination) - 0.8 * eyes - 0.3 * nose - 0.6 * mouth
    images = images + NOISE_SD * gen.standard_normal(images.shape)
    if texture_slope is not None:  # drawn last, so every other draw is the same without it
        texture_slope = check_in_range(texture_slope, "texture_slope", 0.0, 20.0, closed="right")
        texture_amplitude = check_in_range(texture_amplitude, "texture_amplitude", 0.0, 1e6, closed="both")
        identity = _power_law_field(gen, n_subjects, (rows, cols), texture_slope)
        identity = symmetric * (identity + identity[:, :, ::-1]) / 2 + (1 - symmetric) * identity
        per_image = _power_law_field(gen, n_img, (rows, cols), texture_slope)
        images = images + face * texture_amplitude * (identity[labels] + 0.5 * col(scale) * per_image)
    return FacePopulation(images=images, labels=labels, difficulty=difficulty,
                          images_per_subject=images_per_subject)


def _power_law_field(gen: np.random.Generator, n: int, shape: tuple[int, int], slope: float) -> np.ndarray:
    """``n`` Gaussian random images of unit standard deviation with power spectrum ~ f^-slope.

    White noise filtered in the Fourier domain by amplitude (f^2 + f_0^2)^(-slope/4), with f_0 one
    cycle per image so that the mean level stays finite.
    """
    rows, cols = shape
    fy, fx = np.fft.fftfreq(rows)[:, None], np.fft.fftfreq(cols)[None, :]
    amplitude = (fy**2 + fx**2 + (1.0 / max(rows, cols)) ** 2) ** (-slope / 4)
    field = np.fft.ifft2(np.fft.fft2(gen.standard_normal((n, rows, cols))) * amplitude).real
    return field / field.std(axis=(1, 2), keepdims=True)


def _elliptical_mask(shape: tuple[int, int]) -> np.ndarray:
    """Boolean ``(rows, cols)`` mask, True inside the ellipse whose axes are the frame's height and width
    (Sec. 2 step 3), for the shape of a checked image stack."""
    rows, cols = shape
    yy = (np.arange(rows) - (rows - 1) / 2) / (rows / 2)
    xx = (np.arange(cols) - (cols - 1) / 2) / (cols / 2)
    return (yy[:, None] ** 2 + xx[None, :] ** 2) <= 1.0


def downsample_by_two(images: np.ndarray) -> np.ndarray:
    """2 x 2 block mean: a quarter of the pixels (the paper's 65 x 75 from 130 x 150).

    Parameters
    ----------
    images : array_like, shape (n, rows, cols)
        Finite images with even ``rows`` and ``cols``.

    Returns
    -------
    ndarray, shape (n, rows // 2, cols // 2)
        Each pixel the mean of a 2 x 2 block.

    References
    ----------
    Givens et al. (2004), AMDO, LNCS 3179, Sec. 4 (the image-size factor S).
    """
    images = as_finite_array(images, "images", ndim=3)
    n, rows, cols = images.shape
    if rows % 2 or cols % 2:
        raise ValueError(f"images must have even rows and cols, got {rows} x {cols}")
    # a quarter of each pixel, then the sum: the mean of 2 x 2 blocks without overflow near the float maximum
    return (0.25 * images.reshape(n, rows // 2, 2, cols // 2, 2)).sum(axis=(2, 4))


def preprocess_images(images: np.ndarray) -> np.ndarray:
    """Sec. 2 steps 3-5: elliptical mask, histogram equalisation, zero mean and unit variance.

    Histogram equalisation of continuous grey values is the rank transform of the masked pixels to a
    uniform distribution; pixels outside the mask are set to 0.

    Parameters
    ----------
    images : array_like, shape (n, rows, cols)
        Finite raw images with at least 2 pixels inside the elliptical mask.

    Returns
    -------
    ndarray, shape (n, rows, cols)
        Each image's masked pixels have mean 0 and standard deviation 1; the background is 0.

    References
    ----------
    Givens et al. (2004), AMDO, LNCS 3179, Sec. 2 (image pre-processing, steps 3-5).
    """
    images = as_finite_array(images, "images", ndim=3)
    mask = _elliptical_mask(images.shape[1:])
    check_positive_int(int(mask.sum()), "the pixels of images inside the elliptical mask", minimum=2)  # spread of one: 0
    inside = images[:, mask]
    ranks = np.argsort(np.argsort(inside, axis=1), axis=1).astype(float)
    equalised = (ranks + 0.5) / inside.shape[1]
    equalised = (equalised - equalised.mean(axis=1, keepdims=True)) / equalised.std(axis=1, keepdims=True)
    out = np.zeros_like(images)
    out[:, mask] = equalised
    return out
