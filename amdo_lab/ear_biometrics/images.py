"""The inputs every step of chapter 4 starts from: grey-level images and boolean contour images."""

from __future__ import annotations

import numpy as np

from amdo_lab.common import as_bool_mask, as_finite_array, check_in_range, check_instance

MAX_GREY_LEVEL = 1e6
"""Largest grey level of an image: 8- and 16-bit images and float images fit with room to spare;
the squared window sums of eq. (2) and the HOG gradients stay exact and finite far beyond it."""

MIN_IMAGE_SIDE = 8
"""Smallest side of an image, pixels: below it no 3 x 3 window or HOG block fits with a margin."""


def as_grey_image(image: object, name: str = "image") -> np.ndarray:
    """Validate a 2-D grey-level image (uint8 or float) and return it as float64.

    Colour (3-D) images are rejected: convert them with ``cv2.cvtColor`` first (the folder loader
    does this for you).

    Parameters
    ----------
    image : array_like, shape (rows, cols)
        Grey levels: real, finite, in [0, :data:`MAX_GREY_LEVEL`] (0-255 for 8-bit images), at least
        8 x 8 pixels; booleans are refused.
    name : str
        The argument's name in error messages.

    Returns
    -------
    numpy.ndarray, shape (rows, cols), float64
        A float copy of ``image``.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 2: the grey-level input of the contour detector.
    """
    grey = as_finite_array(image, name, ndim=2, bounds=(0, MAX_GREY_LEVEL))
    check_in_range(min(grey.shape), f"{name} side", MIN_IMAGE_SIDE, np.inf, closed="left")
    return grey


def check_record(value: object, name: str, kind: type, source: str) -> object:
    """Check that ``value`` is a ``kind`` (a record of the chapter), naming ``name`` and where one comes from.

    Parameters
    ----------
    value : object
        The argument to check.
    name : str
        The argument's name in error messages.
    kind : type
        The class ``value`` must be an instance of.
    source : str
        The function that makes a ``kind``, for the message.

    Returns
    -------
    object
        ``value``, unchanged.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61 (the records V, F and the stored templates of Secs. 4-5).
    """
    article = "an" if kind.__name__[0] in "AEIOU" else "a"
    return check_instance(value, name, kind, what=f"{article} {kind.__name__} (from {source})")


def as_bool_image(value: object, name: str) -> np.ndarray:
    """Check a non-empty 2-D boolean image (contours, a skeleton).

    OpenCV's morphology and component labelling crash the interpreter on an image with zero rows,
    so empty images are refused here.

    Parameters
    ----------
    value : object
        The argument to check.
    name : str
        The argument's name in error messages.

    Returns
    -------
    numpy.ndarray, shape (rows, cols), bool
        The image as an array.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 2 (the binary contour image) and Sec. 4 (its thinned form).
    """
    array = np.asarray(value)
    if array.dtype != bool or array.ndim != 2:
        raise TypeError(f"{name} must be a 2-D boolean image, got dtype {array.dtype}, shape {array.shape}")
    return as_bool_mask(array, name)


def as_contour_image(contours: object, name: str = "contours") -> np.ndarray:
    """Validate a boolean 2-D contour image with at least one contour pixel.

    Parameters
    ----------
    contours : object
        The argument to check.
    name : str
        The argument's name in error messages.

    Returns
    -------
    numpy.ndarray, shape (rows, cols), bool
        The contour image.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 2 (the contour image of eq. 5 that eqs. 6-9 measure).
    """
    array = as_bool_image(contours, name)
    if not array.any():
        raise ValueError(f"{name} holds no contour pixels (blank or constant image?)")
    return array


def check_images(images: object, name: str = "images") -> None:
    """Refuse anything but a non-empty sequence of grey-level images (each as :func:`as_grey_image` accepts).

    Parameters
    ----------
    images : object
        The argument to check.
    name : str
        The argument's name in error messages (an image is named ``name[index]``).

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 6 (a database of grey-level ear images).
    """
    if isinstance(images, (str, bytes)) or not hasattr(images, "__len__") or len(images) == 0:
        raise ValueError(f"{name} must be a non-empty sequence of grey-level images, got {type(images).__name__}")
    for index, image in enumerate(images):
        as_grey_image(image, f"{name}[{index}]")
