"""Tests for chapter 4 (Choraś 2004): synthetic ears, contour detector, V and F, matcher."""

import cv2
import numpy as np
import pytest
from rejections import check_rejection, reject
from sklearn.exceptions import NotFittedError

from amdo_lab import ear_biometrics as eb
from amdo_lab.common import make_rng
from amdo_lab.ear_biometrics.contours import detect_contours_reference
from amdo_lab.ear_biometrics.enrolment import check_subject_id, check_subject_ids
from amdo_lab.ear_biometrics.frame import moment_frame_fast
from amdo_lab.ear_biometrics.images import as_bool_image, check_images
from amdo_lab.ear_biometrics.matcher import check_templates


@pytest.fixture(scope="module")
def clean_ear_contours():
    """Contours of one noise-light perpendicular ear, padded into a 256x256 frame."""
    rng = make_rng(7)
    shape = eb.draw_ear_shape(rng=rng)
    image = eb.render_ear(shape, eb.CapturePose(0.0, 1.0, np.zeros(2), 0.0), rng=rng, size=128)
    contours = eb.clean_contours(eb.detect_contours(image, 8.0))
    big = np.zeros((256, 256), bool)
    big[64:192, 64:192] = contours
    return big


def test_generator_is_seeded_and_unpacks():
    images, ids = eb.make_ear_database(3, 2, "easy", rng=11)
    again = eb.make_ear_database(3, 2, "easy", rng=11)
    other = eb.make_ear_database(3, 2, "easy", rng=12)
    assert images.shape == (6, 256, 256) and images.dtype == np.uint8
    assert ids.tolist() == [0, 0, 1, 1, 2, 2]
    assert np.array_equal(images, again.images)
    assert not np.array_equal(images, other.images)
    assert again.poses[0].yaw == 0.0 and np.deg2rad(20) - 1e-9 <= again.poses[1].yaw <= np.deg2rad(30) + 1e-9


def test_difficult_images_carry_more_clutter_than_easy_ones():
    """Same subjects and seeds: occluders, noise and uneven light add contour pixels."""
    easy = eb.make_ear_database(4, 1, "easy", rng=3).images
    hard = eb.make_ear_database(4, 1, "difficult", rng=3).images
    clutter = [np.mean([eb.clean_contours(eb.detect_contours(im)).mean() for im in ims]) for ims in (easy, hard)]
    assert clutter[1] > 1.5 * clutter[0]


def test_disabling_a_factor_changes_only_that_factor():
    base = eb.make_ear_database(3, 2, "easy", rng=4)
    no_yaw = eb.make_ear_database(3, 2, "easy", rng=4, disable=("yaw",))
    assert all(p.yaw == 0.0 for p in no_yaw.poses)
    assert [(p.rotation, p.scale) for p in no_yaw.poses] == [(p.rotation, p.scale) for p in base.poses]
    assert np.array_equal(no_yaw.images[0::2], base.images[0::2])  # perpendicular captures unchanged
    assert not np.array_equal(no_yaw.images[1::2], base.images[1::2])
    still = eb.make_ear_database(3, 2, "easy", rng=4, disable=eb.NUISANCE_FACTORS)
    assert np.array_equal(still.images[0::2], still.images[1::2])  # no nuisance: identical captures


def test_easy_lighting_is_fixed_and_difficult_lighting_varies():
    """Paper Sec. 6: the easy images have no illumination changes."""
    easy = eb.make_ear_database(3, 2, "easy", rng=8)
    assert np.array_equal(easy.images, eb.make_ear_database(3, 2, "easy", rng=8, disable=("illumination",)).images)
    hard = eb.make_ear_database(3, 2, "difficult", rng=8)
    assert not np.array_equal(hard.images, eb.make_ear_database(3, 2, "difficult", rng=8, disable=("illumination",)).images)


def test_crura_end_beneath_the_helix():
    rng = make_rng(5)
    for _ in range(200):
        shape = eb.draw_ear_shape(rng=rng)
        for end in (shape.superior_crus_end, shape.inferior_crus_end):
            angle = np.arctan2(end[1] / shape.helix_axes[1], end[0] / shape.helix_axes[0])
            helix_radius = eb.synthetic._radius(np.array([angle]), shape.helix_harmonics)[0]
            assert np.linalg.norm(end / shape.helix_axes) < 0.91 * helix_radius


def test_loader_reads_grey_and_colour_files(tmp_path):
    images, _ = eb.make_ear_database(2, 1, "easy", rng=5)
    cv2.imwrite(str(tmp_path / "007_a.png"), images[0])
    cv2.imwrite(str(tmp_path / "012_b.png"), cv2.cvtColor(images[1], cv2.COLOR_GRAY2BGR))
    (tmp_path / "notes.txt").write_text("not an image")
    loaded, ids = eb.load_ear_folder(tmp_path)
    assert ids.tolist() == ["007", "012"]
    assert np.array_equal(loaded[0], images[0])
    assert loaded[1].ndim == 2 and np.abs(loaded[1].astype(int) - images[1]).max() <= 1
    resized, _ = eb.load_ear_folder(tmp_path, size=64)
    assert resized[0].shape == (64, 64)


def test_detector_matches_a_literal_loop_of_eqs_1_to_5():
    image = make_rng(1).uniform(10, 200, size=(12, 13))
    k = 2.5
    padded = np.pad(image, 1, mode="symmetric")
    expected = np.zeros(image.shape, bool)
    for i in range(image.shape[0]):
        for j in range(image.shape[1]):
            window = padded[i:i + 3, j:j + 3]
            mu, sigma = window.mean(), window.std(ddof=1)  # eqs. 1, 2
            spread = window.max() - window.min()  # eq. 3
            expected[i, j] = spread >= mu - k * sigma and spread > 0  # eqs. 4, 5
    assert np.array_equal(eb.detect_contours(image, k), expected)


def test_detector_uint8_path_matches_the_float_path():
    image = make_rng(3).integers(0, 256, size=(20, 23)).astype(np.uint8)
    for k in (0.0, 1.0, 2.5, 8.0):
        assert np.array_equal(eb.detect_contours(image, k), eb.detect_contours(image.astype(float), k))


def test_detector_finds_a_step_edge_and_is_monotone_in_k():
    image = np.full((20, 20), 100.0)
    image[:, 10:] = 160.0
    contours = eb.detect_contours(image, k=4.0)
    assert contours[:, 9:11].all() and not contours[:, :8].any() and not contours[:, 12:].any()
    noisy = image + make_rng(2).normal(0, 3, image.shape)
    assert np.all(eb.detect_contours(noisy, 2.0) <= eb.detect_contours(noisy, 6.0))
    assert not eb.detect_contours(np.zeros((16, 16)), 5.0).any()  # flat black: S = 0, no contour


def test_circle_features_of_a_plus_sign():
    contours = np.zeros((101, 101), bool)
    contours[50, 10:91] = True
    contours[10:91, 50] = True
    features = eb.circle_features(contours, n_circles=3, step=0.5)
    spread = features.normalisation.spread[0]
    assert features.counts.tolist() == [4, 4, 4]
    radii_px = features.radii * spread
    assert np.all(radii_px < 40)
    np.testing.assert_allclose(features.distance_sums, 4 * np.sqrt(2) * features.radii, rtol=0.03)
    assert features.vector.shape == (3, 3)


def test_min_gap_merges_a_ragged_double_line():
    """Each arm of the plus is drawn twice, one empty pixel apart: without merging every circle sees
    8 runs, with min_gap_px = 3 the 4 arms."""
    contours = np.zeros((101, 101), bool)
    for offset in (-1, 1):
        contours[50 + offset, 10:91] = True
        contours[10:91, 50 + offset] = True
    assert eb.circle_features(contours, n_circles=3, step=0.5, mode="isotropic").counts.tolist() == [8, 8, 8]
    merged = eb.circle_features(contours, n_circles=3, step=0.5, mode="isotropic", min_gap_px=3)
    assert merged.counts.tolist() == [4, 4, 4]


def _plus(size: int = 201, arm: int = 90) -> np.ndarray:
    contours = np.zeros((size, size), bool)
    centre = size // 2
    contours[centre, centre - arm:centre + arm + 1] = True
    contours[centre - arm:centre + arm + 1, centre] = True
    return contours


def test_skeleton_graph_reads_a_staircase_as_one_path():
    """An 8-connected staircase (with L corners) is a path: n - 1 edges, no triangles."""
    stairs = np.zeros((12, 12), bool)
    rows = np.repeat(np.arange(6), 2)
    stairs[rows, np.arange(12)] = True  # two pixels per row: horizontal steps + diagonal risers
    nodes, edges = eb.skeleton_graph(stairs)
    assert len(nodes) == stairs.sum() and len(edges) == len(nodes) - 1
    degree = np.bincount(edges.ravel(), minlength=len(nodes))
    assert sorted(degree.tolist()).count(1) == 2  # two ends
    corner = np.zeros((3, 3), bool)
    corner[0, 0] = corner[0, 1] = corner[1, 1] = True  # an L: the diagonal (0,0)-(1,1) is redundant
    assert len(eb.skeleton_graph(corner)[1]) == 2


def test_polyline_crossings_of_a_plus_sign_and_a_jagged_line():
    plus = _plus()
    features = eb.circle_features(plus, n_circles=3, step=0.5, mode="isotropic", crossings="polyline")
    assert features.counts.tolist() == [4, 4, 4]
    np.testing.assert_allclose(features.distance_sums, 4 * np.sqrt(2) * features.radii, rtol=0.03)
    # a line at a shallow angle rasterises as a staircase; it still crosses each circle once per arm
    jagged = np.zeros((201, 201), np.uint8)
    cv2.line(jagged, (10, 90), (190, 110), 1, 1)
    cv2.line(jagged, (90, 10), (110, 190), 1, 1)
    counts = eb.circle_features(jagged > 0, n_circles=3, step=0.5, mode="isotropic", crossings="polyline").counts
    assert counts.tolist() == [4, 4, 4]


def test_dead_band_ignores_a_graze_and_keeps_a_crossing():
    """A bump whose tip pokes 1.5 px beyond a circle and turns back crosses it twice as a sign change,
    not at all with a 3-px dead band; the plus's real crossings survive the band."""
    plus = _plus()
    base = eb.circle_features(plus, n_circles=2, step=0.5, mode="isotropic")
    radius_px = base.radii[1] * base.normalisation.spread[0]
    centre = base.normalisation.centroid  # (row, col)
    direction = np.array([-1.0, 1.0]) / np.sqrt(2)  # up-right diagonal, between the arms
    tangent = np.array([1.0, 1.0]) / np.sqrt(2)
    apex = centre + (radius_px + 1.5) * direction
    ends = [centre + (radius_px - 12) * direction + sign * 8 * tangent for sign in (-1, 1)]
    canvas = plus.astype(np.uint8)
    for end in ends:
        cv2.line(canvas, tuple(int(v) for v in np.round(end[::-1])), tuple(int(v) for v in np.round(apex[::-1])), 1, 1)
    skeleton = canvas > 0
    common = dict(n_circles=2, step=0.5, mode="isotropic", crossings="polyline", polyline_smoothing=0, skeleton=skeleton)
    plain = eb.circle_features(plus, band_px=0.0, **common).counts
    banded = eb.circle_features(plus, band_px=3.0, **common).counts
    assert plain.tolist() == [4, 6] and banded.tolist() == [4, 4]



def test_contour_crossings_counts_changes_of_side_and_matches_the_graph_path():
    """The readable path for one contour: a graze inside the band is not counted, a crossing once; on
    random wiggly paths it equals the vectorised graph reading of circle_features (band and none)."""
    from amdo_lab.ear_biometrics.circles import _graph_crossings
    graze = [(0.5, 0.0), (1.5, 0.0), (0.98, 0.05), (1.5, 0.2)]
    assert eb.contour_crossings(graze, [1.0]).tolist() == [3]
    assert eb.contour_crossings(graze, [1.0], band=0.05).tolist() == [1]
    assert eb.contour_crossings(graze, [0.2, 2.0]).tolist() == [0, 0]
    rng = np.random.default_rng(5)
    radii = np.array([0.7, 0.9, 1.1, 1.3])
    for _ in range(20):
        t = np.linspace(0, 1, 150)
        r = 1 + 0.35 * np.sin(2 * np.pi * rng.uniform(1, 3) * t + rng.uniform(0, 6)) + 0.04 * rng.normal(size=t.size)
        xy = np.c_[r * np.cos(4 * t), r * np.sin(4 * t)]
        path = np.c_[np.arange(len(xy) - 1), np.arange(1, len(xy))]
        for band in (0.0, 0.05):
            rows, _ = _graph_crossings(xy, path, radii, band)
            assert eb.contour_crossings(xy, radii, band).tolist() == np.bincount(rows, minlength=4).tolist()
    with pytest.raises(ValueError, match="points"):
        eb.contour_crossings([(0.0, 1.0)], [1.0])
    with pytest.raises(ValueError, match="radii"):
        eb.contour_crossings(graze, [0.0])

def test_prune_spurs_removes_short_branches_and_keeps_line_length():
    line = np.zeros((20, 40), bool)
    line[10, 2:38] = True
    spur = line.copy()
    spur[7:10, 20] = True  # a 3-pixel side branch
    pruned = eb.prune_spurs(spur, 5)
    assert np.array_equal(pruned, line)
    assert np.array_equal(eb.prune_spurs(line, 5), line)
    assert np.array_equal(eb.prune_spurs(spur, 0), spur)


def test_smooth_polylines_keeps_ends_and_straightens_a_zigzag():
    nodes = np.c_[np.zeros(9), np.arange(9.0)]
    nodes[1::2, 0] = 1.0  # zigzag between rows 0 and 1
    edges = np.c_[np.arange(8), np.arange(1, 9)]
    smoothed = eb.smooth_polylines(nodes, edges, 4)
    np.testing.assert_array_equal(smoothed[[0, -1]], nodes[[0, -1]])
    assert np.ptp(smoothed[2:-2, 0]) < 0.5 * np.ptp(nodes[2:-2, 0])


def test_principal_normalisation_whitens_and_round_trips(clean_ear_contours):
    norm = eb.normalise_coordinates(clean_ear_contours, "principal")
    xy = norm.to_normalised(np.argwhere(clean_ear_contours))
    np.testing.assert_allclose(xy.mean(axis=0), 0, atol=1e-9)
    np.testing.assert_allclose(np.cov(xy.T, bias=True), np.eye(2), atol=1e-9)
    assert np.mean(xy[:, 0] ** 3) > 0 and np.mean(xy[:, 1] ** 3) > 0  # sign convention
    pixels = np.array([[3.0, 4.0], [100.5, 7.25]])
    np.testing.assert_allclose(norm.to_pixels(norm.to_normalised(pixels)), pixels)
    upright = eb.normalise_coordinates(clean_ear_contours, "axes")
    np.testing.assert_allclose(np.sort(norm.spread), np.sort(upright.spread), rtol=0.1)  # ear is near upright


def test_exact_invariance_to_quarter_turns_shifts(clean_ear_contours):
    base = eb.circle_features(clean_ear_contours)
    for moved in (np.rot90(clean_ear_contours), np.roll(clean_ear_contours, (7, -5), (0, 1))):
        other = eb.circle_features(moved)
        assert np.array_equal(other.counts, base.counts)
        np.testing.assert_allclose(other.distance_sums, base.distance_sums, atol=1e-6)


def _warp(contours, matrix):
    return cv2.warpAffine(contours.astype(np.uint8), matrix, contours.shape[::-1], flags=cv2.INTER_NEAREST) > 0


def test_property_random_similarities_change_features_only_by_discretisation(clean_ear_contours):
    """Property test over random similarity transforms (any rotation, scale 0.8-1.25, shift): the
    isotropic reading of eq. 6 moves V only by discretisation; the literal per-image-axis eq. 6 moves
    the distance sums several times more; the principal-axis reading lies in between (its circles
    run nearly along the helix, where a one-pixel change adds or removes a crossing)."""
    rng = make_rng(2024)
    modes = eb.NORMALISATION_MODES
    base = {mode: eb.circle_features(clean_ear_contours, mode=mode, min_gap_px=3) for mode in modes}
    gaps = {mode: [] for mode in modes}
    for _ in range(10):
        matrix = cv2.getRotationMatrix2D((128, 128), rng.uniform(0, 360), rng.uniform(0.8, 1.25))
        matrix[:, 2] += rng.uniform(-20, 20, 2)
        warped = _warp(clean_ear_contours, matrix)
        for mode in modes:
            moved = eb.circle_features(warped, mode=mode, min_gap_px=3)
            gaps[mode].append((np.abs(moved.counts - base[mode].counts).mean(),
                               np.abs(moved.distance_sums - base[mode].distance_sums).mean()))
    mean = {mode: np.mean(gaps[mode], axis=0) for mode in modes}
    assert mean["isotropic"][0] <= 0.5 and mean["isotropic"][1] <= 0.2
    assert mean["axes"][1] > 3 * mean["isotropic"][1]
    assert mean["isotropic"][1] < mean["principal"][1] < mean["axes"][1]


def test_principal_normalisation_absorbs_horizontal_foreshortening(clean_ear_contours):
    """A camera turned by 30 degrees about the vertical axis squeezes columns by cos 30 degrees; the
    principal (and literal per-axis) reading divides that out, the isotropic one does not."""
    squeeze = np.float32([[np.cos(np.pi / 6), 0, 128 * (1 - np.cos(np.pi / 6))], [0, 1, 0]])
    squeezed = _warp(clean_ear_contours, squeeze)
    gap = {}
    for mode in ("principal", "isotropic"):
        a = eb.circle_features(clean_ear_contours, mode=mode, min_gap_px=3)
        b = eb.circle_features(squeezed, mode=mode, min_gap_px=3)
        gap[mode] = np.abs(a.distance_sums - b.distance_sums).mean()
    assert gap["principal"] < 0.5 * gap["isotropic"]


def test_crossing_number_endings_and_bifurcation():
    skeleton = np.zeros((15, 15), bool)
    skeleton[7, 2:8] = True  # stem
    for step in range(1, 6):
        skeleton[7 - step, 7 + step] = True  # upper branch
        skeleton[7 + step, 7 + step] = True  # lower branch
    n_c = eb.crossing_number(skeleton)
    assert np.sum(n_c == 1) == 3
    assert np.sum(n_c > 2) >= 1 and n_c[7, 7] >= 3
    assert np.all(n_c[~skeleton] == 0)


def test_connectivity_number_differs_from_the_crossing_number_where_branches_touch():
    tee = np.zeros((5, 5), bool)
    tee[2, 1:4] = True
    tee[3, 2] = True  # arms west, east and south of the centre, touching diagonally
    plus = np.zeros((5, 5), bool)
    plus[2, 1:4] = plus[1:4, 2] = True
    y_shape = np.zeros((15, 15), bool)
    y_shape[7, 2:8] = True
    for step in range(1, 6):
        y_shape[7 - step, 7 + step] = y_shape[7 + step, 7 + step] = True  # branches apart from each other
    assert (eb.connectivity_number(tee)[2, 2], eb.crossing_number(tee)[2, 2]) == (1, 3)
    assert (eb.connectivity_number(plus)[2, 2], eb.crossing_number(plus)[2, 2]) == (0, 4)
    assert eb.connectivity_number(y_shape)[7, 7] == eb.crossing_number(y_shape)[7, 7] == 3
    assert eb.connectivity_number(tee)[2, 1] == 1 and eb.connectivity_number(y_shape)[7, 4] == 2


def test_topology_features_reads_eq8_either_way_on_a_y_contour():
    contours = np.zeros((80, 80), bool)
    for end in ((10, 40), (70, 10), (70, 70)):
        cv2.line(contours.view(np.uint8), (40, 40), end, 1, 1)
    for eq8 in eb.EQ8_READINGS:
        n_e, n_b, _ = eb.topology_features(contours, n_circles=4, step=0.4, eq8=eq8).contours[0].triple
        assert (n_e, n_b) == (3, 1), eq8


def test_topology_features_of_a_y_contour():
    contours = np.zeros((80, 80), bool)
    cv2.line(contours.view(np.uint8), (10, 40), (40, 40), 1, 1)
    cv2.line(contours.view(np.uint8), (40, 40), (70, 10), 1, 1)
    cv2.line(contours.view(np.uint8), (40, 40), (70, 70), 1, 1)
    features = eb.topology_features(contours, n_circles=4, step=0.4)
    assert len(features.contours) == 1
    n_e, n_b, n_i = features.contours[0].triple
    assert (n_e, n_b) == (3, 1)
    assert n_i == int(features.circles.counts.sum())


@pytest.fixture(scope="module")
def small_database():
    return eb.make_ear_database(6, 2, "easy", rng=99)


def test_matcher_finds_an_enrolled_image_and_rejects_blank(small_database):
    images, ids = small_database
    matcher = eb.EarMatcher()
    for image, subject in zip(images[0::2], ids[0::2]):
        matcher.enroll(subject, image)
    result = matcher.identify(images[4])
    assert result.subject_id == ids[4] and result.candidate_ids[0] == ids[4]
    assert result.scores.shape == (6,) and np.argmin(result.scores) == 2
    blank = matcher.identify(np.full((128, 128), 120, np.uint8))
    assert blank.subject_id is None and blank.reason == "no contour"
    strict = eb.EarMatcher(eb.MatcherSettings(distance_threshold=1e-9))
    strict.enroll(0, images[0])
    assert strict.identify(images[3]).subject_id is None


def test_hog_baseline_and_cmc(small_database):
    images, ids = small_database
    baseline = eb.HogNearestNeighbour()
    for image, subject in zip(images[0::2], ids[0::2]):
        baseline.enroll(subject, image)
    assert baseline.identify(images[6]) == ids[6]
    assert eb.rank_of_truth(np.array([0.3, 0.1, 0.2]), np.array([5, 6, 7]), 7) == 2
    cmc = eb.cumulative_match(np.array([1, 3, 2, 1]), 3)
    np.testing.assert_allclose(cmc, [0.5, 0.75, 1.0])


def test_lbp_baseline_and_peer_closed_set(small_database):
    images, ids = small_database
    lbp = eb.LbpNearestNeighbour(cells_per_side=4, blur_sigma=1.0)
    descriptor = lbp.describe(images[0])
    assert descriptor.shape == (4 * 4 * 10,)
    np.testing.assert_allclose(descriptor.reshape(16, 10).sum(axis=1), 1.0)  # one histogram per cell
    same_twice = np.repeat(np.asarray(images)[0::2], 2, axis=0)  # each image queried as itself
    ranks, separation = eb.peer_closed_set(same_twice, np.repeat(ids[0::2], 2), lbp)
    assert (ranks == 1).all() and separation.auc == 1.0
    assert lbp.descriptors_ is None  # the baseline given is copied, not fitted
    hog_ranks, _ = eb.peer_closed_set(images, ids)
    np.testing.assert_array_equal(hog_ranks, eb.hog_closed_set(images, ids)[0])


def test_separation_of_a_known_distance_matrix():
    distances = np.array([[0.1, 0.5, 0.9],
                          [0.6, 0.2, 0.4],
                          [0.3, 0.2, 0.7]])  # third query (subject 2) is closer to subjects 0 and 1
    sep = eb.genuine_impostor_separation(distances, [0, 1, 2], [0, 1, 2])
    np.testing.assert_allclose(sep.genuine, [0.1, 0.2, 0.7])
    assert sep.auc == pytest.approx((1 + 1 + 0) / 3)
    impostor = np.array([0.5, 0.9, 0.6, 0.4, 0.3, 0.2])
    genuine = np.array([0.1, 0.2, 0.7])
    expected = (impostor.mean() - genuine.mean()) / np.sqrt(0.5 * (genuine.var() + impostor.var()))
    assert sep.d_prime == pytest.approx(expected)


def test_closed_set_protocol(small_database):
    images, ids = small_database
    matcher = eb.EarMatcher()
    templates = [matcher.extract(im) for im in images]
    result = eb.closed_set(eb.EarMatcher(), templates, ids)
    assert result.ranks.shape == (6,) and result.ranks.min() >= 1 and result.ranks.max() <= 6
    assert 0 <= result.correct <= 1 and result.truth.tolist() == list(ids[1::2])
    assert result.correct + result.rejected <= 1 + 1e-12
    self_match = eb.closed_set(eb.EarMatcher(), [t for t in templates[0::2] for _ in range(2)], np.repeat(ids[0::2], 2))
    assert self_match.rank1 == 1.0 and self_match.correct == 1.0  # an image is found as itself
    assert result.recognised.dtype == bool
    assert result.recognised.tolist() == [decided == truth for decided, truth in zip(result.decided, result.truth)]
    assert self_match.recognised.all()
    hog_ranks, hog_sep = eb.hog_closed_set(images, ids)
    assert hog_ranks.shape == (6,) and 0 <= hog_sep.auc <= 1


def test_open_set_rates_of_enrolled_templates(small_database):
    images, ids = small_database
    matcher = eb.EarMatcher()
    templates = [matcher.extract(im) for im in images]
    for t, s in zip(templates[0:6:2], ids[0:6:2]):  # subjects 0-2 enrolled, 3-5 never seen
        matcher.enroll_template(s, t)
    rates = eb.open_set_rates(matcher, templates[0:6:2], list(ids[0:6:2]), templates[6::2], np.array([0.0, np.inf]))
    assert matcher.settings.distance_threshold == np.inf
    # threshold 0 accepts nothing; an infinite threshold accepts each enrolled image as itself
    np.testing.assert_allclose(rates.false_accept[0], 0.0)
    np.testing.assert_allclose(rates.false_reject, [1.0, 0.0])
    np.testing.assert_allclose(rates.misidentified, [0.0, 0.0])
    assert np.all(np.diff(rates.false_accept) >= 0)


# --- canonical frame (silhouette moments before contour detection) and the point ranking of F ---

def _similarity(image, angle_deg, scale, shift, flags=cv2.INTER_LINEAR):
    matrix = cv2.getRotationMatrix2D((image.shape[1] / 2, image.shape[0] / 2), angle_deg, scale)
    matrix[:, 2] += shift
    return cv2.warpAffine(image, matrix, image.shape[::-1], flags=flags, borderMode=cv2.BORDER_REPLICATE), matrix


def _homogeneous(matrix):
    return np.r_[matrix, [[0.0, 0.0, 1.0]]]


def test_silhouette_covers_the_ear_and_is_empty_on_a_blank_image(small_database):
    image = small_database.images[0]
    mask = eb.silhouette(image)
    assert mask.dtype == bool and 0.1 < mask.mean() < 0.5
    assert not mask[0].any() and not mask[:, 0].any()  # background at the border
    from amdo_lab.ear_biometrics.synthetic import _to_pixels

    outline = _to_pixels(eb.ear_curves(small_database.shapes[0])[0], small_database.poses[0], 256)
    drawn = np.zeros((256, 256), np.uint8)
    cv2.fillPoly(drawn, [np.round(outline).astype(np.int32)], 1)
    overlap = (mask & (drawn > 0)).sum() / (mask | (drawn > 0)).sum()
    assert overlap > 0.9  # the silhouette is the drawn ear (its outline is blurred and jittered)
    assert not eb.silhouette(np.full((64, 64), 120, np.uint8)).any()


def test_moment_frame_fast_path_equals_the_reference(small_database):
    for image in small_database.images[:4]:
        mask = eb.silhouette(image)
        reference, fast = eb.moment_frame(mask, image.shape), moment_frame_fast(mask, image.shape)
        np.testing.assert_allclose(fast.matrix, reference.matrix, atol=1e-9)
        assert fast.third_moment == pytest.approx(reference.third_moment, abs=1e-9) and reference.third_moment >= 0


def test_moment_frame_undoes_a_similarity_including_a_half_turn(small_database):
    """The frame of a transformed mask, composed with the transform, is the frame of the original:
    the same canonical image up to resampling, for small turns and for 180 degrees (the third moment
    fixes the sign of the axis)."""
    mask = eb.silhouette(small_database.images[2]).astype(np.uint8)
    base = _homogeneous(eb.moment_frame(mask > 0, mask.shape).matrix)
    for angle, scale, shift in [(20.0, 1.1, (5.0, -3.0)), (-25.0, 0.9, (0.0, 6.0)), (180.0, 1.0, (0.0, 0.0))]:
        moved, matrix = _similarity(mask, angle, scale, shift, flags=cv2.INTER_NEAREST)
        composed = _homogeneous(eb.moment_frame(moved > 0, mask.shape).matrix) @ _homogeneous(matrix)
        residual = composed @ np.linalg.inv(base)
        assert np.degrees(abs(np.arctan2(residual[1, 0], residual[0, 0]))) < 1.0
        assert abs(np.hypot(residual[0, 0], residual[1, 0]) - 1) < 0.01
        centre = residual @ np.array([128.0, 128.0, 1.0])
        assert np.hypot(*(centre[:2] - 128)) < 1.0


def test_third_moment_points_the_axis_to_the_longer_tail():
    """A teardrop (a disc with a long tail downwards): the signed axis points down the tail, and the
    same shape upside down gets the opposite axis."""
    drop = np.zeros((128, 128), np.uint8)
    cv2.circle(drop, (64, 50), 20, 1, -1)
    cv2.fillConvexPoly(drop, np.array([[48, 55], [80, 55], [64, 110]], np.int32), 1)
    down = eb.moment_frame(drop > 0, drop.shape)
    up = eb.moment_frame(np.flipud(drop) > 0, drop.shape)
    assert down.axis[0] > 0.99 and up.axis[0] < -0.99  # (row, col): +row is down the image
    assert down.third_moment > 0.1 and up.third_moment == pytest.approx(down.third_moment, rel=1e-6)


def test_canonical_image_centres_and_uprights_the_silhouette(small_database):
    image = small_database.images[3]
    frame = eb.moment_frame(eb.silhouette(image), image.shape)
    canonical = eb.to_canonical(image, frame)
    assert canonical.dtype == image.dtype and canonical.shape == image.shape
    again = eb.moment_frame(eb.silhouette(canonical), image.shape)
    np.testing.assert_allclose(again.centroid, [128, 128], atol=1.0)
    assert again.axis[0] > np.cos(np.radians(1.0))  # the major axis is the downward vertical
    assert again.spread == pytest.approx(eb.CANONICAL_SPREAD * 256, rel=0.02)


def test_frame_normalisation_divides_by_the_silhouette_spreads(small_database):
    image = small_database.images[0]
    frame = eb.moment_frame(eb.silhouette(image), image.shape)
    total = eb.CANONICAL_SPREAD * 256
    per_axis = eb.frame_normalisation(frame, image.shape)
    assert np.hypot(*per_axis.spread) == pytest.approx(total)
    assert per_axis.spread[0] / per_axis.spread[1] == pytest.approx(frame.elongation)
    np.testing.assert_allclose(per_axis.to_normalised(np.array([128.0, 128.0])), [[0.0, 0.0]])
    above = per_axis.to_normalised(np.array([128.0 - per_axis.spread[0], 128.0]))
    np.testing.assert_allclose(above, [[0.0, 1.0]])  # y points up the image
    isotropic = eb.frame_normalisation(frame, image.shape, "isotropic")
    np.testing.assert_allclose(isotropic.spread, total / np.sqrt(2))


def test_point_distance_reference_equals_the_matcher_vectorised_path(small_database):
    matcher = eb.EarMatcher()
    templates = [matcher.extract(image) for image in small_database.images[:5]]
    for subject, template in enumerate(templates[:4]):
        matcher.enroll_template(subject, template)
    query = templates[4]
    reference = [eb.point_distance(query.topology, t.topology) for t in templates[:4]]
    assert matcher.settings.ranking == "points"  # identify_template scores by the vectorised point distances
    np.testing.assert_allclose(matcher.identify_template(query).scores, reference, atol=1e-12)
    assert eb.point_distance(query.topology, query.topology) == 0.0
    assert 0 < min(reference) <= max(reference) <= eb.POINT_DISTANCE_CAP


def test_similarity_copies_of_enrolled_images_are_identified(small_database):
    """Invariance as a user sees it: the enrolled images, turned by up to 25 degrees, rescaled by
    0.85-1.15 and shifted by up to 8 px, are identified by the canonical pipeline."""
    images, ids = small_database
    matcher = eb.EarMatcher()
    for image, subject in zip(images[0::2], ids[0::2]):
        matcher.enroll(subject, image)
    rng = make_rng(123)
    for image, subject in zip(images[0::2], ids[0::2]):
        result = matcher.identify(eb.similarity_copy(image, rng=rng))
        assert np.argmin(result.scores) == list(ids[0::2]).index(subject)


def test_reference_of_eqs_6_and_7_equals_the_vectorised_path(clean_ear_contours):
    """The plain-numpy, one-circle-at-a-time reading equals circle_features with the literal
    settings (image axes, pixel runs, no gap merging), on an ear and on a rotated "+" with a ring."""
    toy = np.zeros((101, 101), np.uint8)
    toy[50, 10:91] = 1
    toy[10:91, 50] = 1
    cv2.circle(toy, (50, 50), 28, 1, 1)
    rotated = cv2.warpAffine(toy, cv2.getRotationMatrix2D((50, 50), 30, 1.0), (101, 101), flags=cv2.INTER_NEAREST)
    for contours in (clean_ear_contours, toy > 0, rotated > 0):
        reference = eb.circle_features_reference(contours, 6, 0.3)
        fast = eb.circle_features(contours, 6, 0.3, mode="axes", crossings="pixels", min_gap_px=0.0)
        assert np.array_equal(reference.counts, fast.counts)
        np.testing.assert_allclose(reference.distance_sums, fast.distance_sums, atol=1e-9)
        np.testing.assert_allclose(reference.normalisation.matrix, fast.normalisation.matrix)


def test_similarity_copy_is_seeded_and_exact_for_a_quarter_turn():
    image = np.zeros((64, 64), np.uint8)
    image[10:20, 30:34] = 200
    turned = eb.similarity_copy(image, rng=1, rotation_deg=90.0, scale_range=(1.0, 1.0), max_shift_px=0.0)
    np.testing.assert_array_equal(turned, np.rot90(image))  # +90 degrees = counter-clockwise as displayed
    np.testing.assert_array_equal(eb.similarity_copy(image, rng=5), eb.similarity_copy(image, rng=5))
    assert eb.similarity_copy(image.astype(float), rng=5).dtype == float


def test_matcher_exposes_the_image_and_contours_its_features_come_from(small_database):
    image = small_database.images[0]
    literal = eb.EarMatcher(eb.MatcherSettings(frame="image"))
    assert literal.canonical_frame(image) is None
    np.testing.assert_array_equal(literal.canonical_image(image), image)
    matcher = eb.EarMatcher()
    canonical = matcher.canonical_image(image)
    assert canonical.dtype == np.uint8 and canonical.shape == image.shape
    contours = matcher.contour_image(image)
    from amdo_lab.ear_biometrics.frame import frame_normalisation

    norm = frame_normalisation(matcher.canonical_frame(image), image.shape)
    direct = eb.topology_features(contours, crossings="polyline", band_px=6.0, spur_length_px=8, polyline_smoothing=4,
                                  normalisation=norm)
    template = matcher.extract(image)
    np.testing.assert_array_equal(template.circles.counts, direct.circles.counts)
    np.testing.assert_allclose(eb.characteristic_points(template.topology), eb.characteristic_points(direct))


# --- the rng convention: keyword-only, no default, errors name ``rng`` ---------------------------

_POSE = eb.CapturePose(0.0, 1.0, np.zeros(2), 0.0)
RNG_CALLS = {
    "draw_ear_shape": lambda rng: eb.draw_ear_shape(rng=rng),
    "render_ear": lambda rng: eb.render_ear(eb.draw_ear_shape(rng=0), _POSE, rng=rng, size=64),
    "draw_capture_pose": lambda rng: eb.draw_capture_pose(rng=rng, frontal=True, size=64, difficulty="easy"),
    "make_ear_database": lambda rng: eb.make_ear_database(1, 1, rng=rng, size=64),
    "similarity_copy": lambda rng: eb.similarity_copy(np.zeros((16, 16), np.uint8), rng=rng),
    "nuisance_study": lambda rng: eb.nuisance_study(2, {"a": ()}, rng=rng),
}


@pytest.mark.parametrize("name", sorted(RNG_CALLS))
def test_drawing_functions_take_rng_keyword_only_without_default(name):
    import inspect

    parameter = inspect.signature(getattr(eb, name)).parameters["rng"]
    assert parameter.kind is inspect.Parameter.KEYWORD_ONLY
    assert parameter.default is inspect.Parameter.empty


def test_an_int_seed_and_its_generator_draw_the_same_ears():
    by_seed = eb.make_ear_database(2, 2, rng=21, size=64).images
    np.testing.assert_array_equal(by_seed, eb.make_ear_database(2, 2, rng=make_rng(21), size=64).images)
    np.testing.assert_array_equal(eb.similarity_copy(by_seed[0], rng=3), eb.similarity_copy(by_seed[0], rng=make_rng(3)))


def test_draw_circles_draws_the_circles_and_the_centroid(clean_ear_contours):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    features = eb.circle_features(clean_ear_contours, n_circles=3, step=0.5)
    fig, ax = plt.subplots()
    try:
        eb.draw_circles(ax, clean_ear_contours, features, show_crossings=True)
        assert len(ax.lines) >= 3 + 1  # three circles and the centroid, plus the polygons
    finally:
        plt.close(fig)


@pytest.mark.parametrize("module", ["synthetic", "contours", "circles", "matcher"])
def test_docstring_examples_run(module):
    import doctest
    import importlib

    result = doctest.testmod(importlib.import_module(f"amdo_lab.ear_biometrics.{module}"), verbose=False)
    assert result.attempted > 0 and result.failed == 0


# --- scikit-learn's estimator contract for the two matchers --------------------------------------

def test_matchers_fit_returns_self_and_learns_underscore_attributes(small_database):
    images, ids = small_database
    gallery, gallery_ids = images[0::2], ids[0::2]
    for matcher, learned in ((eb.EarMatcher(), "templates_"), (eb.HogNearestNeighbour(), "descriptors_")):
        assert getattr(matcher, learned) is None and matcher.subject_ids_ is None
        assert matcher.fit(gallery, gallery_ids) is matcher
        assert len(getattr(matcher, learned)) == len(gallery) and list(matcher.subject_ids_) == list(gallery_ids)
        first = matcher.identify(images[1])
        matcher.fit(gallery[:2], gallery_ids[:2])  # a second fit forgets the first
        assert len(matcher.subject_ids_) == 2
    assert first == ids[1]  # the HOG baseline on this easy pair


def test_ear_matcher_fit_equals_enrolling_one_by_one(small_database):
    images, ids = small_database
    fitted = eb.EarMatcher().fit(images[0::2], ids[0::2])
    enrolled = eb.EarMatcher()
    for subject, image in zip(ids[0::2], images[0::2]):
        enrolled.enroll(subject, image)
    a, b = fitted.identify(images[3]), enrolled.identify(images[3])
    assert a.subject_id == b.subject_id
    np.testing.assert_array_equal(a.scores, b.scores)


def test_hog_parameters_are_stored_as_given():
    assert eb.HogNearestNeighbour(pixels_per_cell=1).pixels_per_cell == 1  # checked when used: see REJECTIONS


def test_module_level_checks_return_valid_input(small_database):
    """The checks that evaluation.py and plotting.py share with matcher.py and features.py."""
    assert check_subject_id("ann", "who") == "ann" and check_subject_ids([1, 2], "ids").tolist() == [1, 2]
    check_images(small_database.images[:2])


def test_a_similarity_copy_moves_the_points_of_f_less_than_new_noise():
    """The default pipeline (canonical frame, blur before eqs. 1-5) on 12 ears drawn inside the image:
    a random similarity of the reference image changes F (the point distance D) less, on average,
    than a second capture that differs only by its sensor noise."""
    rng = np.random.default_rng(314)
    matcher, pose = eb.EarMatcher(), eb.CapturePose(0.0, 0.85, np.zeros(2), 0.0)
    noise, copy = [], []
    for _ in range(12):
        shape = eb.draw_ear_shape(rng=rng)
        reference, again = eb.render_ear(shape, pose, rng=rng), eb.render_ear(shape, pose, rng=rng)
        base = matcher.extract(reference).topology
        noise.append(eb.point_distance(matcher.extract(again).topology, base))
        copy.append(eb.point_distance(matcher.extract(eb.similarity_copy(reference, rng=rng)).topology, base))
    assert np.mean(copy) < np.mean(noise)


def test_detect_contours_reference_equals_the_filtered_detector():
    """Eqs. (1)-(5) one window at a time equal the box-filter path, for float and 8-bit images."""
    rng = make_rng(11)
    image = rng.uniform(10, 200, size=(14, 17))
    for k in (0.5, 2.5, 8.0):
        assert np.array_equal(detect_contours_reference(image, k), eb.detect_contours(image, k))
    eight_bit = rng.integers(0, 256, size=(12, 15)).astype(np.uint8)
    eight_bit[:4, :5] = 0  # a flat black corner: never a contour
    expected = eb.detect_contours(eight_bit, 3.0, window=5)
    assert np.array_equal(detect_contours_reference(eight_bit, 3.0, window=5), expected)
    assert 0 < expected.sum() < expected.size and not expected[:2, :2].any()


# --- rejections: the rules of the method, one table ----------------------------------------------
# The generic promises (NaN, empty, wrong shape or type, named by argument) are the bad-input test's
# (tests/test_bad_input.py, table tests/bad_input_cases/ear_biometrics.py); the rows below are the
# rules of this chapter. A call's parameters without a default name the fixtures it needs.

@pytest.fixture(scope="module")
def ctx(clean_ear_contours, small_database):
    """Features, a matcher with three subjects, a HOG baseline, a one-image folder and axes for the rows below."""
    import types

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    images, ids = small_database
    templates = [eb.EarMatcher().extract(im) for im in images[:6]]
    matcher = eb.EarMatcher()
    for t, s in zip(templates[0::2], ids[0:6:2]):
        matcher.enroll_template(s, t)
    baseline = eb.HogNearestNeighbour()
    baseline.enroll(0, images[0])
    fig, ax = plt.subplots()
    yield types.SimpleNamespace(
        features=eb.topology_features(clean_ear_contours), image=images[0], images=images, ids=ids,
        templates=templates, matcher=matcher, baseline=baseline,
        five_circles=eb.EarMatcher(eb.MatcherSettings(n_circles=5)).extract(images[1]), shape=eb.draw_ear_shape(rng=0),
        pose=eb.CapturePose(0.0, 1.0, np.zeros(2), 0.0), ax=ax)
    plt.close(fig)


def _enrolled(matcher, templates):
    """``matcher`` with the first template enrolled, for protocols that need an empty one."""
    matcher.enroll_template(0, templates[0])
    return matcher


REJECTIONS = [
    # --- the synthetic ears: named difficulties and nuisance factors, pose records in range
    reject("make_ear_database difficulty medium", lambda: eb.make_ear_database(2, 2, "medium", rng=0),
           ValueError, "difficulty must be one of"),
    reject("make_ear_database disable glare", lambda: eb.make_ear_database(2, 2, "easy", rng=0,
                                                                                   disable=("glare",)),
           ValueError, r"disable holds unknown name\(s\) \['glare'\]"),
    reject("draw_capture_pose difficulty hard", lambda: eb.draw_capture_pose(rng=0, frontal=True, size=128,
                                                                             difficulty="hard"),
           ValueError, "difficulty must be one of"),
    reject("draw_capture_pose size 31", lambda: eb.draw_capture_pose(rng=0, frontal=True, size=31, difficulty="easy"),
           ValueError, "size must be at least 32"),
    reject("render_ear tuple for a pose", lambda ctx: eb.render_ear(ctx.shape, (0.0, 1.0), rng=0),
           TypeError, "pose must be a CapturePose"),
    reject("render_ear NaN pose.rotation", lambda ctx: eb.render_ear(
        ctx.shape, eb.CapturePose(np.nan, 1.0, np.zeros(2), 0.0), rng=0), ValueError, "pose.rotation must be finite"),
    reject("render_ear pose.scale 0", lambda ctx: eb.render_ear(
        ctx.shape, eb.CapturePose(0.0, 0.0, np.zeros(2), 0.0), rng=0), ValueError, r"pose.scale must be in \(0, 10\]"),
    reject("render_ear pose.yaw 2 rad", lambda ctx: eb.render_ear(
        ctx.shape, eb.CapturePose(0.0, 1.0, np.zeros(2), 2.0), rng=0),
        ValueError, r"pose.yaw must be in \(-1.5708, 1.5708\)"),
    reject("ear_curves NaN shape.lobule_depth", lambda ctx: eb.ear_curves(
        eb.EarShape(**{**vars(ctx.shape), "lobule_depth": np.nan})), ValueError, "shape.lobule_depth must be finite"),
    reject("load_ear_folder no image files", lambda tmp_path: eb.load_ear_folder(tmp_path),
           ValueError, "folder must be an existing directory holding image files"),
    reject("load_ear_folder missing folder", lambda tmp_path: eb.load_ear_folder(tmp_path / "missing"),
           ValueError, "folder must be an existing directory"),
    # --- the contour detector (eqs. 1-5): a grey 2-D image, an odd window
    reject("detect_contours 1-D image", lambda: eb.detect_contours(np.zeros(16)),
           ValueError, "image must have 2 dimensions"),
    reject("detect_contours boolean image", lambda: eb.detect_contours(np.zeros((16, 16), bool)),
           TypeError, "image must be a numeric array"),
    reject("detect_contours 7 x 16 image", lambda: eb.detect_contours(np.zeros((7, 16))),
           ValueError, r"image side must be in \[8, inf\)"),
    reject("detect_contours window 4", lambda: eb.detect_contours(np.ones((16, 16)), window=4),
           ValueError, "window must be odd"),
    reject("detect_contours_reference window 4", lambda: detect_contours_reference(np.ones((16, 16)), 2.0, window=4),
           ValueError, "window must be odd"),
    *[reject(f"{name} image of shape {shape}", lambda function=function, shape=shape: function(
        np.zeros(shape, bool)), ValueError, "must not be empty")  # OpenCV crashed the interpreter on these
      for name, function in (("clean_contours", eb.clean_contours),
                             ("prune_spurs", lambda image: eb.prune_spurs(image, 2)),
                             ("skeleton_graph", eb.skeleton_graph), ("crossing_number", eb.crossing_number))
      for shape in ((0, 0), (5, 0))],
    # --- V and F (eqs. 6-9): contours to measure, named readings, a skeleton of the contours' size
    reject("topology_features eq8 zhang", lambda: eb.topology_features(_plus(), eq8="zhang"),
           ValueError, "eq8 must be one of"),
    reject("normalise_coordinates mode whiten", lambda clean_ear_contours: eb.normalise_coordinates(
        clean_ear_contours, "whiten"), ValueError, "mode must be one of"),
    reject("circle_features no contour", lambda: eb.circle_features(np.zeros((20, 20), bool)), ValueError, "no contour"),
    reject("circle_features_reference no contour", lambda: eb.circle_features_reference(np.zeros((9, 9), bool)),
           ValueError, "no contour"),
    reject("circle_features crossings subpixel", lambda: eb.circle_features(_plus(), crossings="subpixel"),
           ValueError, "crossings must be one of"),
    reject("circle_features skeleton of another size", lambda: eb.circle_features(
        _plus(), crossings="polyline", skeleton=np.zeros((5, 5), bool)),
        ValueError, r"skeleton must have shape \(201, 201\)"),
    reject("smooth_polylines edges beyond the nodes", lambda: eb.smooth_polylines(
        np.zeros((3, 2)), np.array([[0, 1], [1, 3]]), 2), ValueError, r"edges must lie in \[0, 2\]"),
    reject("smooth_polylines fractional edges", lambda: eb.smooth_polylines(np.zeros((3, 2)), np.array([[0.5, 1.0]]), 2),
           ValueError, "edges must hold whole numbers"),
    reject("to_pixels 1-D xy", lambda clean_ear_contours: eb.normalise_coordinates(clean_ear_contours).to_pixels(
        np.ones(4)), ValueError, r"xy must have shape \(n, 2\)"),
    reject("crossing_number 1-D skeleton", lambda: eb.crossing_number(np.ones(5, bool)),
           TypeError, "skeleton must be a 2-D boolean image"),
    reject("topology_similarity circles for topology", lambda ctx: eb.topology_similarity(
        ctx.features.circles, ctx.features), TypeError, "query must be a TopologyFeatures"),
    reject("point_distance circles for topology", lambda ctx: eb.point_distance(ctx.templates[0].circles, None),
           TypeError, "query must be a TopologyFeatures"),
    reject("characteristic_points image for features", lambda ctx: eb.characteristic_points(ctx.image),
           TypeError, "features must be a TopologyFeatures"),
    # --- the canonical frame (beyond the paper): a boolean silhouette of at least 3 pixels, spreads below 0.5
    reject("silhouette boolean image", lambda ctx: eb.silhouette(ctx.image > 100),
           TypeError, "image must be a numeric array"),
    reject("moment_frame empty mask", lambda: eb.moment_frame(np.zeros((32, 32), bool), (32, 32)),
           ValueError, "mask must hold at least 3 pixels"),
    reject("moment_frame shape of 4 rows", lambda ctx: eb.moment_frame(ctx.image > 100, (4, 256)),
           ValueError, r"shape must lie in \[8, 4096\]"),
    reject("frame_normalisation mode affine", lambda ctx: eb.frame_normalisation(
        eb.moment_frame(ctx.image > 100, ctx.image.shape), ctx.image.shape, "affine"),
        ValueError, "mode must be one of"),
    reject("similarity_copy scale_range reversed", lambda: eb.similarity_copy(np.zeros((16, 16)), rng=0,
                                                                              scale_range=(1.2, 0.9)),
           ValueError, "scale_range must be"),
    reject("similarity_copy NaN rotation_deg", lambda: eb.similarity_copy(np.zeros((16, 16)), rng=0,
                                                                          rotation_deg=np.nan),
           ValueError, "rotation_deg must be finite"),
    # --- EarMatcher's settings: an odd window, the named readings, frames, origins and rankings
    reject("MatcherSettings mode affine", lambda: eb.MatcherSettings(mode="affine"), ValueError, "mode must be one of"),
    reject("MatcherSettings crossings edges", lambda: eb.MatcherSettings(crossings="edges"), ValueError, "crossings must be one of"),
    reject("MatcherSettings frame affine", lambda: eb.MatcherSettings(frame="affine"), ValueError, "frame must be one of"),
    reject("MatcherSettings origin centre", lambda: eb.MatcherSettings(origin="centre"), ValueError, "origin must be one of"),
    reject("MatcherSettings ranking votes", lambda: eb.MatcherSettings(ranking="votes"), ValueError, "ranking must be one of"),
    reject("MatcherSettings window 10**9", lambda: eb.MatcherSettings(n_circles=10**9),
           ValueError, "n_circles must be at most 64"),
    reject("EarMatcher settings as a dict", lambda: eb.EarMatcher({"k": 8.0}), TypeError,
           "settings must be a MatcherSettings"),
    # --- matching: fitted first (scikit-learn's NotFittedError), templates of the matcher's settings
    reject("EarMatcher.identify not fitted", lambda ctx: eb.EarMatcher().identify(ctx.image),
           NotFittedError, "not fitted yet"),
    reject("HogNearestNeighbour.identify not fitted", lambda ctx: eb.HogNearestNeighbour().identify(ctx.image),
           NotFittedError, "not fitted yet"),
    reject("EarMatcher.identify_template not fitted", lambda ctx: eb.EarMatcher().identify_template(ctx.templates[0]),
           ValueError, "EarMatcher is not fitted yet"),  # NotFittedError is a ValueError
    reject("EarMatcher.identify boolean image", lambda ctx: ctx.matcher.identify(ctx.image > 100), TypeError,
           "image must be a numeric array"),
    reject("EarMatcher.fit one id for two images", lambda ctx: eb.EarMatcher().fit(
        ctx.images[0::2], ctx.ids[0::2][:2]),
           ValueError, "subject_ids must be a 1-D sequence giving one subject per image"),
    reject("HogNearestNeighbour.fit one id for two images", lambda ctx: eb.HogNearestNeighbour().fit(
        ctx.images[0::2], ctx.ids[0::2][:2]), ValueError, "subject_ids must be a 1-D sequence giving one subject per image"),
    reject("EarMatcher.enroll blank image", lambda: eb.EarMatcher().enroll(1, np.zeros((64, 64), np.uint8)),
           ValueError, "image has no contour"),
    reject("EarMatcher.enroll_template image for a template", lambda ctx: eb.EarMatcher().enroll_template(
        0, ctx.image),
           TypeError, "template must be an EarTemplate"),
    reject("EarMatcher.enroll_template 4 circles for 8", lambda ctx: eb.EarMatcher().enroll_template(
        0, eb.EarMatcher(eb.MatcherSettings(n_circles=4)).extract(ctx.image)), ValueError, "template has 4 circles, matcher expects 8"),
    reject("EarMatcher.identify_template image for a template", lambda ctx: ctx.matcher.identify_template(ctx.image),
           TypeError, "query must be an EarTemplate"),
    reject("EarMatcher.identify_template 5 circles for 8", lambda ctx: ctx.matcher.identify_template(
        ctx.five_circles),
           ValueError, "query has 5 circles, matcher expects 8"),
    reject("HogNearestNeighbour pixels_per_cell 1 when used", lambda ctx: eb.HogNearestNeighbour(
        pixels_per_cell=1).describe(ctx.image), ValueError, "pixels_per_cell must be at least 2"),
    reject("HogNearestNeighbour.enroll image of another size", lambda ctx: ctx.baseline.enroll(
        1, ctx.images[1][:128, :128]), ValueError, r"image must have the enrolled images' shape \(256, 256\)"),
    reject("HogNearestNeighbour.distances image of another size", lambda ctx: ctx.baseline.distances(
        ctx.images[1][:128, :128]), ValueError, "image must have the enrolled images' shape"),
    # --- evaluation protocols: ids that match the scores, thresholds, 1-based ranks, an empty matcher
    reject("open_set_rates one id for three templates", lambda ctx: eb.open_set_rates(
        ctx.matcher, ctx.templates[1::2], [0], ctx.templates[:1], [1.0]),
        ValueError, "genuine_ids must be a 1-D sequence giving one subject per genuine template"),
    reject("open_set_rates scalar thresholds", lambda ctx: eb.open_set_rates(
        ctx.matcher, ctx.templates[1::2], ctx.ids[1:6:2], ctx.templates[:1], 1.0),
        ValueError, "thresholds must be a non-empty 1-D sequence"),
    reject("open_set_rates no impostors", lambda ctx: eb.open_set_rates(
        ctx.matcher, ctx.templates[1::2], ctx.ids[1:6:2], [], [1.0]),
        ValueError, "impostors must be a non-empty list of EarTemplate"),
    reject("open_set_rates images for templates", lambda ctx: eb.open_set_rates(
        ctx.matcher, list(ctx.images[1:6:2]), ctx.ids[1:6:2], ctx.templates[:1], [1.0]),
        TypeError, r"genuine\[0\] must be an EarTemplate"),
    reject("open_set_rates matcher not fitted", lambda ctx: eb.open_set_rates(
        eb.EarMatcher(), ctx.templates[1::2], ctx.ids[1:6:2], ctx.templates[:1], [1.0]),
        ValueError, "EarMatcher is not fitted yet"),
    reject("rank_of_truth true_id not enrolled", lambda: eb.rank_of_truth([0.1, 0.5], [0, 1], 7),
           ValueError, "true_id 7 is not among enrolled_ids"),
    reject("rank_of_truth three scores two ids", lambda: eb.rank_of_truth([0.1, 0.5, 0.3], [0, 1], 1),
           ValueError, "enrolled_ids must be a 1-D sequence giving one subject per entry of scores"),
    reject("cumulative_match rank 0", lambda: eb.cumulative_match([0, 1], 3), ValueError, r"ranks must lie in \[1, inf\]"),
    reject("cumulative_match rank 1.5", lambda: eb.cumulative_match([1.5, 1], 3), ValueError,
           "ranks must hold whole numbers"),
    reject("genuine_impostor_separation query id not enrolled", lambda: eb.genuine_impostor_separation(
        np.eye(3), [0, 1, 2], [0, 1, 5]),
        ValueError, "every subject of query_ids must be in enrolled_ids"),
    reject("genuine_impostor_separation two rows three ids", lambda: eb.genuine_impostor_separation(
        np.eye(3)[:2], [0, 1, 2], [0, 1, 2]),
        ValueError, "query_ids must be a 1-D sequence giving one subject per row of distances"),
    reject("closed_set matcher already enrolled", lambda ctx: eb.closed_set(
        _enrolled(eb.EarMatcher(), ctx.templates), ctx.templates, ctx.ids[:6]),
        ValueError, r"matcher must be empty \(a fresh EarMatcher\)"),
    reject("hog_closed_set odd number of images", lambda ctx: eb.hog_closed_set(ctx.images[:5], ctx.ids[:5]),
           ValueError, "images and subject_ids must have the same even length"),
    reject("hog_closed_set ids of another length", lambda ctx: eb.hog_closed_set(ctx.images, ctx.ids[:4]),
           ValueError, "images and subject_ids must have the same even length"),
    reject("nuisance_study list for conditions", lambda: eb.nuisance_study(2, ["baseline"], rng=0),
           TypeError, "conditions must be a Mapping"),
    # --- the checks evaluation.py and plotting.py share with matcher.py and features.py name what they are given
    reject("check_subject_id None", lambda: check_subject_id(None, "who"), TypeError, "who"),
    reject("check_subject_id bool", lambda: check_subject_id(True, "who"), TypeError, "who"),
    reject("check_subject_id 1e308", lambda: check_subject_id(1e308, "who"), ValueError, "who"),
    reject("as_grey_image 1e308", lambda: eb.as_grey_image(np.full((9, 9), 1e308), "photo"), ValueError, "photo"),
    reject("check_subject_ids NaN", lambda: check_subject_ids([1, np.nan], "ids"), ValueError, r"ids\[1\]"),
    reject("check_images empty", lambda: check_images([], "pictures"), ValueError, "pictures"),
    reject("check_images 3x3 image", lambda: check_images([np.zeros((3, 3))], "pictures"),
           ValueError, r"pictures\[0\]"),
    reject("check_templates image", lambda ctx: check_templates([ctx.image], "gallery"), TypeError, "gallery"),
    reject("as_bool_image empty", lambda: as_bool_image(np.zeros((0, 5), bool), "edges"), ValueError, "edges"),
    reject("as_bool_image numbers", lambda: as_bool_image(np.zeros((5, 5)), "edges"), TypeError, "edges"),
    reject("moment_frame_fast numbers for a mask", lambda: moment_frame_fast(np.ones((9, 9)), (64, 64)),
           TypeError, "mask"),
    reject("moment_frame_fast shape of 3 numbers", lambda: moment_frame_fast(np.ones((9, 9), bool), (64, 64, 1)),
           ValueError, "shape"),
    # --- the rng convention: errors start with "rng", TypeError for a non-seed, ValueError for a negative seed
    *[reject(f"{name} rng {bad!r}", lambda draw=draw, bad=bad: draw(bad), error, "^rng must be")
      for name, draw in sorted(RNG_CALLS.items()) for bad, error in (("7", TypeError), (-1, ValueError))],
]


@pytest.mark.parametrize(("call", "error", "message"), REJECTIONS)
def test_rejections(request, call, error, message):
    check_rejection(request, call, error, message)
