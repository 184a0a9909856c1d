"""Chapter 4: the development-seed check behind the EarMatcher defaults (not the notebook's data).

The matcher's pixel settings for 256 x 256 images (closing 2, fragments >= 40 px, polyline
crossings with a 6-px dead band, 8-px spur pruning, 4 smoothing rounds) were chosen on two
development databases drawn from seeds 77 and 79 (60 easy subjects each); the notebook uses other
seeds. The invariance defaults (canonical frame from the silhouette, eq. 6 in that frame, steps 8-9
ranked by the point distance of F) were chosen on databases from seeds 5-8 (40 and 60 subjects, the
perpendicular captures' similarity copies and the yawed captures), compared with the rows "paper, our
readings of V and F" to "eq. 6 on contour pixels" below (the row "paper's pipeline as printed" came later). The blur before eqs. 1-5 (1.5 px, with k = 12 in
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

``--peers`` measures the spread over seeds of the chapter's peer comparison: for each seed the
chapter's easy database (120 subjects, ``spawn_rngs(seed, 5)[0]``, so seed 2004 is the chapter's own),
rank-1 of ours in the canonical frame and on the image as given, of HOG, HOG after our 1.5-px blur and
LBP histograms on the image as given and on our canonical image, each compared with ours in the frame
query by query (queries only ours gets right / only the peer gets right, McNemar's exact p).

    .venv/bin/python benchmarks/dev_04_ear_defaults.py --peers [--peer-seeds 2004 2005 2006 2007 2008]

``--chapter-seeds S ...`` runs the chapter notebook itself once per seed S, its seeds replaced
(``spawn_rngs(2004, 5)`` by ``spawn_rngs(S, 5)``, the nuisance study's 4004 by S + 2000, the flip
study's 11 by S - 1993), errors allowed, and prints per seed every quantity the chapter's assertions
compare with a threshold (the seed spread behind each margin) and the assertions that failed.

    .venv/bin/python benchmarks/dev_04_ear_defaults.py --chapter-seeds 2005 2006 2007 2008
"""

from __future__ import annotations

from _harness import Benchmark  # first: pins BLAS threads before numpy is imported

VARIANTS = {
    "defaults": {},
    "paper's pipeline as printed": dict(frame="image", origin="contours", ranking="triples", smoothing=0.0, k=8.0, mode="axes",
                             crossings="pixels", min_gap_px=0.0, band_px=0.0, spur_length_px=0),
    "paper, our readings of V and F": dict(frame="image", origin="contours", ranking="triples", smoothing=0.0, k=8.0),
    "no blur, k 8": dict(smoothing=0.0, k=8.0),
    "blur 1.5, k 8": dict(k=8.0),
    "blur 1, k 12": dict(smoothing=1.0),
    "blur 2, k 12": dict(smoothing=2.0),
    "image frame, points of F": dict(frame="image", origin="contours"),
    "canonical frame, triples": dict(ranking="triples"),
    "eq. 6 on contour pixels": dict(origin="contours"),
    "Yokoi's eq. 8": dict(eq8="yokoi"),
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
    "paper's pipeline as printed": dict(frame="image", origin="contours", ranking="triples", smoothing=0.0, k=8.0, mode="axes",
                             crossings="pixels", min_gap_px=0.0, band_px=0.0, spur_length_px=0),
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
        matcher = eb.EarMatcher(eb.MatcherSettings(**settings))
        for (seed, n_subjects), rows in views.items():
            changes = []
            for row in rows:
                templates = [matcher.extract(image) for image in row]
                changes.append([change(templates[0], other) for other in templates[1:]])
            noise, turned, any_angle = np.mean(changes, axis=0)
            table.add(name, f"{n_subjects} ({seed})", *np.round(turned / noise, 2).tolist(), *np.round(any_angle / noise, 2).tolist())
        print(f"{name} measured", flush=True)


def peer_study(bench: Benchmark, seeds: list[int]) -> None:
    """Rank-1 of every descriptor in both frames, against ours in the canonical frame, per seed."""
    import cv2
    import numpy as np

    from amdo_lab import ear_biometrics as eb
    from amdo_lab.common import paired_comparison, spawn_rngs

    table = bench.table("seed", "descriptor", "frame", "rank-1", "ours only", "peer only", "McNemar p",
                        title="120 easy subjects per seed: each descriptor against ours in the canonical frame")
    for seed in seeds:
        easy = eb.make_ear_database(120, 2, "easy", rng=spawn_rngs(seed, 5)[0])
        ids, default = easy.subject_ids, eb.EarMatcher()
        canonical = np.array([default.canonical_image(image) for image in easy.images])
        relaxed_matcher = eb.EarMatcher(eb.MatcherSettings(max_count_violations=2))
        ours = eb.closed_set(relaxed_matcher, [default.extract(im) for im in easy.images],
                             ids).ranks == 1
        image_frame = eb.EarMatcher(eb.MatcherSettings(frame="image", origin="contours", max_count_violations=2))
        runs = {("ours (points of F)", "canonical frame"): ours,
                ("ours (points of F)", "image as given"): eb.closed_set(
                    image_frame, [image_frame.extract(im) for im in easy.images], ids).ranks == 1}
        for frame_name, images in (("image as given", easy.images), ("canonical frame", canonical)):
            blurred = np.array([cv2.GaussianBlur(im.astype(float), (0, 0), default.settings.smoothing) for im in images])
            runs["HOG", frame_name] = eb.peer_closed_set(images, ids)[0] == 1
            runs["HOG after our blur", frame_name] = eb.peer_closed_set(blurred, ids)[0] == 1
            runs["LBP histograms", frame_name] = eb.peer_closed_set(images, ids, eb.LbpNearestNeighbour())[0] == 1
        for (descriptor, frame_name), first in runs.items():
            versus = paired_comparison(ours, first)
            table.add(seed, descriptor, frame_name, round(float(first.mean()), 3), versus.only_first,
                      versus.only_second, float(f"{versus.p_value:.2g}"))
        print(f"seed {seed} measured", flush=True)


ASSERTED = {  # name -> expression in the chapter's namespace, as the chapter's assertions use it
    "flip interval high (< 0.1)": "flip_interval.high",
    "easy rank-1 (>= 0.85)": "runs['easy', 2].rank1",
    "easy relaxed - paper rule correct (> 0.2)": "runs['easy', 2].correct - runs['easy', 0].correct",
    "paper rule interval high (< 1)": "rule_interval.high",
    "HOG frame gain (> 0.5)": "frame_gain['HOG']",
    "LBP frame gain (> 0.4)": "frame_gain['LBP histograms']",
    "ours - HOG in frame (|.| < 0.2)": "gap_in_frame",
    "ours - HOG as given (> 0.6)": "peer_rank1['ours (points of F)', 'canonical frame'] - peer_rank1['HOG', 'image as given']",
    "log10 p ours vs HOG as given (< -6)": "np.log10(versus_ours['HOG', 'image as given'].p_value)",
    "log10 p ours frame vs as given (< log10 0.05)": "np.log10(versus_ours['ours (points of F)', 'image as given'].p_value)",
    "open set min FAR + FRR (> 0.5)": "(paper_rule_rates['FAR'] + paper_rule_rates['FRR (rejected)']).min()",
    "ours similarity / noise, max (< 2 and < paper min)": "over_noise.loc[['similarity, ±25°', 'similarity, any angle'], [(m, ours_col) for m in measures]].to_numpy().max()",
    "paper similarity ±25° / gap, min (> 0.3)": "relative.loc['similarity, ±25°', [(m, paper_col) for m in measures]].min()",
    "paper similarity / noise, min (> 1.5)": "over_noise.loc['similarity, ±25°', [(m, paper_col) for m in measures]].min()",
    "frame alone / noise, min (> 0.5)": "frame_alone.min()",
    "frame alone / noise, max (< 2)": "frame_alone.max()",
    "yaw / gap, min (> 0.1)": "relative.loc['yaw 30°'].min()",
    "yaw / gap, max (< 0.6)": "relative.loc['yaw 30°'].max()",
    "ours copies rank-1 (>= 0.95)": "copy_rows['ours']['rank-1']",
    "ours min over angles (>= 0.9)": "min(angle_rates['ours'])",
    "paper, our readings, max over angles (< 0.85)": "max(angle_rates['paper, our readings'])",
    "copies rank-1: paper as printed < paper, our readings < 0.95": "copy_rank1",
    "Canny gain over eqs. 1-5 k 8 (sum d > 0, l_r > -0.05)": "canny_gain.round(3).to_dict()",
    "ours similarity / noise, mean (< 1)": "ours_moved.mean()",
    "blurred - k 8, min (> 0)": "(detectors.loc[blurred] - detectors.loc['eqs. 1-5, k = 8']).min()",
    "nuisance ours min (>= 0.85)": "nuisance['ours rank-1'].min()",
    "nuisance HOG worst single factor": "nuisance['HOG rank-1'].drop('all on').idxmin()",
    "ablation rank-1": "sweep['rank-1'].round(3).to_dict()",
    "ablation paper rule": "sweep['correct (paper rule)'].round(3).to_dict()",
    "ablation rejected": "sweep['rejected'].round(3).to_dict()",
    "exercise 3 McNemar p (> 0.05)": "solution_3",
    "exercise 4 gains (HOG > 0.2, |ours| <= 0.05)": "gain[['ours rank-1', 'HOG rank-1']].round(3).to_dict()",
    "nuisance: rows with HOG AUC above ours AUC (>= 4)": "hog_wins",
}


def chapter_seeds(seeds: list[int]) -> None:
    """Run the chapter notebook with other seeds and print every asserted quantity per seed."""
    import json
    from pathlib import Path

    import nbformat
    from nbclient import NotebookClient

    path = Path(__file__).resolve().parent.parent / "notebooks" / "04_ear_geometric_features.ipynb"
    for seed in seeds:
        notebook = nbformat.read(path, as_version=4)
        for cell in notebook.cells:
            if cell.cell_type == "code":
                cell.source = (cell.source.replace("spawn_rngs(2004, 5)", f"spawn_rngs({seed}, 5)")
                               .replace("rng=4004", f"rng={seed + 2000}")
                               .replace("np.random.default_rng(11)", f"np.random.default_rng({seed - 1993})"))
        probe = "import json\nvalues = {}\n" + "".join(
            f"try:\n    values[{name!r}] = {expression}\nexcept Exception as error:\n    values[{name!r}] = repr(error)\n"
            for name, expression in ASSERTED.items()) + "print('VALUES ' + json.dumps(values, default=float))"
        notebook.cells.append(nbformat.v4.new_code_cell(probe))
        NotebookClient(notebook, timeout=1800, allow_errors=True, kernel_name="python3").execute()
        failed = [(index, output.get("ename"), output.get("evalue", "")[:200]) for index, cell in enumerate(notebook.cells)
                  if cell.cell_type == "code" for output in cell.get("outputs", []) if output.get("output_type") == "error"]
        values = next(output["text"] for output in notebook.cells[-1].outputs if output.get("output_type") == "stream")
        print(f"seed {seed}: failed cells {failed}")
        print(f"seed {seed}: {values.strip()}", flush=True)


def main() -> None:
    bench = Benchmark(__doc__)
    bench.parser.add_argument("--subjects", type=int, default=60, help="easy subjects per database (default 60)")
    bench.parser.add_argument("--seeds", type=int, nargs="+", default=[77, 79],
                              help="development database seeds (default 77 79)")
    bench.parser.add_argument("--chapter-seeds", type=int, nargs="+", default=[],
                              help="run the chapter notebook with each of these seeds and print its asserted quantities")
    bench.parser.add_argument("--peers", action="store_true", help="the peer comparison over seeds instead")
    bench.parser.add_argument("--peer-seeds", type=int, nargs="+", default=[2004, 2005, 2006, 2007, 2008],
                              help="chapter seeds of --peers (default 2004-2008; 2004 is the chapter's)")
    bench.parser.add_argument("--invariance", action="store_true", help="similarity / new-noise change of V and F instead")
    bench.parser.add_argument("--invariance-sets", nargs="+", default=["11:40", "12:40", "13:40"],
                              help="seed:subjects of each --invariance set (default 11:40 12:40 13:40)")
    bench.parser.add_argument("--reference-scale", type=float, default=0.85,
                              help="scale of the --invariance reference captures (default 0.85: the ear inside the image)")
    args = bench.parse()
    if args.chapter_seeds:
        chapter_seeds(args.chapter_seeds)
        return
    if args.peers:
        peer_study(bench, args.peer_seeds)
        bench.finish()
        return
    if args.invariance:
        sets = [tuple(int(part) for part in item.split(":")) for item in args.invariance_sets]
        invariance_study(bench, sets, args.reference_scale)
        bench.finish()
        return
    import numpy as np

    from amdo_lab import ear_biometrics as eb

    np.seterr(all="raise")  # a silent NaN would corrupt the comparison
    databases = {seed: eb.make_ear_database(args.subjects, 2, "easy", rng=seed) for seed in args.seeds}
    columns = [name for s in args.seeds for name in (f"seed {s} paper", f"seed {s} rank-1")]
    table = bench.table("variant", *columns,
                        title=f"{args.subjects} easy subjects per development seed, 256 px; paper = share of "
                              "queries the paper's rule names correctly, rank-1 = relaxed ranking")
    for name, change in VARIANTS.items():
        cells = []
        for seed, database in databases.items():
            templates = [eb.EarMatcher(eb.MatcherSettings(**change)).extract(image) for image in database.images]
            paper = eb.closed_set(eb.EarMatcher(eb.MatcherSettings(**change)), templates, database.subject_ids)
            relaxed_matcher = eb.EarMatcher(eb.MatcherSettings(**change, max_count_violations=2))
            relaxed = eb.closed_set(relaxed_matcher, templates, database.subject_ids)
            cells += [round(float(paper.correct), 3), round(float(relaxed.rank1), 3)]
        table.add(name, *cells)
        print(f"{name} measured", flush=True)
    bench.note(f"chance rank-1 = {1 / args.subjects:.3f}")
    bench.finish()


if __name__ == "__main__":
    main()
