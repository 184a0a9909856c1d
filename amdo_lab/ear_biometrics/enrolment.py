"""Enrolment shared by the matchers: subject ids, and ``fit`` as one ``enroll`` per image."""

from __future__ import annotations

from abc import ABC, abstractmethod

import numpy as np

from amdo_lab.common import check_in_range
from amdo_lab.ear_biometrics.images import check_images

MAX_NUMERIC_ID = 2.0**53
"""Largest magnitude of a numeric subject id: every integer up to it is exact in float64, so two
different ids never compare equal after a conversion to float."""


def check_subject_id(value: object, name: str) -> object:
    """Check one subject id: a str or a real number within +-2**53; None (rejection), booleans and NaN are refused.

    Parameters
    ----------
    value : object
        The id to check.
    name : str
        The argument's name in error messages.

    Returns
    -------
    object
        ``value``, unchanged.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 5, step 5 (a rejection names no subject).
    """
    if not isinstance(value, str):  # None (a rejection), a bool or NaN are refused here
        check_in_range(value, name, -MAX_NUMERIC_ID, MAX_NUMERIC_ID, closed="both")
    return value


def check_subject_ids(values: object, name: str, *, size: int | None = None, per: str = "item") -> np.ndarray:
    """Check a 1-D sequence of subject ids (each as in :func:`check_subject_id`).

    Parameters
    ----------
    values : object
        The ids to check.
    name : str
        The argument's name in error messages (an element is named ``name[index]``).
    size : int or None
        The number of ids required (one per ``per``), or None for any number.
    per : str
        What each id belongs to, for the error message ("image", "score", ...).

    Returns
    -------
    numpy.ndarray, shape (n,)
        The ids as an array.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 6 (two images per subject).
    """
    ids = np.asarray(values)
    if ids.ndim != 1 or (size is not None and len(ids) != size):
        raise ValueError(f"{name} must be a 1-D sequence giving one subject per {per}, got shape {ids.shape}")
    for index, value in enumerate(ids.tolist()):
        check_subject_id(value, f"{name}[{index}]")
    return ids


class Enrolment(ABC):
    """What every matcher of the chapter shares: :meth:`fit` is one :meth:`enroll` per image.

    A subclass defines ``enroll(subject_id, image)`` and ``_forget()`` (drop every enrolled
    template); ``fit`` then follows scikit-learn's contract (it forgets earlier enrolments and
    returns ``self``) in one place for all of them.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 5 (the stored references F_ref and V_ref).
    """

    def fit(self, images: object, subject_ids: object) -> Enrolment:
        """Enrol one reference image per subject id, forgetting any earlier enrolment.

        Parameters
        ----------
        images : sequence of array_like
            Grey-level images (8-bit or float), each holding an ear.
        subject_ids : sequence
            The subject of each image (str or real ids within +-2**53), as many as ``images``.

        Returns
        -------
        Enrolment
            ``self``, with its learned attributes (ending in ``_``) set.
        """
        check_images(images)
        check_subject_ids(subject_ids, "subject_ids", size=len(images), per="image")
        self._forget()
        for index, (subject_id, image) in enumerate(zip(subject_ids, images)):
            try:
                self.enroll(subject_id, image)
            except ValueError as error:  # name the image at fault (its features could not be extracted)
                raise ValueError(f"images[{index}]: {error}") from error
        return self

    @abstractmethod
    def _forget(self) -> None:
        """Drop every enrolled template."""

    @abstractmethod
    def enroll(self, subject_id: object, image: object) -> object:
        """Add one reference image of ``subject_id`` (defined by each matcher).

        Parameters
        ----------
        subject_id : object
            The subject's id: a str or a real number within +-2**53.
        image : array_like, shape (rows, cols)
            Grey levels holding the subject's ear.

        Returns
        -------
        object
            What the matcher stores for the image.
        """
