"""Chapter 4 benchmark: feature extraction and identification times of Choraś's geometric method
(contours eqs. 1-5, V eq. 7, F eq. 9, Sec. 5 matcher) versus the HOG + 1-NN baseline.

Goals from the issue: features of a 256x256 image in under 20 ms; identification against 240
enrolled images in under 5 ms per query.

    .venv/bin/python benchmarks/bench_04_ear_biometrics.py [--size 256] [--enrolled 240] [--queries 40] [--seed 2004]

BLAS is limited to one thread (set before numpy is imported) so the timing is single-core.
"""

from __future__ import annotations

import os

for _variable in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from amdo_lab import ear_biometrics as eb  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--size", type=int, default=256)
    parser.add_argument("--enrolled", type=int, default=240)
    parser.add_argument("--queries", type=int, default=40)
    parser.add_argument("--seed", type=int, default=2004)
    args = parser.parse_args()
    database = eb.generate_ear_database(args.enrolled, 2, "easy", args.seed, size=args.size)
    gallery = database.images[0::2]
    gallery_ids = database.subject_ids[0::2]
    queries = database.images[1::2][: args.queries]
    ours, baseline = eb.EarMatcher(), eb.HogNearestNeighbour(pixels_per_cell=args.size // 8)

    start = time.perf_counter()
    templates = [ours.extract(image) for image in gallery]
    ours_extract = (time.perf_counter() - start) / len(gallery)
    for subject, template in zip(gallery_ids, templates):
        ours.enroll_template(subject, template)
    start = time.perf_counter()
    for image in gallery:
        baseline.enroll(gallery_ids[len(baseline._ids)], image)
    hog_extract = (time.perf_counter() - start) / len(gallery)

    relaxed = eb.EarMatcher(max_count_violations=2)  # more candidates reach the topology step
    for subject, template in zip(gallery_ids, templates):
        relaxed.enroll_template(subject, template)
    query_templates = [ours.extract(image) for image in queries]
    identify = {}
    for name, matcher in (("paper", ours), ("relaxed", relaxed)):
        start = time.perf_counter()
        for template in query_templates:
            matcher.identify_template(template)
        identify[name] = (time.perf_counter() - start) / len(queries)
    ours_identify = max(identify.values())
    query_hogs = [baseline.describe(image) for image in queries]
    start = time.perf_counter()
    for descriptor in query_hogs:
        int(np.argmin(np.linalg.norm(baseline._matrix - descriptor, axis=1)))
    hog_identify = (time.perf_counter() - start) / len(queries)

    print(f"{args.size}x{args.size} images, {len(gallery)} enrolled, {len(queries)} queries, one BLAS thread")
    print(f"{'method':28s} {'features ms':>12s} {'identify ms':>12s} {'features / ours':>16s}")
    for name, extract_s, identify_s in [("Choras, paper rule (ours)", ours_extract, identify["paper"]),
                                        ("Choras, relaxed rule (ours)", ours_extract, identify["relaxed"]),
                                        ("HOG + 1-NN (skimage)", hog_extract, hog_identify)]:
        print(f"{name:28s} {1e3 * extract_s:12.2f} {1e3 * identify_s:12.3f} {extract_s / ours_extract:16.2f}")
    print(f"goals: features < 20 ms -> {'met' if ours_extract < 0.020 else 'NOT met'}; "
          f"identification < 5 ms -> {'met' if ours_identify < 0.005 else 'NOT met'}")


if __name__ == "__main__":
    main()
