"""Chapter 9: modal matching of pedobarography objects by finite-element modes and assignment.

Bastos & Tavares, AMDO 2004. A seeded synthetic pressure sequence of a foot stands in for the
recorded one; its analytic pressure field gives the truth of every node's partner.
"""

from amdo_lab.modal_matching.axial import AxialElement, axial_element
from amdo_lab.modal_matching.element import (
    MAX_CONDITION,
    MAX_COORDINATE_MM,
    RIGID_MODES,
    GaussianElement,
    gaussian_element,
    mean_spacing,
)
from amdo_lab.modal_matching.matching import (
    ALIGNMENTS,
    CONTOUR_BAR_REACH,
    ELEMENTS,
    SEARCHES,
    MatchResult,
    adcom,
    affinity_matrix,
    global_search,
    local_search,
    match_objects,
    mode_features,
    procrustes_alignment,
)
from amdo_lab.modal_matching.modes import ModalBasis, modal_analysis
from amdo_lab.modal_matching.peers import CPD_KINDS, match_coordinates, match_cpd
from amdo_lab.modal_matching.pedobarography import (
    LOAD_NAMES,
    PAPER_PAIRS,
    SURFACE_BOX_MM,
    ObjectPair,
    PedobarographySequence,
    correct_share,
    frame_pair,
    make_pedobarography_sequence,
    move_object,
    paper_pair,
)

__all__ = [
    "AxialElement",
    "axial_element",
    "MAX_CONDITION",
    "MAX_COORDINATE_MM",
    "RIGID_MODES",
    "GaussianElement",
    "gaussian_element",
    "mean_spacing",
    "ALIGNMENTS",
    "CONTOUR_BAR_REACH",
    "ELEMENTS",
    "SEARCHES",
    "MatchResult",
    "adcom",
    "affinity_matrix",
    "global_search",
    "local_search",
    "match_objects",
    "mode_features",
    "procrustes_alignment",
    "ModalBasis",
    "modal_analysis",
    "CPD_KINDS",
    "match_coordinates",
    "match_cpd",
    "LOAD_NAMES",
    "PAPER_PAIRS",
    "SURFACE_BOX_MM",
    "ObjectPair",
    "PedobarographySequence",
    "correct_share",
    "frame_pair",
    "make_pedobarography_sequence",
    "move_object",
    "paper_pair",
]

from amdo_lab.common.equations import with_equation_map as _with_equation_map  # noqa: E402
from amdo_lab.modal_matching.equations import EQUATIONS as _EQUATIONS, TEST_FILE as _TEST_FILE  # noqa: E402

__doc__ = _with_equation_map(__doc__, _EQUATIONS, _TEST_FILE)
