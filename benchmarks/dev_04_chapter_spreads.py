"""Chapter 4: seed spreads behind three of the chapter's claims (not the notebook's data).

``--eq8``: identification with the two readings of eq. 8, Rutovitz's crossing number (the default)
and Yokoi's connectivity number (``MatcherSettings(eq8="yokoi")``), on the first ``--subjects`` easy
subjects of the chapter's database drawn from each seed (``spawn_rngs(seed, 5)[0]``; 2004 is the
chapter's own): rank-1 of the ranking, the paper's rule, and the queries only one reading gets right.

``--border``: the canonical frame of an ear cut by the image border. Per seed, 20 ears drawn at scale 1
(``spawn_rngs(seed, 5)[2]``, as the chapter's invariance study); each gets a copy turned by 20 degrees
and scaled by 0.9 (no shift), and the frame's spread of the copy is compared with 0.9 times the
original's: the relative error, for the ears whose silhouette touches the border and for the others.

``--nuisance``: the chapter's nuisance study (30 subjects, one factor at a time) drawn from seeds
``--nuisance-seeds`` (4004 is the chapter's): per row the AUC of step 4's distance-sum gaps ("ours
AUC"), of the distance D between F's points, and of HOG on the image as given.

    .venv/bin/python benchmarks/dev_04_chapter_spreads.py --eq8 --border [--seeds 2004 2005 2006 2007 2008]
    .venv/bin/python benchmarks/dev_04_chapter_spreads.py --nuisance [--nuisance-seeds 4004 4005 4006]
"""

from __future__ import annotations

from _harness import Benchmark  # first: pins BLAS threads before numpy is imported


def eq8_study(bench: Benchmark, seeds: list[int], n_subjects: int) -> None:
    """Rank-1 and the paper's rule with each reading of eq. 8, and the discordant queries."""
    from amdo_lab import ear_biometrics as eb
    from amdo_lab.common import paired_comparison, spawn_rngs

    table = bench.table("seed", "rank-1 crossing", "rank-1 Yokoi", "rule crossing", "rule Yokoi",
                        "only crossing", "only Yokoi", title=f"eq. 8 readings, {n_subjects} easy subjects")
    for seed in seeds:
        database = eb.make_ear_database(n_subjects, 2, "easy", rng=spawn_rngs(seed, 5)[0])
        first, rule = {}, {}
        for eq8 in eb.EQ8_READINGS:
            templates = [eb.EarMatcher(eb.MatcherSettings(eq8=eq8)).extract(image) for image in database.images]
            relaxed_matcher = eb.EarMatcher(eb.MatcherSettings(eq8=eq8, max_count_violations=2))
            relaxed = eb.closed_set(relaxed_matcher, templates, database.subject_ids)
            first[eq8] = relaxed.ranks == 1
            rule[eq8] = eb.closed_set(eb.EarMatcher(eb.MatcherSettings(eq8=eq8)), templates, database.subject_ids).correct
        versus = paired_comparison(first["crossing"], first["yokoi"])
        table.add(seed, first["crossing"].mean(), first["yokoi"].mean(), rule["crossing"], rule["yokoi"],
                  versus.only_first, versus.only_second)


def border_study(bench: Benchmark, seeds: list[int]) -> None:
    """Relative error of the frame's spread on a turned, scaled copy: ears cut by the border or whole."""
    import numpy as np

    from amdo_lab import ear_biometrics as eb
    from amdo_lab.common import spawn_rngs

    table = bench.table("seed", "share touching", "error touching", "error whole", "ratio",
                        title="frame spread of a copy (20 degrees, scale 0.9) against 0.9 x the original's")
    for seed in seeds:
        rng = spawn_rngs(seed, 5)[2]
        shapes = [eb.draw_ear_shape(rng=rng) for _ in range(20)]
        images = [eb.render_ear(shape, eb.CapturePose(0.0, 1.0, np.zeros(2), 0.0), rng=rng) for shape in shapes]
        masks = [eb.silhouette(image) for image in images]
        touching = np.array([np.r_[m[[0, -1]].ravel(), m[:, [0, -1]].ravel()].any() for m in masks])
        error = []
        for image in images:
            copy = eb.similarity_copy(image, rng=0, rotation_deg=20.0, scale_range=(0.9, 0.9), max_shift_px=0.0)
            spreads = [eb.moment_frame(eb.silhouette(im), im.shape).spread for im in (image, copy)]
            error.append(abs(spreads[1] / (0.9 * spreads[0]) - 1))
        error = np.array(error)
        cut = error[touching].mean() if touching.any() else float("nan")
        table.add(seed, touching.mean(), cut, error[~touching].mean(), cut / error[~touching].mean())


def nuisance_auc(bench: Benchmark, seeds: list[int]) -> None:
    """AUC of ours (step 4's sums, F's points) and of HOG per nuisance condition, per seed."""
    from amdo_lab import ear_biometrics as eb

    factors = [f for f in eb.NUISANCE_FACTORS if f != "illumination"]  # as in the chapter
    conditions = {"all on": ()}
    conditions.update({f"only {f}": tuple(g for g in eb.NUISANCE_FACTORS if g != f) for f in factors})
    table = bench.table("seed", "condition", "ours AUC", "ours AUC (F points)", "HOG AUC",
                        title="nuisance study, 30 easy subjects")
    for seed in seeds:
        for row in eb.nuisance_study(30, conditions, rng=seed):
            table.add(seed, row["condition"], row["ours AUC"], row["ours AUC (F points)"], row["HOG AUC"])


def main() -> None:
    bench = Benchmark(__doc__)
    bench.parser.add_argument("--eq8", action="store_true", help="identification with both readings of eq. 8")
    bench.parser.add_argument("--border", action="store_true", help="the frame of ears cut by the border")
    bench.parser.add_argument("--seeds", type=int, nargs="+", default=[2004, 2005, 2006, 2007, 2008],
                              help="seeds (default 2004-2008; 2004 is the chapter's)")
    bench.parser.add_argument("--subjects", type=int, default=40, help="easy subjects for --eq8 (default 40)")
    bench.parser.add_argument("--nuisance", action="store_true", help="AUC per nuisance condition over seeds")
    bench.parser.add_argument("--nuisance-seeds", type=int, nargs="+", default=[4004, 4005, 4006],
                              help="seeds of the nuisance study (default 4004-4006; 4004 is the chapter's)")
    args = bench.parse()
    if args.eq8:
        eq8_study(bench, args.seeds, args.subjects)
    if args.border:
        border_study(bench, args.seeds)
    if args.nuisance:
        nuisance_auc(bench, args.nuisance_seeds)
    bench.finish()


if __name__ == "__main__":
    main()
