"""Chapter 4: the development-seed check behind the EarMatcher defaults (not the notebook's data).

The matcher's pixel settings for 256 x 256 images (closing 2, fragments >= 40 px, polyline
crossings with a 6-px dead band, 8-px spur pruning, 4 smoothing rounds) were chosen on two
development databases drawn from seeds 77 and 79 (60 easy subjects each); the notebook uses other
seeds. The invariance defaults (canonical frame from the silhouette, eq. 6 in that frame, steps 8-9
ranked by the point distance of F) were chosen on databases from seeds 5-8 (40 and 60 subjects, the
perpendicular captures' similarity copies and the yawed captures), compared with the rows "paper's
pipeline" to "eq. 6 on contour pixels" below. This script re-runs the comparison: the defaults and
one-at-a-time changes, each scored by the paper's rule (fraction of yawed queries given the right
subject) and by the relaxed ranking's rank-1 rate.

    .venv/bin/python benchmarks/dev_04_ear_defaults.py [--subjects 60] [--seeds 77 79]

Each row scores one variant on every seed; ``--json PATH`` writes the table.
"""

from __future__ import annotations

from _harness import Benchmark  # first: pins BLAS threads before numpy is imported

VARIANTS = {
    "defaults": {},
    "paper's pipeline": dict(frame="image", origin="contours", ranking="triples"),
    "image frame, points of F": dict(frame="image", origin="contours"),
    "canonical frame, triples": dict(ranking="triples"),
    "eq. 6 on contour pixels": dict(origin="contours"),
    "frame from contour pixels": dict(frame="contours"),
    "band 0": dict(band_px=0.0),
    "band 3": dict(band_px=3.0),
    "band 9": dict(band_px=9.0),
    "no spur pruning": dict(spur_length_px=0),
    "no smoothing": dict(polyline_smoothing=0),
    "closing 1": dict(closing=1),
    "fragments >= 20 px": dict(min_component_size=20),
    "pixel runs, min_gap 6": dict(crossings="pixels"),
    "literal pixel count": dict(crossings="pixels", min_gap_px=0.0),
}


def main() -> None:
    bench = Benchmark(__doc__)
    bench.parser.add_argument("--subjects", type=int, default=60, help="easy subjects per database (default 60)")
    bench.parser.add_argument("--seeds", type=int, nargs="+", default=[77, 79],
                              help="development database seeds (default 77 79)")
    args = bench.parse()
    import numpy as np

    from amdo_lab import ear_biometrics as eb

    np.seterr(all="raise")  # a silent NaN would corrupt the comparison
    databases = {seed: eb.generate_ear_database(args.subjects, 2, "easy", rng=seed) for seed in args.seeds}
    columns = [name for s in args.seeds for name in (f"seed {s} paper", f"seed {s} rank-1")]
    table = bench.table("variant", *columns,
                        title=f"{args.subjects} easy subjects per development seed, 256 px; paper = share of "
                              "queries the paper's rule names correctly, rank-1 = relaxed ranking")
    for name, change in VARIANTS.items():
        cells = []
        for seed, database in databases.items():
            templates = [eb.EarMatcher(**change).extract(image) for image in database.images]
            paper = eb.closed_set(eb.EarMatcher(**change), templates, database.subject_ids)
            relaxed = eb.closed_set(eb.EarMatcher(**change, max_count_violations=2), templates, database.subject_ids)
            cells += [round(float(paper.correct), 3), round(float(relaxed.rank1), 3)]
        table.add(name, *cells)
        print(f"{name} measured", flush=True)
    bench.note(f"chance rank-1 = {1 / args.subjects:.3f}")
    bench.finish()


if __name__ == "__main__":
    main()
