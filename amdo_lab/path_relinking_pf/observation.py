"""The observation model and weighting function of Sec. 5.2: eqs. (5)-(7).

A frame is measured once (:func:`measure`: the silhouette B^M by background subtraction, the smoothed
Canny edges E^M); a particle is weighed by rendering its pose (B^P, E^P) and counting the differences.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from amdo_lab.common import as_finite_array
from amdo_lab.path_relinking_pf.body import BodyModel, _edge_map, _fixed_point

__all__ = ["PAPER_ALPHA", "Measurement", "ObservationModel", "check_frame_pair", "check_measurement", "measure"]

#: Our eq. (7) constant alpha, per pixel of cost (the paper calls it experimental and gives no value).
PAPER_ALPHA = 0.01
#: Largest alpha: alpha C stays below exp's range for any image of at most 4,096 x 4,096 x 2 pixels.
MAX_ALPHA = 1e-2 * 2**10


@dataclass(frozen=True)
class Measurement:
    """What one frame offers the weighting function (Fig. 4 (b)).

    Parameters
    ----------
    B : numpy.ndarray
        ``(rows, cols)`` bool silhouette B^M (background subtraction).
    E : numpy.ndarray
        ``(rows, cols)`` float edge map E^M in [0, 1]: Canny edges smoothed by a Gaussian, 1 on an edge.

    References
    ----------
    Pantrigo et al., AMDO 2004, Sec. 5.2 and Fig. 4 (b).
    """

    B: np.ndarray
    E: np.ndarray


def check_measurement(measurement: object, name: str = "measurement") -> Measurement:
    """Return ``measurement`` after checking its fields' documented rules, or raise naming the field.

    ``B`` a 2-D bool silhouette; ``E`` a finite float map of B's shape with values in [0, 1]. A
    measurement edited with ``dataclasses.replace`` is checked here, where the observation model
    receives it.

    Parameters
    ----------
    measurement : Measurement
        The measurement of one frame.
    name : str
        The caller's argument, for the messages.

    Returns
    -------
    Measurement
        ``measurement``.
    """
    if not isinstance(measurement, Measurement):
        raise TypeError(f"{name} must be a Measurement, got {type(measurement).__name__}")
    B = measurement.B
    if not isinstance(B, np.ndarray) or B.dtype != np.bool_ or B.ndim != 2 or min(B.shape) < 1:
        raise TypeError(f"{name}.B must be a 2-D bool silhouette, got {type(B).__name__} "
                        f"{getattr(B, 'dtype', '')} {getattr(B, 'shape', '')}".rstrip())
    as_finite_array(measurement.E, f"{name}.E", shape=B.shape, bounds=(0.0, 1.0))
    return measurement


def check_frame_pair(frame: object, background: object) -> tuple[np.ndarray, np.ndarray]:
    """Return a grey frame and its background as uint8 images of one shape, or raise naming the culprit.

    Parameters
    ----------
    frame, background : numpy.ndarray
        ``(rows, cols)`` uint8 images, each side from 3 to 4,096 pixels.

    Returns
    -------
    tuple of numpy.ndarray
        The two images.
    """
    for value, name in ((frame, "frame"), (background, "background")):
        if not isinstance(value, np.ndarray) or value.dtype != np.uint8 or value.ndim != 2:
            raise ValueError(f"{name} must be a 2-D uint8 image")
        if min(value.shape) < 3 or max(value.shape) > 4096:
            raise ValueError(f"{name} must have sides of 3 to 4,096 pixels, got {value.shape}")
    if frame.shape != background.shape:
        raise ValueError(f"frame and background must have one shape, got {frame.shape} and {background.shape}")
    return frame, background


def measure(frame: np.ndarray, background: np.ndarray, *, threshold: float = 25.0,
            canny: tuple[float, float] = (40.0, 120.0), sigma: float = 1.5) -> Measurement:
    """Measure a frame: B^M by background subtraction, E^M by Canny edges smoothed with a Gaussian.

    Parameters
    ----------
    frame, background : numpy.ndarray
        ``(rows, cols)`` uint8 grey images of one shape (the background is known, Sec. 6).
    threshold : float
        Grey-level difference above which a pixel is foreground, in (0, 255].
    canny : tuple of float
        Canny's low and high thresholds, each in (0, 1,000].
    sigma : float
        Standard deviation of the smoothing Gaussian, pixels, in (0, 20].

    Returns
    -------
    Measurement
        ``B`` (a 3 x 3 median removes isolated noise pixels) and ``E``, scaled so a straight edge reads 1.

    References
    ----------
    Pantrigo et al., AMDO 2004, Sec. 5.2 and Fig. 4 (b).

    Examples
    --------
    >>> background = np.zeros((20, 20), np.uint8)
    >>> frame = background.copy(); frame[5:15, 5:15] = 200
    >>> int(measure(frame, background).B.sum())  # the 10 x 10 square, its corners rounded by the median
    96
    """
    frame, background = check_frame_pair(frame, background)
    threshold = float(as_finite_array(threshold, "threshold", shape=(), bounds=(0.0, 255.0), closed="right"))
    canny = as_finite_array(canny, "canny", shape=(2,), bounds=(0.0, 1000.0), closed="right")
    sigma = float(as_finite_array(sigma, "sigma", shape=(), bounds=(0.0, 20.0), closed="right"))
    difference = np.abs(frame.astype(np.int16) - background.astype(np.int16))
    silhouette = cv2.medianBlur((difference > threshold).astype(np.uint8), 3)
    masked = np.where(silhouette > 0, frame, 0).astype(np.uint8)  # the clutter's edges are subtracted away
    edges = (cv2.Canny(masked, float(canny[0]), float(canny[1])) > 0).astype(np.float64)
    smoothed = cv2.GaussianBlur(edges, (0, 0), sigma, borderType=cv2.BORDER_CONSTANT)
    line_peak = 1.0 / (sigma * np.sqrt(2 * np.pi))  # the peak of a smoothed straight one-pixel edge
    return Measurement(B=silhouette > 0, E=np.minimum(smoothed / line_peak, 1.0))


#: The 4-neighbourhood, for the morphological gradient that finds E^P's label changes.
_CROSS = cv2.getStructuringElement(cv2.MORPH_CROSS, (3, 3))


class ObservationModel:
    """The weighting function of one frame: costs C_E + C_B (eqs. 5-6) and weights exp(-alpha C) (eq. 7).

    Every pose passed to :meth:`cost` or :meth:`cost_reference` counts as one evaluation of the
    weighting function (Fig. 2's asterisk), in ``n_evaluations``.

    Parameters
    ----------
    measurement : Measurement
        The frame's B^M and E^M.
    model : BodyModel
        The body model that renders a pose.
    alpha : float
        Eq. (7)'s constant, per pixel of cost, in (0, 10.24].

    Attributes
    ----------
    n_evaluations : int
        Poses weighed so far.

    References
    ----------
    Pantrigo et al., AMDO 2004, Sec. 5.2, eqs. (5)-(7).

    Examples
    --------
    >>> from amdo_lab.path_relinking_pf import make_upper_body_sequence
    >>> seq = make_upper_body_sequence(rng=0, n_frames=2)
    >>> obs = ObservationModel(measure(seq.frames[0], seq.background), seq.model)
    >>> bool(obs.cost(seq.truth[:1])[0] < obs.cost(seq.truth[:1] + 5.0)[0])
    True
    """

    def __init__(self, measurement: Measurement, model: BodyModel, *, alpha: float = PAPER_ALPHA) -> None:
        check_measurement(measurement)
        if not isinstance(model, BodyModel):
            raise TypeError(f"model must be a BodyModel, got {type(model).__name__}")
        self.alpha = float(as_finite_array(alpha, "alpha", shape=(), bounds=(0.0, MAX_ALPHA), closed="right"))
        self.measurement, self.model = measurement, model
        self.shape = measurement.B.shape
        B, E = measurement.B.astype(np.float64), measurement.E
        # For binary P and M in [0, 1]: sum_j |M_j - P_j| = sum_j M_j + sum_{j in P} (1 - 2 M_j).
        self._constant = float(B.sum() + E.sum())
        self._blob_gain, self._edge_gain = 1.0 - 2.0 * B, 1.0 - 2.0 * E
        self._labels = np.zeros(self.shape, np.uint8)
        self.n_evaluations = 0

    def cost_reference(self, poses: np.ndarray) -> np.ndarray:
        """C_E + C_B of each pose, eqs. (5)-(6) summed over every pixel: the readable path.

        Parameters
        ----------
        poses : numpy.ndarray
            ``(n_pose,)`` or ``(N, n_pose)`` poses.

        Returns
        -------
        numpy.ndarray
            ``(N,)`` costs, pixels.

        References
        ----------
        Pantrigo et al., AMDO 2004, eqs. (5) and (6) (E^B and B^B read as the particle's E^P and B^P).
        """
        poses = np.atleast_2d(self.model.check_poses(poses))
        costs = np.empty(len(poses))
        for i, pose in enumerate(poses):
            labels = np.zeros(self.shape, np.uint8)
            self.model._render_into(labels, self.model._polygons(pose))
            B_P, E_P = labels > 0, _edge_map(labels)
            C_E = np.abs(self.measurement.E - E_P).sum()  # eq. (5): sum_j |E^M_j - E^P_j|
            C_B = np.abs(self.measurement.B.astype(float) - B_P).sum()  # eq. (6): sum_j |B^M_j - B^P_j|
            costs[i] = C_E + C_B
        self.n_evaluations += len(poses)
        return costs

    def cost(self, poses: np.ndarray) -> np.ndarray:
        """C_E + C_B of each pose, reading only the pixels the model covers (fast, equal to the reference).

        Parameters
        ----------
        poses : numpy.ndarray
            ``(n_pose,)`` or ``(N, n_pose)`` poses.

        Returns
        -------
        numpy.ndarray
            ``(N,)`` costs, pixels (equal to :meth:`cost_reference` to round-off).

        References
        ----------
        Pantrigo et al., AMDO 2004, eqs. (5) and (6).
        """
        return self._cost(np.atleast_2d(self.model.check_poses(poses)))

    def _cost(self, poses: np.ndarray) -> np.ndarray:
        """Check-free batched cost: kinematics for all poses at once, then one small crop per pose."""
        polygons = self.model._polygons(poses)
        corners = np.concatenate(polygons, axis=-2)  # (N, all vertices, 2)
        low = np.floor(corners.min(axis=1)).astype(int) - 2
        high = np.ceil(corners.max(axis=1)).astype(int) + 3
        rows, cols = self.shape
        costs = np.full(len(poses), self._constant)
        labels, fixed = self._labels, _fixed_point(polygons)  # rounded for the whole batch at once
        for i in range(len(poses)):
            c0, r0 = max(low[i, 0], 0), max(low[i, 1], 0)
            c1, r1 = min(high[i, 0], cols), min(high[i, 1], rows)
            if c1 <= c0 or r1 <= r0:  # the whole model is off the image: nothing drawn
                continue
            labels[r0:r1, c0:c1] = 0
            self.model._fill(labels, [points[i] for points in fixed])
            crop = labels[r0:r1, c0:c1]  # a background margin of 2 px keeps every label change inside
            # _edge_map(crop) by OpenCV: a label differs from a 4-neighbour where their max and min differ
            inside, edges = crop > 0, cv2.morphologyEx(crop, cv2.MORPH_GRADIENT, _CROSS) > 0
            costs[i] += self._blob_gain[r0:r1, c0:c1][inside].sum() + self._edge_gain[r0:r1, c0:c1][edges].sum()
        self.n_evaluations += len(poses)
        return costs

    def log_weights(self, costs: np.ndarray) -> np.ndarray:
        """Eq. (7) in the log domain: ``log pi = -alpha (C_E + C_B)``.

        Parameters
        ----------
        costs : numpy.ndarray
            ``(N,)`` costs from :meth:`cost`, pixels, each in [0, 2 rows cols].

        Returns
        -------
        numpy.ndarray
            ``(N,)`` log-weights (normalise them with :func:`amdo_lab.common.normalised_weights`).

        References
        ----------
        Pantrigo et al., AMDO 2004, eq. (7).
        """
        costs = as_finite_array(costs, "costs", ndim=1, bounds=(0.0, 2.0 * self.shape[0] * self.shape[1]))
        return -self.alpha * costs  # eq. (7): pi = exp(-alpha (C_E + C_B))

