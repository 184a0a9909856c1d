"""The paper's published numbers, our side-by-side tables, and Figs. 1-2 in the paper's encoding."""

from __future__ import annotations

import numpy as np
import pandas as pd
from matplotlib.axes import Axes

from amdo_lab.common import PALETTE, check_axes, check_instance
from amdo_lab.face_glmm.glmm import GlmmResult

__all__ = ["PAPER_TABLE2", "PAPER_NUMBERS", "table2_comparison", "cell_predictions", "findings",
           "plot_figure1", "plot_figure2", "SUPPLEMENT_COLOURS"]

#: Table 2 of Givens et al. (2004): numerator d.f., F value, p-value as printed.
PAPER_TABLE2 = pd.DataFrame(
    {"df": [3, 1, 1, 1, 3, 3, 3, 1, 1, 1, 1],
     "F": [139.1, 1087.8, 936.6, 333.8, 14.2, 67.0, 41.5, 717.6, 59.1, 703.7, 5.04],
     "p_value": ["<.0001"] * 10 + [".0248"]},
    index=pd.Index(["U", "M", "D", "F", "U:M", "U:F", "U:D", "M:F", "M:D", "D:F", "M:D:F"], name="term"))

#: Other numbers quoted in Secs. 6-7.
PAPER_NUMBERS = {"rho": 0.70, "best_included": 0.87, "best_not_included": 0.75,
                 "baseline_included": 0.77, "baseline_not_included": 0.74,
                 "all_30_share": 0.47, "rank1_rate": 0.76}

#: Sec. 6 colours: orange none, green reflection, red noise, blue shift.
SUPPLEMENT_COLOURS = {"none": PALETTE["orange"], "reflection": PALETTE["green"],
                      "noise": PALETTE["vermillion"], "shift": PALETTE["blue"]}
_MARKERS = {"l2": "s", "soft_l2": "o"}
_LINES = {"fixed": "-", "e90": "--"}


# Levels of the paper's factors that the findings and Fig. 2 compare (they must all be in the fit).
_COMPARED_LEVELS = {"U": ("none", "reflection"), "M": ("l2", "soft_l2"), "D": ("fixed", "e90"), "F": ("no", "yes")}


def _check_result(result: object, name: str = "result", *, compared: bool = False, drawn: bool = False) -> None:
    """A :class:`GlmmResult` with the paper's factors U, M, D and F.

    ``compared``: the levels the findings compare are present; ``drawn``: every level has a colour,
    marker or line style in the figures (a level without one would be dropped from the plot).
    """
    check_instance(result, name, GlmmResult, what="a GlmmResult (from fit_binomial_glmm)")
    levels = result.design.levels
    missing = [factor for factor in _COMPARED_LEVELS if levels.get(factor) is None]
    if missing:
        raise ValueError(f"{name} must be a fit with the paper's factors U, M, D and F (e.g. PAPER_FORMULA); "
                         f"it lacks {missing}")
    for factor, wanted in _COMPARED_LEVELS.items() if compared else ():
        absent = [level for level in wanted if level not in levels[factor]]
        if absent:
            raise ValueError(f"{name} factor {factor!r} lacks the level(s) {absent} that are compared")
    if drawn:
        styles = {"U": SUPPLEMENT_COLOURS, "M": _MARKERS, "D": _LINES, "F": {"no": None, "yes": None}}
        for factor, known in styles.items():
            unknown = [level for level in levels[factor] if level not in known]
            if unknown:
                raise ValueError(f"{name} factor {factor!r} has level(s) {unknown} the figures cannot draw; "
                                 f"known: {list(known)}")


def table2_comparison(result: GlmmResult) -> pd.DataFrame:
    """The paper's Table 2 next to our Wald F tests of the same terms.

    Parameters
    ----------
    result : GlmmResult
        A fit of :data:`PAPER_FORMULA` (terms absent from the fit give NaN rows).

    Returns
    -------
    pandas.DataFrame
        Indexed by term (U, M, D, F and the interactions of eq. 2) with ``df``, ``F paper``, ``p paper``
        (as printed), ``F ours`` (chi2 / df, i.e. the denominator degrees of freedom taken as infinite,
        rounded to 0.1) and ``p ours`` (two significant digits, as text).

    References
    ----------
    Givens et al. (2004), AMDO, LNCS 3179, Table 2 (tests of the fixed effects of eq. 2).
    """
    check_instance(result, "result", GlmmResult, what="a GlmmResult (from fit_binomial_glmm)")
    ours = result.tests.reindex(PAPER_TABLE2.index)
    return pd.DataFrame({"df": PAPER_TABLE2["df"], "F paper": PAPER_TABLE2["F"], "p paper": PAPER_TABLE2["p_value"],
                         "F ours": ours["F"].round(1), "p ours": ours["p_value"].map(lambda p: f"{p:.2g}")})


def cell_predictions(result: GlmmResult, ci: float | None = None) -> pd.DataFrame:
    """Predicted rank-1 probability of every U x M x D x F cell for a typical probe and training set.

    Parameters
    ----------
    result : GlmmResult
        A fit with the paper's factors U, M, D and F.
    ci : float or None, default None
        Level in (0, 1) of a Wald interval on the logit scale; None for no interval.

    Returns
    -------
    pandas.DataFrame
        One row per cell: columns U, M, D, F and ``p`` (probability in [0, 1], random effects 0),
        plus ``lower`` and ``upper`` when ``ci`` is given.

    References
    ----------
    Givens et al. (2004), AMDO, LNCS 3179, eq. (2) and Fig. 1 (the cell probabilities it plots).
    """
    _check_result(result)
    levels = result.design.levels
    grid = pd.MultiIndex.from_product([levels["U"], levels["M"], levels["D"], levels["F"]],
                                      names=["U", "M", "D", "F"]).to_frame(index=False)
    return pd.concat([grid, result.predict(grid, ci=ci)], axis=1)


def _marg(result, **levels):
    grid = pd.DataFrame({k: [v] for k, v in levels.items()})
    return float(result.predict_marginal(grid).p.iloc[0])


def findings(result: GlmmResult, size_result: GlmmResult | None = None) -> pd.DataFrame:
    """The paper's qualitative findings (Sec. 6), each evaluated on our fit.

    Parameters
    ----------
    result : GlmmResult
        A fit of the paper's factors U, M, D and F with the levels the findings compare (none and
        reflection; l2 and soft_l2; fixed and e90; no and yes).
    size_result : GlmmResult or None, default None
        A fit with image-size (S) terms, such as one of :data:`SIZE_FORMULA`; adds the finding that
        image size does not matter.

    Returns
    -------
    pandas.DataFrame
        Indexed by the finding in words, with the bool column ``holds for ours`` and ``measured``, the
        marginal rank-1 probabilities (or variances, p-values) the verdict compares, as text.

    References
    ----------
    Givens et al. (2004), AMDO, LNCS 3179, Secs. 6-7 (the effects of supplement, metric, PCA dimension, inclusion and image size).
    """
    _check_result(result, compared=True)
    if size_result is not None:
        check_instance(size_result, "size_result", GlmmResult, what="a GlmmResult")
        # with no S term, "all p > 0.05" would hold vacuously
        if not any("S" in term.split(":") for term in size_result.tests.index):
            raise ValueError("size_result must be a fit with image-size (S) terms, e.g. of SIZE_FORMULA")
    m = lambda **kw: _marg(result, **kw)  # noqa: E731
    u_levels = result.design.levels["U"]
    u_marg = {u: m(U=u) for u in u_levels}
    spread = {f: np.ptp([m(U=u, F=f) for u in u_levels]) for f in ("yes", "no")}
    soft_gain = {f: m(M="soft_l2", F=f) - m(M="l2", F=f) for f in ("yes", "no")}
    e90_loss = {f: m(D="fixed", F=f) - m(D="e90", F=f) for f in ("yes", "no")}
    incl = {(mm, d): m(M=mm, D=d, F="yes") - m(M=mm, D=d, F="no") for mm in ("l2", "soft_l2")
            for d in ("fixed", "e90")}
    vc = result.variance_components
    t_share = vc.get("t", 0.0) / vc.get("p", np.inf)
    rows = [
        ("shift is the best supplement", max(u_marg, key=u_marg.get) == "shift",
         ", ".join(f"{u} {p:.3f}" for u, p in u_marg.items())),
        ("reflection is worse than no supplement", u_marg["reflection"] < u_marg["none"],
         f"reflection {u_marg['reflection']:.3f}, none {u_marg['none']:.3f}"),
        ("supplement effects mainly for included probes (range yes > 2 x range no)", spread["yes"] > 2 * spread["no"],
         f"range yes {spread['yes']:.3f}, no {spread['no']:.3f}"),
        ("soft L2 beats L2 overall", m(M="soft_l2") > m(M="l2"),
         f"soft L2 {m(M='soft_l2'):.3f}, L2 {m(M='l2'):.3f}"),
        ("soft L2 gain mainly for included probes (gain yes > 2 x gain no)", soft_gain["yes"] > 2 * soft_gain["no"],
         f"gain yes {soft_gain['yes']:+.3f}, no {soft_gain['no']:+.3f}"),
        ("inclusion in training helps overall (slightly)", m(F="yes") > m(F="no"),
         f"yes {m(F='yes'):.3f}, no {m(F='no'):.3f}"),
        ("inclusion helps at 114 dims for both metrics", incl[("l2", "fixed")] > 0 and incl[("soft_l2", "fixed")] > 0,
         f"L2 {incl[('l2', 'fixed')]:+.3f}, soft L2 {incl[('soft_l2', 'fixed')]:+.3f}"),
        ("at E90: inclusion helps soft L2, hurts L2", incl[("soft_l2", "e90")] > 0 > incl[("l2", "e90")],
         f"soft L2 {incl[('soft_l2', 'e90')]:+.3f}, L2 {incl[('l2', 'e90')]:+.3f}"),
        ("E90 is worse than 114 dims overall", m(D="e90") < m(D="fixed"),
         f"E90 {m(D='e90'):.3f}, 114 {m(D='fixed'):.3f}"),
        ("E90 loss mainly for included probes (loss yes > 2 x loss no)", e90_loss["yes"] > 2 * e90_loss["no"],
         f"loss yes {e90_loss['yes']:+.3f}, no {e90_loss['no']:+.3f}"),
        ("training-set variance ~ 0 (< 5 % of probe variance)", t_share < 0.05,
         f"{100 * t_share:.2f} % of the probe variance"),
    ]
    if size_result is not None:
        size_terms = [t for t in size_result.tests.index if "S" in t.split(":")]
        p_values = size_result.tests.loc[size_terms, "p_value"]
        rows.append(("image size and its interactions not significant (all p > 0.05)", bool((p_values > 0.05).all()),
                     f"smallest p {p_values.min():.2g} ({p_values.idxmin()})"))
    return pd.DataFrame(rows, columns=["paper's finding", "holds for ours", "measured"]).set_index("paper's finding")


def _draw(ax, x, p, colours, marker, filled, linestyle):
    ax.plot(x, p, color="0.55", linestyle=linestyle, linewidth=1.0, zorder=1)
    for xi, pi, c in zip(x, p, colours):
        ax.scatter([xi], [pi], marker=marker, s=45, zorder=2, edgecolors=c, linewidths=1.5,
                   facecolors=c if filled else "white")


#: Tick labels in words for the factor levels' code names (Fig. 2).
_TICK_NAMES = {"l2": "L2", "soft_l2": "soft L2", "fixed": "114 dims", "e90": "E90", "no": "no", "yes": "yes"}


def plot_figure1(result: GlmmResult, ax) -> None:
    """Fig. 1: predicted rank-1 probability of a typical probe against the training supplement.

    The paper's encoding: colour = supplement, marker = metric (square L2, circle soft L2), filled =
    probe in the training set, line style = PCA dimension (solid 114, dashed E90).

    Parameters
    ----------
    result : GlmmResult
        A fit with the paper's factors U, M, D and F, every level of which the figure can draw.
    ax : matplotlib.axes.Axes
        Where to draw; the legend is placed to its right.

    References
    ----------
    Givens et al. (2004), AMDO, LNCS 3179, Fig. 1.
    """
    _check_result(result, drawn=True)
    check_axes(ax)
    cells = cell_predictions(result)
    order = ["none", "reflection", "noise", "shift"]
    order = [u for u in order if u in result.design.levels["U"]]
    for (mm, d, f), grp in cells.groupby(["M", "D", "F"], observed=True):
        p = grp.set_index("U").loc[order, "p"].to_numpy()
        _draw(ax, np.arange(len(order)), p, [SUPPLEMENT_COLOURS[u] for u in order], _MARKERS[mm], f == "yes",
              _LINES[d])
    ax.set_xticks(np.arange(len(order)), order)
    ax.set_xlabel("training supplement")
    ax.set_ylabel("predicted P(rank 1), typical probe")
    ax.legend(handles=_figure1_legend(order), loc="center left", bbox_to_anchor=(1.02, 0.5), fontsize=8,
              frameon=False)


def _figure1_legend(supplements) -> list:
    """Legend entries for the paper's encoding: colour, marker, fill and line style."""
    from matplotlib.lines import Line2D

    grey = "0.3"
    handles = [Line2D([], [], marker="o", linestyle="", color=SUPPLEMENT_COLOURS[u], label=f"supplement: {u}")
               for u in supplements]
    handles += [Line2D([], [], marker=_MARKERS["l2"], linestyle="", color=grey, label="metric: L2"),
                Line2D([], [], marker=_MARKERS["soft_l2"], linestyle="", color=grey, label="metric: soft L2"),
                Line2D([], [], marker="o", linestyle="", color=grey, label="probe in training"),
                Line2D([], [], marker="o", linestyle="", color=grey, markerfacecolor="white",
                       label="probe not in training"),
                Line2D([], [], linestyle=_LINES["fixed"], color="0.55", label="114 PCA dims"),
                Line2D([], [], linestyle=_LINES["e90"], color="0.55", label="E90 PCA dims")]
    return handles


def plot_figure2(result: GlmmResult, axes) -> None:
    """Fig. 2: metric (left), inclusion (centre) and PCA dimension (right), averaged over supplements.

    Parameters
    ----------
    result : GlmmResult
        A fit with the paper's factors U, M, D and F and the levels Fig. 2 compares.
    axes : sequence of three matplotlib.axes.Axes
        The three panels, e.g. from ``plt.subplots(1, 3)``.

    References
    ----------
    Givens et al. (2004), AMDO, LNCS 3179, Fig. 2 (marginal probabilities, the supplement averaged on the logit scale).
    """
    _check_result(result, compared=True, drawn=True)
    axes = list(np.ravel(axes)) if isinstance(axes, (list, tuple, np.ndarray)) else [axes]
    if len(axes) != 3 or not all(isinstance(ax, Axes) for ax in axes):
        raise ValueError(f"axes must be three matplotlib Axes, got {len(axes)} object(s)")
    black = PALETTE["black"]
    panels = [("M", ["l2", "soft_l2"], ["F", "D"]), ("F", ["no", "yes"], ["M", "D"]),
              ("D", ["fixed", "e90"], ["M", "F"])]
    for ax, (xvar, xlev, series) in zip(axes, panels):
        levels = {v: result.design.levels[v] for v in series}
        for a in levels[series[0]]:
            for b in levels[series[1]]:
                grid = pd.DataFrame({xvar: xlev, series[0]: a, series[1]: b})
                p = result.predict_marginal(grid).p.to_numpy()
                style = {**{xvar: None}, series[0]: a, series[1]: b}
                for i, xl in enumerate(xlev):
                    cell = {**style, xvar: xl}
                    marker = _MARKERS[cell["M"]]
                    filled = cell["F"] == "yes"
                    ax.scatter([i], [p[i]], marker=marker, s=45, edgecolors=black, linewidths=1.5,
                               facecolors=black if filled else "white", zorder=2)
                ls = _LINES[style["D"]] if style.get("D") else "-"
                ax.plot(range(len(xlev)), p, color="0.55", linestyle=ls, linewidth=1.0, zorder=1)
        ax.set_xticks(range(len(xlev)), [_TICK_NAMES.get(level, level) for level in xlev])
        ax.set_xlim(-0.4, len(xlev) - 0.6)
        ax.set_xlabel({"M": "distance metric", "F": "probe in training?", "D": "PCA dimension"}[xvar])
    axes[0].set_ylabel("predicted P(rank 1)")
