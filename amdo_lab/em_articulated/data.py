"""Seeded synthetic data: single registration problems and a tracking sequence (Sec. 5 style)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from amdo_lab.common import MAX_ITERATIONS, MAX_SAMPLES
from amdo_lab.common import (as_finite_array, check_bool, check_choice, check_in_range, check_positive,
                             check_positive_int, make_rng)

from amdo_lab.em_articulated.hand import MAX_LENGTH_MM, SIDEWAYS_DOFS, HandModel, TextureBinding, check_hand

__all__ = ["RegistrationProblem", "make_registration_problem", "perturb_pose",
           "make_tracking_sequence", "TrackingSequence", "joint_rmse_deg", "worst_joint_deg", "SkinTexture", "make_skin_texture",
           "random_pose", "DEFAULT_REPEATABILITY"]

_ARTICULATION = slice(6, 27)


def joint_rmse_deg(theta_est: np.ndarray, theta_true: np.ndarray) -> float:
    """RMSE over the 21 finger/thumb joint angles, in degrees.

    Parameters
    ----------
    theta_est : array_like, shape (27,)
        Estimated pose (mm for DOFs 0-2, radians for the others, each within ±1e6); only DOFs 6-26
        are compared.
    theta_true : array_like, shape (27,)
        True pose, same layout.

    Returns
    -------
    float
        sqrt(mean over the 21 joints of the squared angle error), degrees (≥ 0).

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591. The paper reports no joint-angle error
    (its Sec. 5 tracks real stereo data without ground truth); this measure is ours, over the 21
    finger and thumb joints (the palm's 6 DOF excluded).
    """
    return float(np.sqrt(np.mean(_joint_errors_deg(theta_est, theta_true) ** 2)))


def worst_joint_deg(theta_est: np.ndarray, theta_true: np.ndarray) -> float:
    """Largest error over the 21 finger/thumb joint angles, in degrees.

    A trial succeeds when it is below :data:`SUCCESS_DEG`.

    Parameters
    ----------
    theta_est : array_like, shape (27,)
        Estimated pose (mm for DOFs 0-2, radians for the others, each within ±1e6); only DOFs 6-26
        are compared.
    theta_true : array_like, shape (27,)
        True pose, same layout.

    Returns
    -------
    float
        max over the 21 joints of the absolute angle error, degrees (≥ 0).

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591. Our success criterion: the paper reports
    no joint-angle error and no success rate (its Sec. 5 tracks real stereo data without ground truth).
    """
    return float(np.max(np.abs(_joint_errors_deg(theta_est, theta_true))))


def _joint_errors_deg(theta_est: object, theta_true: object) -> np.ndarray:
    """The checked poses' errors on the 21 finger and thumb joint angles (DOFs 6-26), degrees."""
    theta_est = as_finite_array(theta_est, "theta_est", ndim=1, shape=(27,), max_abs=MAX_LENGTH_MM)
    theta_true = as_finite_array(theta_true, "theta_true", ndim=1, shape=(27,), max_abs=MAX_LENGTH_MM)
    return np.degrees(theta_est[_ARTICULATION] - theta_true[_ARTICULATION])


#: Poses whose digits overlap by more than this (mm) are physically impossible and are redrawn.
MIN_DIGIT_CLEARANCE_MM = -2.0
_MAX_DRAWS = 200
#: Sideways DOFs of the thumb, and the abduction DOFs of the index, middle, ring and little fingers.
_THUMB_SIDEWAYS, _FINGER_ABDUCTION = SIDEWAYS_DOFS[:2], SIDEWAYS_DOFS[2:]


def _first_valid(hand: HandModel, draw, what: str) -> np.ndarray:
    """Redraw until the digits do not interpenetrate (see :meth:`HandModel.digit_clearance`)."""
    for _ in range(_MAX_DRAWS):
        theta = draw()
        if hand.digit_clearance(theta) >= MIN_DIGIT_CLEARANCE_MM:
            return theta
    raise RuntimeError(f"no {what} without crossed fingers in {_MAX_DRAWS} draws")


def perturb_pose(hand: HandModel, theta: np.ndarray, joint_error_deg: float, *, rng: np.random.Generator | int,
                 palm_rotation_deg: float = 5.0, palm_translation_mm: float = 5.0) -> np.ndarray:
    """Offset each articulation DOF by ±``joint_error_deg`` (random signs), staying inside the limits.

    Where the offset would leave a joint's range its sign is flipped (then clipped as a last
    resort). Sign patterns that make two digits cross are redrawn: a start pose with the index
    lying inside the middle finger is not a pose a tracker could have produced.

    Parameters
    ----------
    hand : HandModel
        The hand whose joint limits and digit clearance constrain the draw.
    theta : array_like, shape (27,)
        Pose to perturb (mm for DOFs 0-2, radians for the others).
    joint_error_deg : float
        Offset of every finger/thumb joint, degrees (≥ 0); the four finger abductions share one sign.
    rng : int or numpy.random.Generator
        Seed (≥ 0) or generator of the random signs and palm offsets.
    palm_rotation_deg : float, default 5.0
        RMS of the palm's rotation offset over its three angles, degrees (≥ 0).
    palm_translation_mm : float, default 5.0
        RMS length of the palm's translation offset, mm, in [0, 1e6].

    Returns
    -------
    numpy.ndarray, shape (27,)
        The perturbed pose, inside ``hand.joint_limits()``.

    Raises
    ------
    RuntimeError
        When 200 draws all make two digits cross.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591, Sec. 5 (start poses of the
    synthetic experiments).
    """
    check_hand(hand)
    theta = hand.check_theta(theta, "theta")
    joint_error_deg = check_positive(joint_error_deg, "joint_error_deg", allow_zero=True)
    palm_rotation_deg = check_positive(palm_rotation_deg, "palm_rotation_deg", allow_zero=True)
    palm_translation_mm = check_in_range(palm_translation_mm, "palm_translation_mm", 0.0, MAX_LENGTH_MM, closed="both")
    rng = make_rng(rng, "rng")
    limits = hand.joint_limits()
    lo, hi = limits[_ARTICULATION, 0], limits[_ARTICULATION, 1]
    offset = np.radians(joint_error_deg)

    def draw() -> np.ndarray:
        out = np.array(theta, dtype=float)
        signs = rng.choice([-1.0, 1.0], size=21)
        # the four finger abductions share one sign: turning all fingers the same way keeps
        # them side by side; independent signs would cross neighbours in half of the draws
        signs[np.array(_FINGER_ABDUCTION) - 6] = signs[_FINGER_ABDUCTION[0] - 6]
        proposal = out[_ARTICULATION] + signs * offset
        flipped = np.where((proposal < lo) | (proposal > hi), out[_ARTICULATION] - signs * offset, proposal)
        out[_ARTICULATION] = np.clip(flipped, lo, hi)
        out[:3] += rng.normal(scale=palm_translation_mm / np.sqrt(3), size=3)
        out[3:6] += rng.normal(scale=np.radians(palm_rotation_deg) / np.sqrt(3), size=3)
        return np.clip(out, limits[:, 0], limits[:, 1])

    return _first_valid(hand, draw, "perturbed pose")


def random_pose(hand: HandModel, *, rng: np.random.Generator | int) -> np.ndarray:
    """A natural pose: rest pose, small spreads and moderate flexions, digits not crossing.

    Parameters
    ----------
    hand : HandModel
        The hand whose rest pose, joint limits and digit clearance shape the draw.
    rng : int or numpy.random.Generator
        Seed (≥ 0) or generator of the flexions and spreads.

    Returns
    -------
    numpy.ndarray, shape (27,)
        Pose with the palm at the origin: flexions of -0.1 to 0.6 rad added to the rest pose, the
        fingers fanned out together by up to 0.15 rad, inside ``hand.joint_limits()``.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591, Sec. 5 (synthetic poses).
    """
    check_hand(hand)
    rng = make_rng(rng, "rng")
    limits = hand.joint_limits()
    flexion = ~np.isin(np.arange(6, 27), SIDEWAYS_DOFS)

    def draw() -> np.ndarray:
        theta = hand.rest_pose()
        theta[6:] += np.where(flexion, rng.uniform(-0.1, 0.6, size=21), 0.0)
        theta[list(_THUMB_SIDEWAYS)] += rng.uniform(-0.2, 0.2, size=2)
        # fingers fan out together (index and little most), plus a little independent jitter
        fan = rng.uniform(0.0, 0.15) * np.array([-1.0, -1 / 3, 1 / 3, 1.0])
        theta[list(_FINGER_ABDUCTION)] += fan + rng.uniform(-0.03, 0.03, size=4)
        return np.clip(theta, limits[:, 0], limits[:, 1])

    return _first_valid(hand, draw, "random pose")


def _visible_points(hand: HandModel, points: np.ndarray, theta: np.ndarray, camera: np.ndarray) -> np.ndarray:
    """Back-face culling on checked input: True where the surface normal at a point faces ``camera``.

    ``points`` (M, 3) lie on or near the surface at pose ``theta``; the normals are those of the fused
    surface of eq. (2) (:meth:`HandModel.surface_normals`), so the generators see the hand from one side,
    as the stereo data of the paper's Sec. 5.
    """
    normals = hand._surface_normals(points, theta)
    return np.sum(normals * (camera - points), axis=1) > 0


#: Share of the skin's features a stereo detector finds again in a new view. Interest points
#: between nearby views are re-detected at roughly this rate (Schmid, Mohr & Bauckhage, IJCV 2000,
#: report 0.7-0.9 repeatability for Harris under small rotations and viewpoint changes).
DEFAULT_REPEATABILITY = 0.8


@dataclass(frozen=True)
class SkinTexture:
    """Features of the skin (the paper's texture): fixed surface points that move with the hand.

    Every observation of the hand sees a subset of the same features, which is what makes
    point-to-point matching (Sec. 3) meaningful: a data point is the same skin mark as some
    texture point.

    Parameters
    ----------
    rest_points : numpy.ndarray, shape (K, 3)
        The features at the rest pose, mm.
    binding : TextureBinding
        Attaches them to the kinematic chain, so that :meth:`positions` moves them by the bending
        model of eq. (3).

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591, Sec. 3 and eq. (3).
    """

    rest_points: np.ndarray
    binding: TextureBinding

    @property
    def n_features(self) -> int:
        """Number of skin features K."""
        return len(self.rest_points)

    def positions(self, hand: HandModel, theta: np.ndarray) -> np.ndarray:
        """Noise-free 3-D positions of every feature at pose ``theta`` (eq. 3).

        Parameters
        ----------
        hand : HandModel
            The hand the features were bound to.
        theta : array_like, shape (27,)
            Pose.

        Returns
        -------
        numpy.ndarray, shape (K, 3)
            Feature positions, mm.
        """
        return check_hand(hand).transform_texture(self.binding, hand.check_theta(theta))


def make_skin_texture(hand: HandModel, n_features: int, *, rng: np.random.Generator | int,
                      a: float = 2.0) -> SkinTexture:
    """``n_features`` skin features drawn uniformly on the fused surface at the rest pose.

    Parameters
    ----------
    hand : HandModel
        The hand to draw the features on.
    n_features : int
        Number of features K (≥ 1). At most :data:`amdo_lab.common.MAX_SAMPLES` (1,000,000).
    rng : int or numpy.random.Generator
        Seed (≥ 0) or generator of the feature positions.
    a : float, default 2.0
        Exponent of the bending weights of eq. (3) (in (0, :data:`MAX_BENDING_EXPONENT`]; 2 is the
        paper's value).

    Returns
    -------
    SkinTexture
        The features at the rest pose and their binding to the hand.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591, Sec. 3 (texture) and eq. (3).
    """
    check_hand(hand)
    rng = make_rng(rng, "rng")
    rest = hand.rest_pose()
    n_features = check_positive_int(n_features, "n_features", maximum=MAX_SAMPLES)
    points = hand.sample_surface(rest, n_features, rng=rng)
    return SkinTexture(points, hand.texture_binding(points, rest, a))


def _observe(positions: np.ndarray, candidates: np.ndarray, n: int, noise_mm: float,
             rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Detect ``n`` of the ``candidates`` features at random and add isotropic Gaussian noise."""
    chosen = rng.choice(candidates, size=min(n, len(candidates)), replace=False)
    points = positions[chosen]
    if noise_mm > 0:
        points = points + rng.normal(scale=noise_mm, size=points.shape)
    return points, chosen


@dataclass(frozen=True)
class RegistrationProblem:
    """One synthetic problem: model texture at ``theta_init``, data at ``theta_true``.

    Parameters
    ----------
    theta_true : numpy.ndarray, shape (27,)
        The pose the data were observed at.
    theta_init : numpy.ndarray, shape (27,)
        The start pose, where the model texture was observed.
    model_points : numpy.ndarray, shape (N, 3)
        The texture X_i, mm.
    data_points : numpy.ndarray, shape (M, 3)
        The data Y_j (skin points and outliers, shuffled), mm.
    is_outlier : numpy.ndarray of bool, shape (M,)
        True for the uniform outliers among the data.
    model_feature : numpy.ndarray of int, shape (N,)
        Skin feature each texture point observes (-1 with independent samples).
    data_feature : numpy.ndarray of int, shape (M,)
        Skin feature each data point observes (-1 for an outlier or with independent samples),
        so the true matches are known.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591, Sec. 3 (texture and data) and Sec. 5.
    """

    theta_true: np.ndarray
    theta_init: np.ndarray
    model_points: np.ndarray
    data_points: np.ndarray
    is_outlier: np.ndarray
    model_feature: np.ndarray
    data_feature: np.ndarray

    def true_matches(self) -> tuple[np.ndarray, np.ndarray]:
        """Index pairs (model i, data j) that observe the same skin feature.

        Returns
        -------
        model_index : numpy.ndarray of int, shape (P,)
            Rows of ``model_points``.
        data_index : numpy.ndarray of int, shape (P,)
            The rows of ``data_points`` they match (P = 0 without shared features).
        """
        data_of_feature = {f: j for j, f in enumerate(self.data_feature) if f >= 0}
        pairs = [(i, data_of_feature[f]) for i, f in enumerate(self.model_feature) if f in data_of_feature]
        pairs = np.array(pairs, dtype=int).reshape(-1, 2)
        return pairs[:, 0], pairs[:, 1]


_CAMERA = np.array([0.0, 40.0, 500.0])
#: Most outliers per inlier make_registration_problem draws (a bound on its memory, far above any
#: clutter the chapter studies).
_MAX_OUTLIER_RATIO = 1000.0


def make_registration_problem(hand: HandModel, *, rng: np.random.Generator | int, joint_error_deg: float = 20.0,
                              noise_mm: float = 2.0, outlier_ratio: float = 1.0, n_model: int = 500,
                              n_data: int = 500, occlusion: bool = False,
                              repeatability: float = DEFAULT_REPEATABILITY,
                              texture_noise_mm: float | None = None) -> RegistrationProblem:
    """Texture observed at the initial pose, data observed at the true pose, plus uniform outliers.

    The hand carries max(n_model, n_data) / repeatability skin features (the paper's texture;
    twice that with ``occlusion``, since about half face the camera). The model
    texture is ``n_model`` of them seen at ``theta_init`` (a previous frame's data, so it is
    noisy too), the data ``n_data`` of them seen at ``theta_true``, both with Gaussian noise of
    ``noise_mm`` per coordinate; on average ``repeatability``·n_data data points have a true match.
    ``repeatability=0`` draws model and data as independent samples of the surface (no feature
    seen twice: the textureless case where point matching has nothing to match). Outliers are
    uniform in the data's bounding box enlarged by 30 mm, ``outlier_ratio`` per inlier.
    ``occlusion`` keeps only features facing a camera 500 mm above the hand.
    ``texture_noise_mm`` sets the texture's noise apart from the data's (default: ``noise_mm``;
    0 reads "2 mm noise" as noise on the data only, with an exactly known texture).

    Parameters
    ----------
    hand : HandModel
        The hand to observe.
    rng : int or numpy.random.Generator
        Seed (≥ 0) or generator of the poses, features, noise and outliers.
    joint_error_deg : float, default 20.0
        Offset of every joint of the start pose from the true pose, degrees (≥ 0; :func:`perturb_pose`).
    noise_mm : float, default 2.0
        Standard deviation of the Gaussian noise per coordinate on the data, mm, in [0, 1e6].
    outlier_ratio : float, default 1.0
        Uniform outliers per inlier data point, in [0, 1000].
    n_model : int, default 500
        Texture points N (≥ 1). At most :data:`amdo_lab.common.MAX_SAMPLES` (1,000,000).
    n_data : int, default 500
        Skin points among the data (≥ 1), before the outliers.
        At most :data:`amdo_lab.common.MAX_SAMPLES` (1,000,000).
    occlusion : bool, default False
        Keep only features facing a camera 500 mm above the hand.
    repeatability : float, default DEFAULT_REPEATABILITY
        Share of the data with a true match, in [0, 1]; 0 draws independent samples.
    texture_noise_mm : float or None, default None
        Noise per coordinate on the texture, mm, in [0, 1e6]; None: ``noise_mm``.

    Returns
    -------
    RegistrationProblem
        Texture, data, both poses and the true matches.

    Examples
    --------
    >>> from amdo_lab.em_articulated import HandModel
    >>> problem = make_registration_problem(HandModel(), rng=1, n_model=300, n_data=300)
    >>> problem.model_points.shape, problem.data_points.shape, int(problem.is_outlier.sum())
    ((300, 3), (600, 3), 300)

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591, Sec. 5 (synthetic experiments).
    """
    check_hand(hand)
    rng = make_rng(rng, "rng")
    noise_mm = check_in_range(noise_mm, "noise_mm", 0.0, MAX_LENGTH_MM, closed="both")
    texture_noise_mm = noise_mm if texture_noise_mm is None else check_in_range(texture_noise_mm, "texture_noise_mm",
                                                                                 0.0, MAX_LENGTH_MM, closed="both")
    outlier_ratio = check_in_range(outlier_ratio, "outlier_ratio", 0.0, _MAX_OUTLIER_RATIO, closed="both")
    occlusion = check_bool(occlusion, "occlusion")
    n_model = check_positive_int(n_model, "n_model", maximum=MAX_SAMPLES)
    n_data = check_positive_int(n_data, "n_data", maximum=MAX_SAMPLES)
    repeatability = check_in_range(repeatability, "repeatability", 0.0, 1.0, closed="both")
    for _ in range(_MAX_DRAWS):
        theta_true = random_pose(hand, rng=rng)
        try:
            theta_init = perturb_pose(hand, theta_true, joint_error_deg, rng=rng)
            break
        except RuntimeError:  # a true pose with no valid start at this distance: draw another
            continue
    else:
        raise RuntimeError(f"no start pose {joint_error_deg} deg away without crossed fingers")
    scale = 2 if occlusion else 1  # about half of the features face the camera
    if repeatability == 0:
        at_init = hand.sample_surface(theta_init, scale * n_model, rng=rng)
        at_true = hand.sample_surface(theta_true, scale * n_data, rng=rng)
        n_skin = 0
    else:
        skin = make_skin_texture(hand, int(np.ceil(scale * max(n_model, n_data) / repeatability)), rng=rng)
        at_init, at_true = skin.positions(hand, theta_init), skin.positions(hand, theta_true)
        n_skin = skin.n_features
    seen_init, seen_true = np.arange(len(at_init)), np.arange(len(at_true))
    if occlusion:
        seen_init = seen_init[_visible_points(hand, at_init, theta_init, _CAMERA)]
        seen_true = seen_true[_visible_points(hand, at_true, theta_true, _CAMERA)]
    model_points, model_feature = _observe(at_init, seen_init, n_model, texture_noise_mm, rng)
    inliers, data_feature = _observe(at_true, seen_true, n_data, noise_mm, rng)
    if n_skin == 0:
        model_feature, data_feature = np.full(len(model_points), -1), np.full(len(inliers), -1)
    n_out = int(round(outlier_ratio * len(inliers)))
    lo, hi = inliers.min(axis=0) - 30, inliers.max(axis=0) + 30
    outliers = rng.uniform(lo, hi, size=(n_out, 3))
    data = np.concatenate([inliers, outliers])
    is_outlier = np.r_[np.zeros(len(inliers), bool), np.ones(n_out, bool)]
    feature = np.r_[data_feature, np.full(n_out, -1)]
    order = rng.permutation(len(data))
    return RegistrationProblem(theta_true, theta_init, model_points, data[order], is_outlier[order],
                               model_feature, feature[order])


@dataclass(frozen=True)
class TrackingSequence:
    """A synthetic tracking sequence: true poses and per-frame data clouds with outlier masks.

    Parameters
    ----------
    poses : numpy.ndarray, shape (F, 27)
        True pose of every frame.
    frames : list of numpy.ndarray
        Data of every frame, shape (M_f, 3), mm: skin points then clutter.
    is_outlier : list of numpy.ndarray of bool
        Per frame, shape (M_f,): True for clutter.
    fps : float
        Frame rate, frames per second.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591, Sec. 5 (Fig. 3).
    """

    poses: np.ndarray
    frames: list
    is_outlier: list
    fps: float


def make_tracking_sequence(hand: HandModel, *, rng: np.random.Generator | int, n_frames: int = 100,
                           fps: float = 20.0, n_features: int = 1500, noise_mm: float = 2.0,
                           n_clutter: int = 150, repeatability: float = DEFAULT_REPEATABILITY,
                           motion: str = "turn", camera: object = None) -> TrackingSequence:
    """A hand turning about an axis parallel to the image plane while bending its fingers (Fig. 3).

    ``motion="turn"`` (default) is that sequence; ``motion="bend"`` keeps the palm still and only
    bends and stretches the fingers, the paper's other two sequences, which it shows from two
    viewpoints: ``camera`` (3,) is the camera centre in mm (default 500 mm above the hand).

    The skin carries ``n_features`` features (:func:`make_skin_texture`); each frame a camera
    500 mm above the hand detects ``repeatability`` of those facing it (about 500-700 points),
    with ``noise_mm`` of noise. Clutter: points on an unmodelled forearm cylinder behind the wrist
    plus uniform background points, ``n_clutter`` and ``n_clutter // 3`` per frame.

    Parameters
    ----------
    hand : HandModel
        The hand to observe.
    rng : int or numpy.random.Generator
        Seed (≥ 0) or generator of the features, detections, noise and clutter.
    n_frames : int, default 100
        Number of frames F (≥ 2). At most :data:`amdo_lab.common.MAX_ITERATIONS` (100,000).
    fps : float, default 20.0
        Frame rate, frames per second (> 0); one full motion cycle spans the sequence.
    n_features : int, default 1500
        Skin features on the hand (≥ 1).
    noise_mm : float, default 2.0
        Standard deviation of the Gaussian noise per coordinate, mm, in [0, 1e6].
    n_clutter : int, default 150
        Forearm clutter points per frame (≥ 0). At most :data:`amdo_lab.common.MAX_SAMPLES` (1,000,000).
    repeatability : float, default DEFAULT_REPEATABILITY
        Share of the camera-facing features detected per frame, in (0, 1].
    motion : {"turn", "bend"}, default "turn"
        The paper's turning hand, or fingers bending with the palm still.
    camera : array_like, shape (3,), optional
        Camera centre, mm, within ±1e6 (default 500 mm above the hand).

    Returns
    -------
    TrackingSequence
        The true poses and every frame's data.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591, Sec. 5 and Fig. 3.
    """
    check_hand(hand)
    rng = make_rng(rng, "rng")
    n_frames = check_positive_int(n_frames, "n_frames", minimum=2, maximum=MAX_ITERATIONS)
    n_clutter = check_positive_int(n_clutter, "n_clutter", minimum=0, maximum=MAX_SAMPLES)
    check_choice(motion, "motion", ("turn", "bend"))
    camera = _CAMERA if camera is None else as_finite_array(camera, "camera", ndim=1, shape=(3,),
                                                            max_abs=MAX_LENGTH_MM)
    noise_mm = check_in_range(noise_mm, "noise_mm", 0.0, MAX_LENGTH_MM, closed="both")
    repeatability = check_in_range(repeatability, "repeatability", 0.0, 1.0, closed="right")
    time = np.arange(n_frames) / check_positive(fps, "fps")
    base = hand.rest_pose()
    poses = np.repeat(base[None], n_frames, axis=0)
    phase = 2 * np.pi * time / (n_frames / fps)
    if motion == "turn":
        poses[:, 4] = 0.6 * np.sin(phase)  # turn about the hand's long axis (parallel to the image)
    bend = 0.5 * (1 - np.cos(phase))  # 0 -> 1 -> 0
    for f in range(4):
        poses[:, 12 + 4 * f] = 0.1 + 1.0 * bend
        poses[:, 13 + 4 * f] = 0.1 + 0.9 * bend
        poses[:, 14 + 4 * f] = 0.1 + 0.6 * bend
    poses[:, 10] = 0.1 + 0.6 * bend
    skin = make_skin_texture(hand, n_features, rng=rng)
    frames, masks = [], []
    for pose in poses:
        features = skin.positions(hand, pose)
        facing = np.flatnonzero(_visible_points(hand, features, pose, camera))
        surface, _ = _observe(features, facing, int(round(repeatability * len(facing))), noise_mm, rng)
        # forearm: a cylinder of radius 30 mm along -y below the wrist, front half only
        angle = rng.uniform(0, np.pi, size=n_clutter)
        arm = np.column_stack([30 * np.cos(angle), rng.uniform(-160, -60, n_clutter), 30 * np.sin(angle) - 10])
        background = rng.uniform([-120, -150, -150], [120, 200, -100], size=(n_clutter // 3, 3))
        clutter = np.concatenate([arm, background])
        frames.append(np.concatenate([surface, clutter]))
        masks.append(np.r_[np.zeros(len(surface), bool), np.ones(len(clutter), bool)])
    return TrackingSequence(poses, frames, masks, float(fps))
