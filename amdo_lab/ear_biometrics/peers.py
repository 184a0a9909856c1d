"""Two nearest-neighbour peers of Choraś's method (AMDO 2004): HOG descriptors and LBP histograms."""

from __future__ import annotations

import cv2
import numpy as np
from skimage.feature import hog, local_binary_pattern

from amdo_lab.common import check_fitted, check_in_range, check_positive_int
from amdo_lab.ear_biometrics.enrolment import Enrolment, check_subject_id
from amdo_lab.ear_biometrics.images import as_grey_image

LBP_POINTS = 8
"""Neighbours :class:`LbpNearestNeighbour` samples on its circle (``LBP_POINTS + 2`` uniform codes)."""


class HogNearestNeighbour(Enrolment):
    """Baseline: HOG descriptors (9 orientations, square cells, 2x2 blocks) and 1-nearest neighbour (L2).

    Parameters
    ----------
    pixels_per_cell : int
        Side of a HOG cell, pixels, from 2 to half the image's shorter side (checked when a
        descriptor is computed: a 2 x 2 block of cells must fit the image).

    Attributes
    ----------
    subject_ids_ : list or None
        Subject of each enrolled image (None before :meth:`fit` or :meth:`enroll`).
    descriptors_ : numpy.ndarray or None
        The enrolled HOG descriptors, shape (n_enrolled, n_features).
    image_shape_ : tuple or None
        Shape of the enrolled images (queries must have it).

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 6 (the task; this baseline is ours).
    N. Dalal, B. Triggs, "Histograms of Oriented Gradients for Human Detection", CVPR 2005.
    """

    def __init__(self, pixels_per_cell: int = 16) -> None:
        self.pixels_per_cell = pixels_per_cell  # stored as given, checked where it is used (describe)
        self.subject_ids_: list | None = None  # learned: None until the first enrolment
        self.descriptors_: np.ndarray | None = None  # (n_enrolled, n_features)
        self.image_shape_: tuple | None = None

    def describe(self, image: object) -> np.ndarray:
        """The HOG descriptor of one image.

        Parameters
        ----------
        image : array_like, shape (rows, cols)
            Grey levels.

        Returns
        -------
        numpy.ndarray, shape (n_features,)
            The descriptor (its length depends on the image size).
        """
        grey = as_grey_image(image)
        side = check_positive_int(self.pixels_per_cell, "pixels_per_cell", minimum=2, maximum=min(grey.shape) // 2)
        cell = (side, side)
        return hog(grey, orientations=9, pixels_per_cell=cell, cells_per_block=(2, 2), feature_vector=True)

    def _check_size(self, image: object) -> None:
        """Descriptors are only comparable between images of one size (the HOG grid depends on it)."""
        if self.image_shape_ is not None and np.shape(image) != self.image_shape_:
            raise ValueError(f"image must have the enrolled images' shape {self.image_shape_}, got {np.shape(image)}")

    def enroll(self, subject_id: object, image: object) -> None:
        """Add one reference image of ``subject_id``.

        Parameters
        ----------
        subject_id : object
            The subject's id: a str or a real number within +-2**53 (not None nor a bool).
        image : array_like, shape (rows, cols)
            Grey levels, of the shape of the images enrolled before.
        """
        check_subject_id(subject_id, "subject_id")
        self._check_size(image)
        descriptor = self.describe(image)[None]
        if self.descriptors_ is None:
            self.subject_ids_, self.descriptors_ = [], np.zeros((0, descriptor.shape[1]))
        self.descriptors_ = np.vstack([self.descriptors_, descriptor])
        self.subject_ids_.append(subject_id)
        self.image_shape_ = np.shape(image)

    def _forget(self) -> None:
        """Drop every enrolled descriptor (before :meth:`fit` enrols afresh)."""
        self.subject_ids_, self.descriptors_, self.image_shape_ = None, None, None

    def distances(self, image: object) -> np.ndarray:
        """L2 distance from the query's HOG to every enrolled HOG (lower is better).

        Parameters
        ----------
        image : array_like, shape (rows, cols)
            Grey levels, of the enrolled images' shape.

        Returns
        -------
        numpy.ndarray, shape (n_enrolled,)
            The distances, in enrolment order.
        """
        check_fitted(self, "descriptors_")  # NotFittedError (a ValueError) before any enrolment
        self._check_size(image)
        return np.linalg.norm(self.descriptors_ - self.describe(image), axis=1)

    def identify(self, image: object) -> object:
        """The subject of the nearest enrolled descriptor.

        Parameters
        ----------
        image : array_like, shape (rows, cols)
            Grey levels, of the enrolled images' shape.

        Returns
        -------
        object
            The subject id of the nearest enrolled image.
        """
        return self.subject_ids_[int(np.argmin(self.distances(image)))]


class LbpNearestNeighbour(HogNearestNeighbour):
    """Baseline: histograms of uniform local binary patterns on a grid of cells, and 1-nearest neighbour (L2).

    The image is blurred (Gaussian, ``blur_sigma`` pixels) and rounded to 8 bits, each pixel coded by
    the uniform LBP of its :data:`LBP_POINTS` neighbours at ``radius`` pixels (``LBP_POINTS + 2`` codes), and
    the image cut into ``cells_per_side`` x ``cells_per_side`` cells; the descriptor is the
    concatenation of the cells' normalised code histograms. The defaults were chosen on a development
    database (seed 77, 60 easy subjects, in the canonical frame), not on the chapter's images: without
    the blur the codes follow the sensor noise.

    Parameters
    ----------
    cells_per_side : int
        Cells along each image side, from 1 to the image's shorter side (checked when a descriptor is
        computed, as every parameter: each cell must hold at least one pixel).
    radius : int
        Radius of the LBP neighbourhood, pixels, from 1 to half the image's shorter side.
    blur_sigma : float
        Standard deviation of the Gaussian blur before coding, pixels, from 0 (none) to the image's
        larger side.

    Attributes
    ----------
    subject_ids_, descriptors_, image_shape_
        As in :class:`HogNearestNeighbour`.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 6 (the task; this baseline is ours).
    T. Ojala, M. Pietikäinen, T. Mäenpää, "Multiresolution Gray-Scale and Rotation Invariant Texture
    Classification with Local Binary Patterns", IEEE TPAMI 24(7), 2002.
    """

    def __init__(self, cells_per_side: int = 8, radius: int = 1, blur_sigma: float = 3.0) -> None:
        super().__init__()
        self.cells_per_side = cells_per_side  # stored as given, checked where they are used (describe)
        self.radius = radius
        self.blur_sigma = blur_sigma

    def describe(self, image: object) -> np.ndarray:
        """The concatenated LBP histograms of one image.

        Parameters
        ----------
        image : array_like, shape (rows, cols)
            Grey levels.

        Returns
        -------
        numpy.ndarray, shape (cells_per_side**2 * (LBP_POINTS + 2),)
            The descriptor; each cell's histogram sums to 1.
        """
        grey = as_grey_image(image)
        cells = check_positive_int(self.cells_per_side, "cells_per_side", maximum=min(grey.shape))
        radius = check_positive_int(self.radius, "radius", maximum=min(grey.shape) // 2)
        sigma = check_in_range(self.blur_sigma, "blur_sigma", 0, max(grey.shape), closed="both")
        if sigma > 0:
            grey = cv2.GaussianBlur(grey, (0, 0), sigma)
        codes = local_binary_pattern(np.clip(np.round(grey), 0, 255).astype(np.uint8), LBP_POINTS, radius, "uniform")
        row_edges = np.linspace(0, grey.shape[0], cells + 1).astype(int)
        col_edges = np.linspace(0, grey.shape[1], cells + 1).astype(int)
        histograms = []
        for top, bottom in zip(row_edges[:-1], row_edges[1:]):
            for left, right in zip(col_edges[:-1], col_edges[1:]):
                counts = np.bincount(codes[top:bottom, left:right].astype(int).ravel(), minlength=LBP_POINTS + 2)
                histograms.append(counts / counts.sum())
        return np.concatenate(histograms)
