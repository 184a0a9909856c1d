"""Chapter 4: the development-seed check behind the EarMatcher defaults (not the notebook's data).

The matcher's pixel settings for 256 x 256 images (closing 2, fragments >= 40 px, polyline
crossings with a 6-px dead band, 8-px spur pruning, 4 smoothing rounds) were chosen on two
development databases drawn from seeds 77 and 79 (60 easy subjects each); the notebook uses other
seeds. The invariance defaults (canonical frame from the silhouette, eq. 6 in that frame, steps 8-9
ranked by the point distance of F) were chosen on databases from seeds 5-8 (40 and 60 subjects, the
perpendicular captures' similarity copies and the yawed captures), compared with the rows "paper's
pipeline" to "eq. 6 on contour pixels" below. The blur before eqs. 1-5 (1.5 px, with k = 12 in
place of 8) was added for invariance (``--invariance`` below); on these seeds it keeps rank-1 and
costs the paper's rule a few queries (rows "defaults" and "no blur, k 8"). This script re-runs the
comparison: the defaults and one-at-a-time changes, each scored by the paper's rule (fraction of
yawed queries given the right subject) and by the relaxed ranking's rank-1 rate.

    .venv/bin/python benchmarks/dev_04_ear_defaults.py [--subjects 60] [--seeds 77 79]

Each row scores one variant on every seed; ``--json PATH`` writes the table.

``--invariance`` measures instead what the chapter's invariance table measures, on other seeds: for
each subject a perpendicular reference capture (drawn at ``--reference-scale``), a second capture with
new sensor noise only, and a random similarity copy of the reference itself (rotation within +-25
degrees or any angle, scale 0.85-1.15, shift up to 8 px). Printed per variant and seed set: the mean
change of l_r, sum d and the point distance D of F under the copy, divided by the mean change under new
noise (below 1: the similarity moves the features less than new noise does). The blur default
(smoothing 1.5, k 12) was chosen on seed sets 11-13 (40 subjects each) at scales 0.85 and 1.

    .venv/bin/python benchmarks/dev_04_ear_defaults.py --invariance [--invariance-sets 11:40 12:40 13:40] [--reference-scale 0.85]
"""

from __future__ import annotations

from _harness import Benchmark  # first: pins BLAS threads before numpy is imported

VARIANTS = {
    "defaults": {},
    "paper's pipeline": dict(frame="image", origin="contours", ranking="triples", smoothing=0.0, k=8.0),
    "no blur, k 8": dict(smoothing=0.0, k=8.0),
    "blur 1.5, k 8": dict(k=8.0),
    "blur 1, k 12": dict(smoothing=1.0),
    "blur 2, k 12": dict(smoothing=2.0),
    "image frame, points of F": dict(frame="image", origin="contours"),
    "canonical frame, triples": dict(ranking="triples"),
    "eq. 6 on contour pixels": dict(origin="contours"),
    "frame from contour pixels": dict(frame="contours"),
    "band 0": dict(band_px=0.0),
    "band 3": dict(band_px=3.0),
    "band 9": dict(band_px=9.0),
    "no spur pruning": dict(spur_length_px=0),
    "no polyline smoothing": dict(polyline_smoothing=0),
    "closing 1": dict(closing=1),
    "fragments >= 20 px": dict(min_component_size=20),
    "pixel runs, min_gap 6": dict(crossings="pixels"),
    "literal pixel count": dict(crossings="pixels", min_gap_px=0.0),
}


INVARIANCE_VARIANTS = {
    "defaults (canonical frame, blur 1.5, k 12)": {},
    "no blur, k 8": dict(smoothing=0.0, k=8.0),
    "blur 1.5, k 8": dict(k=8.0),
    "blur 1, k 12": dict(smoothing=1.0),
    "paper's pipeline": dict(frame="image", origin="contours", ranking="triples", smoothing=0.0, k=8.0, mode="axes"),
}


def invariance_study(bench: Benchmark, sets: list[tuple[int, int]], reference_scale: float) -> None:
    """Change of V and F under a similarity copy of the reference, over their change under new noise."""
    import numpy as np

    from amdo_lab import ear_biometrics as eb

    def change(a, b):
        return np.array([np.abs(a.circles.counts - b.circles.counts).mean(),
                         np.abs(a.circles.distance_sums - b.circles.distance_sums).mean(),
                         eb.point_distance(b.topology, a.topology)])

    views = {}
    for seed, n_subjects in sets:
        rng = np.random.default_rng(seed)
        pose = eb.CapturePose(0.0, reference_scale, np.zeros(2), 0.0)
        rows = []
        for _ in range(n_subjects):
            shape = eb.draw_ear_shape(rng=rng)
            reference = eb.render_ear(shape, pose, rng=rng)
            rows.append([reference, eb.render_ear(shape, pose, rng=rng), eb.similarity_copy(reference, rng=rng),
                         eb.similarity_copy(reference, rng=rng, max_rotation_deg=180)])
        views[seed, n_subjects] = rows
    measures = ("l_r", "sum d", "D")
    table = bench.table("variant", "subjects (seed)", *(f"{m} ±25°" for m in measures), *(f"{m} any angle" for m in measures),
                        title=f"change under a similarity copy / change under new noise, references at scale {reference_scale}")
    for name, settings in INVARIANCE_VARIANTS.items():
        matcher = eb.EarMatcher(**settings)
        for (seed, n_subjects), rows in views.items():
            changes = []
            for row in rows:
                templates = [matcher.extract(image) for image in row]
                changes.append([change(templates[0], other) for other in templates[1:]])
            noise, turned, any_angle = np.mean(changes, axis=0)
            table.add(name, f"{n_subjects} ({seed})", *np.round(turned / noise, 2).tolist(), *np.round(any_angle / noise, 2).tolist())
        print(f"{name} measured", flush=True)


def main() -> None:
    bench = Benchmark(__doc__)
    bench.parser.add_argument("--subjects", type=int, default=60, help="easy subjects per database (default 60)")
    bench.parser.add_argument("--seeds", type=int, nargs="+", default=[77, 79],
                              help="development database seeds (default 77 79)")
    bench.parser.add_argument("--invariance", action="store_true", help="similarity / new-noise change of V and F instead")
    bench.parser.add_argument("--invariance-sets", nargs="+", default=["11:40", "12:40", "13:40"],
                              help="seed:subjects of each --invariance set (default 11:40 12:40 13:40)")
    bench.parser.add_argument("--reference-scale", type=float, default=0.85,
                              help="scale of the --invariance reference captures (default 0.85: the ear inside the image)")
    args = bench.parse()
    if args.invariance:
        sets = [tuple(int(part) for part in item.split(":")) for item in args.invariance_sets]
        invariance_study(bench, sets, args.reference_scale)
        bench.finish()
        return
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
