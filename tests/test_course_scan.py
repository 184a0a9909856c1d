"""The scan of a student's cells: what rebinds the checking machinery is flagged, ordinary answers are not."""

from __future__ import annotations

import pytest

from amdo_lab.course.scan import scan_source

MODULES = {"np", "plt"}


@pytest.mark.parametrize("source", [
    "answer_1 = 0.0314",
    "import numpy as np\nimport math\nx = np.sqrt(2) * math.pi",
    "step = 5\nexperiment_2 = simulated_rms(outline[::step], moved[::step], noise_sigma, rng=11)\nprint(experiment_2)",
    "def my_scale(source, target):\n    x = source - source.mean(axis=0)\n    return float(x.sum())\nanswer_4 = my_scale",
    "from amdo_lab.common import procrustes_align as fit\nfig, ax = plt.subplots()\nfig.tight = True",
    "%matplotlib inline\nanswer_3 = '12 points'",
    "this is not python (",
])
def test_ordinary_answers_are_not_flagged(source):
    assert scan_source(source, MODULES) == []


@pytest.mark.parametrize(("source", "found"), [
    ("class F:\n    def check(self, *a):\n        print('correct')\nEXERCISES = F()", "rebinds EXERCISES"),
    ("EXERCISES.check = print", "assigns EXERCISES.check"),
    ("import builtins\nbuiltins.abs = lambda x: 0", "imports builtins"),
    ("import builtins\nbuiltins.abs = lambda x: 0", "assigns builtins.abs"),
    ("import math\nmath.isclose = lambda *a, **k: True", "assigns math.isclose"),
    ("np.isclose = lambda *a, **k: True", "assigns np.isclose"),
    ("abs = lambda x: 0", "rebinds abs"),
    ("def print(*a):\n    pass", "rebinds print"),
    ("import sys\nsys.modules['amdo_lab'] = None", "touches sys.modules"),
    ("import amdo_lab.common.exercises as ex\nex.judge_answer = lambda *a, **k: 'correct'", "assigns ex.judge_answer"),
    ("setattr(EXERCISES, 'check', print)", "calls setattr()"),
    ("exec('EXERCISES = 1')", "calls exec()"),
    ("globals()['EXERCISES'] = None", "assigns globals()['EXERCISES']"),
    ("get_ipython().events.register('post_run_cell', print)", "calls get_ipython()"),
    ("import json as np", "rebinds np by an import"),
])
def test_tampering_is_flagged(source, found):
    assert found in scan_source(source, MODULES)
