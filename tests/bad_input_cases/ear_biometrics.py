"""Bad-input table of ``amdo_lab.ear_biometrics``: a valid call and the kind of each argument.

The valid inputs are small (64 x 64 synthetic ears, three subjects) so that a spoiled call that is
wrongly accepted stays cheap.
"""

from __future__ import annotations

import atexit
import copy
import functools
import shutil
import tempfile
from pathlib import Path

import numpy as np

from bad_input_cases._core import Case

#: (callable, argument, spoiled label) calls known to fail the test, with the reason; each must
#: still fail (remove it once fixed).
KNOWN_FAILURES: dict[tuple[str, str, str], str] = {}

#: Public names not called with user input, with the reason.
EXEMPT = {
    "CanonicalFrame": "a result record, built by moment_frame from checked input",
    "CircleFeatures": "a result record, built by circle_features from checked input",
    "ClosedSetResult": "a result record, built by closed_set from checked input",
    "ContourTopology": "a result record, built by topology_features from checked input",
    "EarDatabase": "a result record, built by make_ear_database from checked input",
    "EarTemplate": "a result record, built by EarMatcher.extract from checked input",
    "IdentificationResult": "a result record, built by EarMatcher.identify from checked input",
    "OpenSetRates": "a result record, built by open_set_rates from checked input",
    "Separation": "a result record, built by genuine_impostor_separation from checked input",
    "TopologyFeatures": "a result record, built by topology_features from checked input",
    "Normalisation": "a result record, built by normalise_coordinates; its methods are tabled",
}


@functools.cache
def _context():
    """Small shared inputs, made once per process."""
    import types

    import cv2
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from amdo_lab import ear_biometrics as eb

    images, ids = eb.make_ear_database(3, 2, "easy", rng=0, size=64)
    contours = eb.clean_contours(eb.detect_contours(images[0]))
    features = eb.topology_features(contours)
    other = eb.topology_features(eb.clean_contours(eb.detect_contours(images[1])))
    matcher = eb.EarMatcher()
    templates = [matcher.extract(image) for image in images]
    matcher.fit(images[0::2], ids[0::2])
    baseline = eb.HogNearestNeighbour().fit(images[0::2], ids[0::2])
    lbp = eb.LbpNearestNeighbour().fit(images[0::2], ids[0::2])
    folder = Path(tempfile.mkdtemp(prefix="ears"))
    atexit.register(shutil.rmtree, folder, True)
    cv2.imwrite(str(folder / "001_a.png"), np.full((16, 16), 100, np.uint8))
    skeleton = eb.prune_spurs(features.skeleton, 0) if features.skeleton.any() else features.skeleton
    nodes, edges = eb.skeleton_graph(skeleton)
    mask = eb.silhouette(images[0])
    frame = eb.moment_frame(mask, images[0].shape)
    figure, axes = plt.subplots()
    return types.SimpleNamespace(
        images=images, ids=ids, contours=contours, features=features, other=other, matcher=matcher,
        templates=templates, baseline=baseline, lbp=lbp, folder=folder, skeleton=skeleton, nodes=nodes, edges=edges,
        mask=mask, frame=frame, axes=axes, shape=eb.draw_ear_shape(rng=0),
        pose=eb.CapturePose(0.0, 1.0, np.zeros(2), 0.0), norm=eb.normalise_coordinates(contours))


def cases() -> dict[str, Case]:
    """The public callables of ``amdo_lab.ear_biometrics``, by name."""
    from amdo_lab import ear_biometrics as eb

    c = _context()
    image = c.images[0]
    scores = np.array([0.1, 0.5, 0.3])
    ids3 = np.array([0, 1, 2])
    # a 64 x 65 image (or contour image, or stack of them) is as valid as a 64 x 64 one
    other_size = {"a wrong trailing axis"}
    # counts whose documented range starts at 0 (0 switches the step off)
    zero_ok = {"zero"}

    def ok(**labels):
        return frozenset((argument, label) for argument, names in labels.items() for label in names)

    def closed_set(matcher, templates, subject_ids):  # closed_set enrols into the matcher: a fresh copy each call
        return eb.closed_set(copy.deepcopy(matcher) if isinstance(matcher, eb.EarMatcher) else matcher,
                             templates, subject_ids)

    def matcher_method(name):
        def call(**kwargs):
            return getattr(c.matcher, name)(**kwargs)
        return call

    def baseline_method(name):
        def call(**kwargs):
            return getattr(eb.HogNearestNeighbour().fit(c.images[0::2], c.ids[0::2]), name)(**kwargs)
        return call

    def fresh_matcher(name):
        def call(**kwargs):
            return getattr(eb.EarMatcher(), name)(**kwargs)
        return call

    def fresh_baseline(name):
        def call(**kwargs):
            return getattr(eb.HogNearestNeighbour(), name)(**kwargs)
        return call

    return {
        # features
        "as_grey_image": Case(eb.as_grey_image, {"image": image, "name": "image"}, {"image": "image", "name": "name"},
                  accept=ok(image=other_size)),
        "detect_contours": Case(eb.detect_contours, {"image": image, "k": 8.0, "window": 3},
                                {"image": "image", "k": "non_negative", "window": "count"},
                  accept=ok(image=other_size)),
        "detect_contours_reference": Case(eb.detect_contours_reference, {"image": image[:16, :16], "k": 8.0, "window": 3},
                                          {"image": "image", "k": "non_negative", "window": "count"},
                  accept=ok(image=other_size)),
        "clean_contours": Case(eb.clean_contours, {"contours": c.contours, "min_size": 20, "closing": 1},
                               {"contours": "bool_array", "min_size": "count", "closing": "count"},
                  accept=ok(contours=other_size, closing=zero_ok)),
        "canny_contours": Case(eb.canny_contours, {"image": image}, {"image": "image"},
                  accept=ok(image=other_size)),
        "normalise_coordinates": Case(eb.normalise_coordinates, {"contours": c.contours, "mode": "principal"},
                                      {"contours": "bool_array", "mode": "object"}),
        "Normalisation.to_normalised": Case(lambda rows_cols: c.norm.to_normalised(rows_cols),
                                            {"rows_cols": np.array([[10.0, 12.0], [30.0, 20.0]])},
                                            {"rows_cols": "points"},
                  accept=ok(rows_cols={"an empty array"})),  # no points in, no points out
        "Normalisation.to_pixels": Case(lambda xy: c.norm.to_pixels(xy), {"xy": np.array([[0.1, 0.2], [-0.3, 0.4]])},
                                        {"xy": "points"},
                  accept=ok(xy={"an empty array"})),  # no points in, no points out
        "circle_features": Case(eb.circle_features,
                                {"contours": c.contours, "n_circles": 4, "step": 0.25, "mode": "principal",
                                 "min_gap_px": 0.0, "crossings": "pixels", "polyline_smoothing": 2, "band_px": 0.0,
                                 "spur_length_px": 0},
                                {"contours": "bool_array", "n_circles": "count", "step": "positive", "mode": "object",
                                 "min_gap_px": "non_negative", "crossings": "object", "polyline_smoothing": "count",
                                 "band_px": "non_negative", "spur_length_px": "count"},
                  accept=ok(contours=other_size, polyline_smoothing=zero_ok, spur_length_px=zero_ok)),
        "circle_features_reference": Case(eb.circle_features_reference,
                                          {"contours": c.contours, "n_circles": 4, "step": 0.25},
                                          {"contours": "bool_array", "n_circles": "count", "step": "positive"}),
        "contour_crossings": Case(eb.contour_crossings,
                                  {"points": np.array([[0.5, 0.0], [1.5, 0.0], [0.98, 0.05], [1.5, 0.2]]),
                                   "radii": np.array([1.0, 1.2]), "band": 0.05},
                                  {"points": "points", "radii": "array", "band": "non_negative"}),
        "thin_contours": Case(eb.thin_contours, {"contours": c.contours}, {"contours": "bool_array"},
                  accept=ok(contours=other_size)),
        "connectivity_number": Case(eb.connectivity_number, {"skeleton": c.skeleton}, {"skeleton": "bool_array"},
                  accept=ok(skeleton=other_size)),
        "crossing_number": Case(eb.crossing_number, {"skeleton": c.skeleton}, {"skeleton": "bool_array"},
                  accept=ok(skeleton=other_size)),
        "skeleton_graph": Case(eb.skeleton_graph, {"skeleton": c.skeleton}, {"skeleton": "bool_array"},
                  accept=ok(skeleton=other_size)),
        "smooth_polylines": Case(eb.smooth_polylines, {"nodes": c.nodes, "edges": c.edges, "n_iter": 2},
                                 {"nodes": "points", "edges": "array", "n_iter": "count"},
                  accept=ok(edges={"an empty array"}, n_iter=zero_ok)),  # isolated nodes; no smoothing
        "prune_spurs": Case(eb.prune_spurs, {"skeleton": c.skeleton, "length_px": 4},
                            {"skeleton": "bool_array", "length_px": "count"},
                  accept=ok(skeleton=other_size, length_px=zero_ok)),
        # a given skeleton and frame (the call above thins and frames the contours itself)
        "circle_features (given skeleton)": Case(
            eb.circle_features, {"contours": c.contours, "n_circles": 4, "step": 0.25, "skeleton": c.contours,
                                 "normalisation": None},
            {"skeleton": "bool_array", "normalisation": "object"},
            accept=frozenset({("normalisation", "None"), ("skeleton", "None")})),  # None: computed
        "topology_features (given frame)": Case(
            eb.topology_features, {"contours": c.contours, "n_circles": 4, "step": 0.25, "normalisation": None},
            {"normalisation": "object"}, accept=frozenset({("normalisation", "None")})),
        "topology_features": Case(eb.topology_features,
                                  {"contours": c.contours, "n_circles": 4, "step": 0.25, "mode": "principal",
                                   "min_gap_px": 0.0, "crossings": "pixels", "polyline_smoothing": 2, "band_px": 0.0,
                                   "spur_length_px": 0, "eq8": "yokoi"},
                                  {"contours": "bool_array", "n_circles": "count", "step": "positive",
                                   "mode": "object", "min_gap_px": "non_negative", "crossings": "object",
                                   "polyline_smoothing": "count", "band_px": "non_negative",
                                   "spur_length_px": "count", "eq8": "object"},
                  accept=ok(contours=other_size, polyline_smoothing=zero_ok, spur_length_px=zero_ok)),
        # frame
        "silhouette": Case(eb.silhouette, {"image": image}, {"image": "image"},
                  accept=ok(image=other_size)),
        "moment_frame": Case(eb.moment_frame, {"mask": c.mask, "shape": (64, 64)},
                             {"mask": "bool_array", "shape": "array"}),
        "to_canonical": Case(eb.to_canonical, {"image": image, "frame": c.frame},
                             {"image": "image", "frame": "object"},
                  accept=ok(image=other_size)),
        "frame_normalisation": Case(eb.frame_normalisation,
                                    {"frame": c.frame, "shape": (64, 64), "mode": "principal"},
                                    {"frame": "object", "shape": "array", "mode": "object"}),
        "similarity_copy": Case(eb.similarity_copy,
                                {"image": image, "rng": 0, "max_rotation_deg": 25.0, "scale_range": (0.85, 1.15),
                                 "max_shift_px": 8.0, "rotation_deg": None},
                                {"image": "image", "rng": "seed", "max_rotation_deg": "non_negative",
                                 "scale_range": "array", "max_shift_px": "non_negative", "rotation_deg": "real"},
                  accept=ok(image=other_size) | {("rotation_deg", "None")}),  # None: a drawn rotation
        # matcher
        "topology_similarity": Case(eb.topology_similarity,
                                    {"query": c.features, "reference": c.other},
                                    {"query": "object", "reference": "object"}),
        "characteristic_points": Case(eb.characteristic_points, {"features": c.features}, {"features": "object"}),
        "point_distance": Case(eb.point_distance, {"query": c.features, "reference": c.other},
                               {"query": "object", "reference": "object"}),
        "EarMatcher": Case(eb.EarMatcher, {"settings": eb.OUR_SETTINGS}, {"settings": "object"}),
        "MatcherSettings": Case(eb.MatcherSettings,
                           {"k": 8.0, "smoothing": 0.0, "n_circles": 8, "step": 0.25,
                            "min_component_size": 40, "closing": 2,
                            "max_count_violations": 0, "distance_threshold": 1.0,
                            "mode": "principal", "min_gap_px": 6.0, "crossings": "polyline",
                            "polyline_smoothing": 4, "band_px": 6.0, "spur_length_px": 8, "frame": "silhouette",
                            "origin": "frame", "ranking": "points", "eq8": "crossing"},
                           {"k": "non_negative", "smoothing": "non_negative", "n_circles": "count",
                            "step": "positive", "min_component_size": "count", "closing": "count",
                            "max_count_violations": "count", "distance_threshold": "non_negative",
                            "mode": "object", "min_gap_px": "non_negative", "crossings": "object",
                            "polyline_smoothing": "count", "band_px": "non_negative", "spur_length_px": "count",
                            "frame": "object", "origin": "object", "eq8": "object",
                            "ranking": "object"},
                  accept=ok(closing=zero_ok, max_count_violations=zero_ok,
                            polyline_smoothing=zero_ok, spur_length_px=zero_ok,
                            distance_threshold={"inf"})),  # inf: no threshold
        "EarMatcher.canonical_frame": Case(matcher_method("canonical_frame"), {"image": image}, {"image": "image"}),
        "EarMatcher.canonical_image": Case(matcher_method("canonical_image"), {"image": image}, {"image": "image"}),
        "EarMatcher.contour_image": Case(matcher_method("contour_image"), {"image": image}, {"image": "image"}),
        "EarMatcher.extract": Case(matcher_method("extract"), {"image": image}, {"image": "image"}),
        "EarMatcher.enroll": Case(fresh_matcher("enroll"), {"subject_id": 5, "image": image},
                                  {"subject_id": "real", "image": "image"},
                  accept=ok(subject_id={"a string"})),  # ids may be names
        "EarMatcher.enroll_template": Case(fresh_matcher("enroll_template"),
                                           {"subject_id": 5, "template": c.templates[0]},
                                           {"subject_id": "real", "template": "record"},
                  accept=ok(subject_id={"a string"})),
        "EarMatcher.fit": Case(fresh_matcher("fit"), {"images": c.images[0::2], "subject_ids": c.ids[0::2]},
                               {"images": "array", "subject_ids": "array"}),
        "EarMatcher.identify": Case(matcher_method("identify"), {"image": c.images[1]}, {"image": "image"},
                  accept=ok(image=other_size)),  # the matcher's features are size-free
        "EarMatcher.identify_template": Case(matcher_method("identify_template"),
                                             {"query": c.templates[1]}, {"query": "record"}),
        # scikit-learn's contract: parameters are stored as given and checked where they are used
        "HogNearestNeighbour": Case(lambda pixels_per_cell: eb.HogNearestNeighbour(pixels_per_cell).describe(image),
                                    {"pixels_per_cell": 16}, {"pixels_per_cell": "count"}),
        "HogNearestNeighbour.describe": Case(lambda image: c.baseline.describe(image), {"image": image},
                                             {"image": "image"},
                  accept=ok(image=other_size)),
        "HogNearestNeighbour.enroll": Case(baseline_method("enroll"), {"subject_id": 5, "image": c.images[1]},
                                           {"subject_id": "real", "image": "image"},
                  accept=ok(subject_id={"a string"})),
        "HogNearestNeighbour.fit": Case(fresh_baseline("fit"), {"images": c.images[0::2], "subject_ids": c.ids[0::2]},
                                        {"images": "array", "subject_ids": "array"},
                  accept=ok(images=other_size)),  # three 64 x 65 images
        "HogNearestNeighbour.distances": Case(lambda image: c.baseline.distances(image), {"image": c.images[1]},
                                              {"image": "image"}),
        "HogNearestNeighbour.identify": Case(lambda image: c.baseline.identify(image), {"image": c.images[1]},
                                             {"image": "image"}),
        "LbpNearestNeighbour": Case(lambda cells_per_side, radius, blur_sigma: eb.LbpNearestNeighbour(
                                        cells_per_side, radius, blur_sigma).describe(image),
                                    {"cells_per_side": 8, "radius": 1, "blur_sigma": 3.0},
                                    {"cells_per_side": "count", "radius": "count", "blur_sigma": "non_negative"}),
        "LbpNearestNeighbour.describe": Case(lambda image: eb.LbpNearestNeighbour().describe(image), {"image": image},
                                             {"image": "image"},
                  accept=ok(image=other_size)),
        "LbpNearestNeighbour.enroll": Case(lambda **kw: eb.LbpNearestNeighbour().fit(c.images[0::2], c.ids[0::2]).enroll(**kw),
                                           {"subject_id": 5, "image": c.images[1]},
                                           {"subject_id": "real", "image": "image"},
                  accept=ok(subject_id={"a string"})),
        "LbpNearestNeighbour.fit": Case(lambda **kw: eb.LbpNearestNeighbour().fit(**kw),
                                        {"images": c.images[0::2], "subject_ids": c.ids[0::2]},
                                        {"images": "array", "subject_ids": "array"},
                  accept=ok(images=other_size)),
        "LbpNearestNeighbour.distances": Case(lambda image: c.lbp.distances(image), {"image": c.images[1]},
                                              {"image": "image"}),
        "LbpNearestNeighbour.identify": Case(lambda image: c.lbp.identify(image), {"image": c.images[1]},
                                             {"image": "image"}),
        "open_set_rates": Case(eb.open_set_rates,
                               {"matcher": c.matcher, "genuine": c.templates[1::2], "genuine_ids": c.ids[1::2],
                                "impostors": c.templates[:1], "thresholds": np.array([0.5, 1.0])},
                               {"matcher": "object", "genuine": "object", "genuine_ids": "array",
                                "impostors": "object", "thresholds": "array"},
                  accept=ok(thresholds={"a wrong trailing axis", "inf inside"})),  # three thresholds; inf: no threshold
        "rank_of_truth": Case(eb.rank_of_truth, {"scores": scores, "enrolled_ids": ids3, "true_id": 1},
                              {"scores": "array", "enrolled_ids": "array", "true_id": "real"}),
        "cumulative_match": Case(eb.cumulative_match, {"ranks": np.array([1, 2, 1]), "max_rank": 3},
                                 {"ranks": "array", "max_rank": "count"}),
        # synthetic
        "draw_ear_shape": Case(eb.draw_ear_shape, {"rng": 0}, {"rng": "seed"}),
        "draw_capture_pose": Case(eb.draw_capture_pose,
                                  {"rng": 0, "frontal": False, "size": 64, "difficulty": "easy"},
                                  {"rng": "seed", "frontal": "flag", "size": "count", "difficulty": "object"}),
        "EarShape": Case(eb.EarShape, dict(vars(c.shape)),
                         {name: "array" if np.ndim(value) else "real" for name, value in vars(c.shape).items()}),
        "CapturePose": Case(eb.CapturePose, {"rotation": 0.3, "scale": 1.0, "translation": np.zeros(2), "yaw": 0.2},
                            {"rotation": "real", "scale": "positive", "translation": "array", "yaw": "real"}),
        "ear_curves": Case(eb.ear_curves, {"shape": c.shape}, {"shape": "object"}),
        "render_ear": Case(eb.render_ear,
                           {"shape": c.shape, "pose": c.pose, "rng": 0, "difficulty": "easy", "size": 64,
                            "disable": ()},
                           {"shape": "object", "pose": "object", "rng": "seed", "difficulty": "object",
                            "size": "count", "disable": "object"}),
        "make_ear_database": Case(eb.make_ear_database,
                                      {"n_subjects": 1, "images_per_subject": 1, "difficulty": "easy", "rng": 0,
                                       "size": 64, "disable": ()},
                                      {"n_subjects": "count", "images_per_subject": "count",
                                       "difficulty": "object", "rng": "seed", "size": "count",
                                       "disable": "object"}),
        "load_ear_folder": Case(eb.load_ear_folder, {"folder": c.folder, "size": 16},
                                {"folder": "object", "size": "count"},
                  accept=ok(size={"None"})),  # None: keep each image's size
        # evaluation
        "genuine_impostor_separation": Case(eb.genuine_impostor_separation,
                                            {"distances": np.array([[0.1, 0.9], [0.8, 0.2]]),
                                             "enrolled_ids": np.array([0, 1]), "query_ids": np.array([0, 1])},
                                            {"distances": "array", "enrolled_ids": "array", "query_ids": "array"}),
        "closed_set": Case(closed_set,
                           {"matcher": eb.EarMatcher(), "templates": c.templates, "subject_ids": c.ids},
                           {"matcher": "object", "templates": "object", "subject_ids": "array"}),
        "hog_closed_set": Case(eb.hog_closed_set, {"images": c.images, "subject_ids": c.ids, "pixels_per_cell": 16},
                               {"images": "array", "subject_ids": "array", "pixels_per_cell": "count"},
                  accept=ok(images=other_size, pixels_per_cell={"None"})),  # None: an eighth of the side
        "peer_closed_set": Case(eb.peer_closed_set, {"images": c.images, "subject_ids": c.ids,
                                                     "baseline": eb.LbpNearestNeighbour()},
                                {"images": "array", "subject_ids": "array", "baseline": "object"},
                  accept=ok(images=other_size, baseline={"None"})),  # None: HOG
        "nuisance_study": Case(eb.nuisance_study,
                               {"n_subjects": 2, "conditions": {"a": ()}, "rng": 0, "size": 64},
                               {"n_subjects": "count", "conditions": "object", "rng": "seed", "size": "count"}),
        # plots
        "draw_circles": Case(eb.draw_circles,
                             {"ax": c.axes, "contours": c.contours, "features": c.features.circles,
                              "show_crossings": False},
                             {"ax": "object", "contours": "bool_array", "features": "object",
                              "show_crossings": "flag"},
                             accept=ok(contours=other_size)),
        "draw_topology": Case(eb.draw_topology, {"ax": c.axes, "features": c.features},
                              {"ax": "object", "features": "object"}),
    }
