"""Controlled experiment: when does a mixture of PDMs per class beat a single PDM per class?

The separation between each class's two articulation modes is scaled by ``mode_separation``
(``make_pose_dataset``); at every level and seed a fresh training and test set are drawn and
the same recogniser is trained with two polar-PDM components per class (the paper's mixture) and
with one (a single PDM per class); a single Cartesian PDM per class is scored alongside.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from amdo_lab.common import check_choice, check_in_range, check_positive_int, make_rng, spawn_rngs
from amdo_lab.common.threads import one_blas_thread
from amdo_lab.pdm_mixtures.baselines import SingleCartesianPDMClassifier
from amdo_lab.pdm_mixtures.poses import MAX_MODE_SEPARATION, MAX_PER_CLASS, TABLE1_CLASSES, make_pose_dataset
from amdo_lab.pdm_mixtures.recogniser import ArticulatedShapeRecogniser, RecogniserSettings

__all__ = ["SEPARATION_MODELS", "SeparationTrial", "mode_separation_trial"]

SEPARATION_MODELS: tuple[str, ...] = ("mixture of PDMs", "single polar PDM", "single Cartesian PDM")


@dataclass(frozen=True)
class SeparationTrial:
    """The outcome of one seeded draw at one mode separation.

    Parameters
    ----------
    separation : float
        The mode separation factor ``s`` (non-negative) the data were drawn with.
    rng : int or numpy.random.Generator
        The ``rng`` given to :func:`mode_separation_trial`.
    correct : dict of str to numpy.ndarray
        Each name in ``SEPARATION_MODELS`` to a boolean array ``(n_test * len(classes),)`` saying
        which test shapes it recognised.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 4 (mixtures of PDMs).
    """

    separation: float
    rng: int | np.random.Generator
    correct: dict[str, np.ndarray]

    def rate(self, model: str) -> float:
        """Fraction of the test shapes that one model recognised.

        Parameters
        ----------
        model : str
            A name in ``SEPARATION_MODELS``.

        Returns
        -------
        float
            The recognition rate, in [0, 1].
        """
        check_choice(model, "model", self.correct)
        return float(np.mean(self.correct[model]))


def mode_separation_trial(separation: float, *, rng: int | np.random.Generator, n_train: int = 20, n_test: int = 10,
                          classes: tuple[str, ...] = TABLE1_CLASSES) -> SeparationTrial:
    """Train the mixture, the single polar PDM and the single Cartesian PDM on one seeded draw at
    one mode separation and score them on an independent test draw.

    Parameters
    ----------
    separation : float
        Factor in [0, 100] on the distance between each class's articulation modes (0: one mode,
        1: the chapter's default data).
    rng : int or numpy.random.Generator
        Seed or generator of the training and test streams (``make_rng(rng).spawn(2)``; keyword-only,
        no default). The recognisers' k-means++ starts use seed 0, as the chapter's recogniser does.
    n_train, n_test : int
        Training (at least 6) and test shapes per class, at most ``MAX_PER_CLASS``.
    classes : tuple of str
        Pose classes (the six of Table 1 by default).

    Returns
    -------
    SeparationTrial
        Which test shapes each of the three models recognised.

    References
    ----------
    Al-Shaher & Hancock, AMDO 2004, Sec. 4: mixtures of PDMs for shape variation one covariance
    matrix cannot capture.
    """
    separation = check_in_range(separation, "separation", 0, MAX_MODE_SEPARATION, closed="both")
    n_train = check_positive_int(n_train, "n_train", minimum=6, maximum=MAX_PER_CLASS)
    n_test = check_positive_int(n_test, "n_test", maximum=MAX_PER_CLASS)
    train_rng, test_rng = spawn_rngs(make_rng(rng, "rng"), 2)
    train = make_pose_dataset(classes, n_train, rng=train_rng, mode_separation=separation)
    test = make_pose_dataset(classes, n_test, rng=test_rng, mode_separation=separation)
    models = (ArticulatedShapeRecogniser(RecogniserSettings(n_shape_components=2), rng=0),
              ArticulatedShapeRecogniser(RecogniserSettings(n_shape_components=1), rng=0),
              SingleCartesianPDMClassifier())
    with one_blas_thread():  # small matrices: BLAS threads only contend on a shared machine
        correct = {name: model.fit(train.shapes, train.labels).predict(test.shapes) == test.labels
                   for name, model in zip(SEPARATION_MODELS, models)}
    return SeparationTrial(separation, rng, correct)
