"""The equation map of chapter 4: each equation the notebook cites, its code and its test.

Shown by ``help(amdo_lab.ear_biometrics)``; checked by ``tests/test_equation_paths.py``.
"""

from __future__ import annotations

from amdo_lab.common.equations import EquationPath

TEST_FILE = "test_ear_biometrics.py"

EQUATIONS: dict[int, EquationPath] = {
    1: EquationPath(code='amdo_lab.ear_biometrics.contours.detect_contours_reference',
                    test='test_detect_contours_reference_equals_the_filtered_detector'),
    2: EquationPath(code='amdo_lab.ear_biometrics.contours.detect_contours_reference',
                    test='test_detect_contours_reference_equals_the_filtered_detector'),
    3: EquationPath(code='amdo_lab.ear_biometrics.contours.detect_contours_reference',
                    test='test_detect_contours_reference_equals_the_filtered_detector'),
    4: EquationPath(code='amdo_lab.ear_biometrics.contours.detect_contours_reference',
                    test='test_detect_contours_reference_equals_the_filtered_detector'),
    5: EquationPath(code='amdo_lab.ear_biometrics.contours.detect_contours_reference',
                    test='test_detect_contours_reference_equals_the_filtered_detector'),
    6: EquationPath(code='amdo_lab.ear_biometrics.circles.circle_features_reference',
                    test='test_reference_of_eqs_6_and_7_equals_the_vectorised_path'),
    7: EquationPath(code='amdo_lab.ear_biometrics.circles.circle_features_reference',
                    test='test_reference_of_eqs_6_and_7_equals_the_vectorised_path'),
    8: EquationPath(code='amdo_lab.ear_biometrics.skeleton.crossing_number',
                    test='test_crossing_number_endings_and_bifurcation'),
    9: EquationPath(code='amdo_lab.ear_biometrics.topology.topology_features',
                    test='test_topology_features_of_a_y_contour'),
}
