"""Chapter 4: ear biometrics with geometric features (Choraś, AMDO 2004).

Synthetic seeded ear images stand in for the paper's (unavailable) database. Beyond the paper, the
image is brought into a canonical frame (silhouette moments) before contour detection, and steps
8-9 rank the enrolled templates by the distance between the characteristic points of F.

One module per step: ``images`` (the inputs), ``contours`` (eqs. 1-5), ``normalisation`` (eq. 6),
``circles`` (V, eq. 7), ``skeleton`` (eq. 8 and the thinned contours), ``topology`` (F, eq. 9),
``frame`` (the canonical frame), ``matcher`` (Sec. 5, steps 1-9), ``peers`` (HOG and LBP),
``enrolment`` (subject ids and ``fit``), ``evaluation`` (Sec. 6), ``synthetic`` (the data) and
``plotting``.
"""

from amdo_lab.ear_biometrics.circles import (CROSSING_READINGS, CircleFeatures, circle_features,
                                             circle_features_reference, contour_crossings)
from amdo_lab.ear_biometrics.contours import canny_contours, clean_contours, detect_contours, detect_contours_reference
from amdo_lab.ear_biometrics.evaluation import (
    ClosedSetResult,
    OpenSetRates,
    Separation,
    closed_set,
    cumulative_match,
    genuine_impostor_separation,
    hog_closed_set,
    nuisance_study,
    open_set_rates,
    peer_closed_set,
    rank_of_truth,
)
from amdo_lab.ear_biometrics.frame import (
    CANONICAL_SPREAD,
    FRAME_SOURCES,
    CanonicalFrame,
    frame_normalisation,
    moment_frame,
    silhouette,
    similarity_copy,
    to_canonical,
)
from amdo_lab.ear_biometrics.images import as_grey_image
from amdo_lab.ear_biometrics.matcher import (
    OUR_SETTINGS,
    PAPER_SETTINGS,
    PAPER_WITH_OUR_READINGS,
    POINT_DISTANCE_CAP,
    RANKINGS,
    EarMatcher,
    EarTemplate,
    IdentificationResult,
    MatcherSettings,
    characteristic_points,
    point_distance,
    topology_similarity,
)
from amdo_lab.ear_biometrics.normalisation import NORMALISATION_MODES, Normalisation, normalise_coordinates
from amdo_lab.ear_biometrics.peers import HogNearestNeighbour, LbpNearestNeighbour
from amdo_lab.ear_biometrics.plotting import draw_circles, draw_topology
from amdo_lab.ear_biometrics.skeleton import (EQ8_READINGS, connectivity_number, crossing_number, prune_spurs,
                                              skeleton_graph, smooth_polylines, thin_contours)
from amdo_lab.ear_biometrics.synthetic import (
    NUISANCE_FACTORS,
    CapturePose,
    EarDatabase,
    EarShape,
    draw_capture_pose,
    draw_ear_shape,
    ear_curves,
    load_ear_folder,
    make_ear_database,
    render_ear,
)
from amdo_lab.ear_biometrics.topology import ContourTopology, TopologyFeatures, topology_features

__all__ = [
    # inputs and step 1: contours (eqs. 1-5)
    "as_grey_image", "detect_contours", "detect_contours_reference", "clean_contours", "canny_contours",
    # eq. 6
    "NORMALISATION_MODES", "Normalisation", "normalise_coordinates",
    # V (eq. 7)
    "CROSSING_READINGS", "CircleFeatures", "circle_features", "circle_features_reference", "contour_crossings",
    # the thinned contours and eq. 8
    "thin_contours", "EQ8_READINGS", "crossing_number", "connectivity_number", "prune_spurs", "skeleton_graph", "smooth_polylines",
    # F (eq. 9)
    "ContourTopology", "TopologyFeatures", "topology_features",
    # the canonical frame
    "CANONICAL_SPREAD", "FRAME_SOURCES", "CanonicalFrame", "silhouette", "moment_frame", "to_canonical",
    "frame_normalisation", "similarity_copy",
    # classification (Sec. 5) and the peers
    "POINT_DISTANCE_CAP", "RANKINGS", "EarTemplate", "IdentificationResult", "MatcherSettings", "PAPER_SETTINGS", "PAPER_WITH_OUR_READINGS",
    "OUR_SETTINGS", "EarMatcher", "characteristic_points",
    "point_distance", "topology_similarity", "HogNearestNeighbour", "LbpNearestNeighbour",
    # evaluation (Sec. 6)
    "ClosedSetResult", "OpenSetRates", "Separation", "closed_set", "peer_closed_set", "hog_closed_set",
    "open_set_rates", "rank_of_truth", "cumulative_match", "genuine_impostor_separation",
    "nuisance_study",
    # the synthetic ears
    "NUISANCE_FACTORS", "EarShape", "CapturePose", "EarDatabase", "draw_ear_shape", "draw_capture_pose",
    "ear_curves", "render_ear", "make_ear_database", "load_ear_folder",
    # figures
    "draw_circles", "draw_topology",
]

from amdo_lab.common.equations import with_equation_map as _with_equation_map  # noqa: E402
from amdo_lab.ear_biometrics.equations import EQUATIONS as _EQUATIONS, TEST_FILE as _TEST_FILE  # noqa: E402

__doc__ = _with_equation_map(__doc__, _EQUATIONS, _TEST_FILE)
