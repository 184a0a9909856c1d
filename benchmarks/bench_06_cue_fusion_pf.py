"""Chapter 6 benchmark: cue subsets × seeds on the "fusion" head sequence, peers and speed.

For every seed (a new sequence and a new filter seed) and every non-empty subset of the three cues,
the filter of Fig. 1 (N = 300, calibrated σ) tracks the 128 frames; a frame is a success when the
tracked ellipse overlaps the true one with IoU >= 0.5. Prints, per method: the median seed's
success rate, the pooled rate with its Wilson interval, median centre error on tracked frames,
and milliseconds per frame; then the paired Wilcoxon test of all three cues against each single
cue on per-seed success, and the oracle filter's centre error (same filter, true likelihood).

Peers on the same frames: cv2.CamShift, cv2.TrackerMIL (not seedable: its runs vary a little), and our
three-cue likelihood inside the generic pfilter package (linear weights exp(log L - max log L), numpy's
global generator seeded per run). ``--lighting`` instead measures Fig. 3: colour-only success on the
lighting frames against the size of the colour cast.

Run:  OMP_NUM_THREADS=1 .venv/bin/python benchmarks/bench_06_cue_fusion_pf.py --seeds 20        (~25 min)
      OMP_NUM_THREADS=1 .venv/bin/python benchmarks/bench_06_cue_fusion_pf.py --lighting --seeds 4 [--bins 8]
"""

from __future__ import annotations

import argparse
import itertools
import time


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=20, help="number of sequences/seeds (default 20)")
    parser.add_argument("--first-seed", type=int, default=0, help="first sequence seed (default 0)")
    parser.add_argument("--particles", type=int, default=300, help="N_w (default 300)")
    parser.add_argument("--sigmas", choices=("calibrated", "paper"), default="calibrated")
    parser.add_argument("--subsets", default="all", help="'all' (7 subsets) or e.g. 'color+edge,structure'")
    parser.add_argument("--bins", type=int, default=32, help="colour histogram bins per channel (default 32, Table 1)")
    parser.add_argument("--printed-ar2", action="store_true", help="eq. (4) as printed (unstable) in our filter")
    parser.add_argument("--no-slow-peers", action="store_true", help="skip TrackerMIL and pfilter")
    parser.add_argument("--lighting", action="store_true", help="Fig. 3: colour only against the cast strength")
    args = parser.parse_args()
    if args.lighting:
        lighting_sweep(args)
        return

    import numpy as np
    from scipy.stats import wilcoxon

    from amdo_lab import cue_fusion_pf as cf
    from amdo_lab.common import rate_interval

    cues = ("color", "edge", "structure")
    if args.subsets == "all":
        subsets = [c for r in (1, 2, 3) for c in itertools.combinations(cues, r)]
    else:
        subsets = [tuple(s.split("+")) for s in args.subsets.split(",")]
    slow_peers = [] if args.no_slow_peers else ["mil", "pfilter (3 cues)"]
    names = ["+".join(s) for s in subsets] + ["camshift"] + slow_peers + ["oracle"]
    success = {name: [] for name in names}
    errors = {name: [] for name in names}
    ms = {name: [] for name in names}
    cf.load_or_train_cascade(cf.CASCADE_SEED)  # train (or load) before timing
    began = time.perf_counter()
    for seed in range(args.first_seed, args.first_seed + args.seeds):
        sequence = cf.make_head_sequence("fusion", seed)
        init = sequence.true_ellipses[0]
        runs = {}
        for subset in subsets:
            try:
                runs["+".join(subset)] = cf.track(sequence.frames, init, rng=10_000 + seed, cues=subset,
                                                  n_particles=args.particles, sigmas=args.sigmas, bins=args.bins,
                                                  printed_order=args.printed_ar2)
            except RuntimeError as error:  # a diverging filter (eq. 4 as printed) counts as lost on every frame
                print(f"seed {seed}, {'+'.join(subset)}: {error}")
                lost = np.full((len(sequence.frames), 5), [0.0, 0.0, 1.0, 1.0, 0.0])
                runs["+".join(subset)] = cf.TrackResult(lost[:, :3], lost, lost[:, :2], np.ones(len(lost)), 0.0,
                                                        lost[:, None, :3], np.ones((len(lost), 1)))
        runs["camshift"] = cf.track_camshift(sequence.frames, init)
        if slow_peers:
            runs["mil"] = cf.track_mil(sequence.frames, init)
            runs["pfilter (3 cues)"] = cf.track_pfilter(sequence.frames, init, rng=10_000 + seed, cues=cues,
                                                        n_particles=args.particles, sigmas=args.sigmas)
        runs["oracle"] = cf.track(sequence.frames, init, rng=10_000 + seed, cues=("oracle",),
                                  n_particles=args.particles, oracle=sequence.oracle_log_likelihood)
        for name, result in runs.items():
            tracked = cf.ellipse_iou(result.ellipses, sequence.true_ellipses) >= 0.5
            success[name].append(tracked)
            error = np.linalg.norm(result.centers - sequence.truth[:, :2], axis=1)
            errors[name].append(np.median(error[tracked]) if tracked.any() else np.nan)
            ms[name].append(result.ms_per_frame)
        print(f"seed {seed}: " + "  ".join(f"{n}={np.mean(success[n][-1]):.2f}" for n in names), flush=True)
    print(f"\n{args.seeds} seeds, N = {args.particles}, sigmas = {args.sigmas}, {time.perf_counter() - began:.0f} s\n")
    print(f"{'method':<24}{'median seed':>12}{'pooled rate [95% Wilson]':>28}{'median err px':>15}{'ms/frame':>10}")
    for name in names:
        per_seed = np.array([s.mean() for s in success[name]])
        pooled = rate_interval(np.concatenate(success[name]))
        print(f"{name:<24}{np.median(per_seed):>12.3f}{pooled.rate:>12.3f} [{pooled.low:.3f}, {pooled.high:.3f}]"
              f"{np.nanmedian(errors[name]):>15.2f}{np.median(ms[name]):>10.1f}")
    best = "+".join(cues)
    if best in success and args.seeds >= 6:
        print("\npaired Wilcoxon, per-seed success, all three cues vs:")
        ours = np.array([s.mean() for s in success[best]])
        for single in cues:
            if single in success:
                other = np.array([s.mean() for s in success[single]])
                p = wilcoxon(ours, other, alternative="greater", zero_method="zsplit").pvalue if np.any(ours != other) else 1.0
                print(f"  {single:<10} median difference {np.median(ours - other):+.3f}  one-sided p = {p:.2g}")
    if best in success and np.median(ms[best]) > 0:  # a diverged run has no time
        ratio = np.median(ms["camshift"]) / np.median(ms[best])
        print(f"\nCamShift / three cues, time per frame: {ratio:.3f}")
        if slow_peers:
            print(f"pfilter / ours, same three-cue likelihood, time per frame: "
                  f"{np.median(ms['pfilter (3 cues)']) / np.median(ms[best]):.2f}")
        print(f"oracle median centre error {np.nanmedian(errors['oracle']):.2f} px; "
              f"three cues {np.nanmedian(errors[best]):.2f} px (bound 2 x oracle + 2 = {2 * np.nanmedian(errors['oracle']) + 2:.2f})")


def lighting_sweep(args) -> None:
    """Fig. 3: share of the lighting frames (29-80) tracked by colour alone, against the cast strength."""
    import numpy as np

    from amdo_lab import cue_fusion_pf as cf
    from amdo_lab.common import rate_interval

    print(f"{args.bins}^3 RGB bins, sigma_c = {args.sigmas}")
    print(f"{'cast strength':>14}{'colour only, lighting frames [95% Wilson]':>46}{'three cues':>14}")
    for strength in (0.0, 0.25, 0.5, 0.75, 1.0):
        colour, three = [], []
        for seed in range(args.first_seed, args.first_seed + args.seeds):
            sequence = cf.make_head_sequence("fusion", seed, cast_strength=strength)
            start, stop = sequence.segments["lighting"]
            for cues, store in ((("color",), colour), (("color", "edge", "structure"), three)):
                result = cf.track(sequence.frames[:stop], sequence.true_ellipses[0], rng=10_000 + seed, cues=cues,
                                  n_particles=args.particles, sigmas=args.sigmas, bins=args.bins)
                store.append(cf.ellipse_iou(result.ellipses[start:], sequence.true_ellipses[start:stop]) >= 0.5)
        c, t = rate_interval(np.concatenate(colour)), rate_interval(np.concatenate(three))
        print(f"{strength:>14.2f}{c.rate:>26.3f} [{c.low:.3f}, {c.high:.3f}]{t.rate:>14.3f}", flush=True)


if __name__ == "__main__":
    main()
