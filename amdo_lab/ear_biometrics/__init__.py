"""Chapter 4: ear biometrics with geometric features (Choraś, AMDO 2004).

Synthetic seeded ear images stand in for the paper's (unavailable) database. Beyond the paper, the
image is brought into a canonical frame (silhouette moments) before contour detection, and steps
8-9 rank the enrolled templates by the distance between the characteristic points of F.
"""

from amdo_lab.ear_biometrics.features import (
    CROSSING_READINGS,
    NORMALISATION_MODES,
    CircleFeatures,
    ContourTopology,
    Normalisation,
    TopologyFeatures,
    as_grey_image,
    canny_contours,
    circle_features,
    circle_features_reference,
    clean_contours,
    crossing_number,
    detect_contours,
    normalise_coordinates,
    prune_spurs,
    skeleton_graph,
    smooth_polylines,
    topology_features,
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
from amdo_lab.ear_biometrics.matcher import (
    EarMatcher,
    EarTemplate,
    HogNearestNeighbour,
    IdentificationResult,
    LbpNearestNeighbour,
    OpenSetRates,
    POINT_DISTANCE_CAP,
    RANKINGS,
    characteristic_points,
    cumulative_match,
    open_set_rates,
    point_distance,
    rank_of_truth,
    topology_similarity,
)
from amdo_lab.ear_biometrics.synthetic import (
    NUISANCE_FACTORS,
    CapturePose,
    EarDatabase,
    EarShape,
    draw_capture_pose,
    draw_ear_shape,
    ear_curves,
    generate_ear_database,
    load_ear_folder,
    render_ear,
)
from amdo_lab.ear_biometrics.evaluation import (
    ClosedSetResult,
    Separation,
    closed_set,
    distance_sum_gaps,
    genuine_impostor_separation,
    hog_closed_set,
    nuisance_study,
    peer_closed_set,
)
from amdo_lab.ear_biometrics.plotting import draw_circles, draw_topology

from amdo_lab.common.equations import with_equation_map as _with_equation_map  # noqa: E402
from amdo_lab.ear_biometrics.equations import EQUATIONS as _EQUATIONS, TEST_FILE as _TEST_FILE  # noqa: E402

__doc__ = _with_equation_map(__doc__, _EQUATIONS, _TEST_FILE)
