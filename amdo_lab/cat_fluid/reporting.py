"""Tables of the chapter: Table 1 of the paper beside ours, and accuracy against the known warp.

Small helpers so that the notebook's cells read as the comparison they make, not as the
bookkeeping behind it.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd

from amdo_lab.cat_fluid.data import RegistrationPair
from amdo_lab.cat_fluid.registration import (MAX_GREY_LEVEL, displacement_rmse, grey_level_difference,
                                             inverse_consistency_error, jacobian_determinant)
from amdo_lab.common import as_finite_array, check_bool, check_choice, check_dataframe, check_instance

__all__ = ["PAPER_TABLE1", "paper_table1", "grey_level_table", "mean_sd_strings", "accuracy_row"]

#: Table 1 of the paper: (mean, standard deviation) of |deformed template - study|, grey levels 0-255.
PAPER_TABLE1: dict[str, dict[str, tuple[float, float]]] = {
    "A": {"CAT": (6.0, 12.6), "SOR": (10.9, 19.2)},
    "B": {"CAT": (6.8, 13.8), "SOR": (9.3, 17.2)},
    "C": {"CAT": (6.2, 13.2), "SOR": (9.1, 16.6)},
}


def paper_table1() -> pd.DataFrame:
    """The paper's Table 1 as numbers.

    Returns
    -------
    pandas.DataFrame
        Rows the pairs A-C, columns (``"paper CAT"`` or ``"paper SOR"``, ``"mean"`` or ``"sd"``), grey
        levels 0-255.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    Table 1.
    """
    return pd.DataFrame({(f"paper {method}", stat): {pair: values[method][k] for pair, values in PAPER_TABLE1.items()}
                         for method in ("CAT", "SOR") for k, stat in enumerate(("mean", "sd"))}).rename_axis("pair")


def grey_level_table(pairs: Mapping[str, RegistrationPair], deformed: Mapping[str, Mapping[str, np.ndarray]],
                     *, masked: bool = False, scale: float = 255.0) -> pd.DataFrame:
    """Table 1's measure for our runs: mean and sd of |deformed - study| per pair and method.

    Parameters
    ----------
    pairs : mapping of str to RegistrationPair
        Pair name -> pair (its study, and its mask when ``masked``).
    deformed : mapping of str to mapping of str to numpy.ndarray
        Pair name -> {column label -> deformed template (H, W)}; every pair name in ``pairs``.
    masked : bool, optional
        Average over the pair's foreground mask instead of the whole image (default False).
    scale : float, optional
        Grey-level scale, > 0 (default 255 for the paper's 0-255 levels; our images are in [0, 1]).

    Returns
    -------
    pandas.DataFrame
        Rows the pairs, columns (label, "mean" or "sd").

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    Table 1.
    """
    check_bool(masked, "masked")  # scale: checked by grey_level_difference, which takes it
    check_instance(pairs, "pairs", Mapping, what="a mapping (a dict) by pair name")
    check_instance(deformed, "deformed", Mapping, what="a mapping (a dict) by pair name")
    table = {}
    for name, images in deformed.items():
        check_choice(name, "deformed's pair name (a key of pairs)", pairs)
        pair = pairs[name]
        for label, image in images.items():
            mean, sd = grey_level_difference(image, pair.study, pair.mask if masked else None, scale=scale)
            table[(label, "mean")] = {**table.get((label, "mean"), {}), name: mean}
            table[(label, "sd")] = {**table.get((label, "sd"), {}), name: sd}
    return pd.DataFrame(table).rename_axis("pair")


def mean_sd_strings(table: pd.DataFrame) -> pd.DataFrame:
    """Collapse (label, "mean"/"sd") columns into one "mean / sd" text column per label, two decimals.

    Parameters
    ----------
    table : pandas.DataFrame
        Columns (label, "mean") and (label, "sd"), as from :func:`grey_level_table` or
        :func:`paper_table1`.

    Returns
    -------
    pandas.DataFrame
        Same rows, one text column per label.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    Table 1 (its "mean / sd" layout).
    """
    check_dataframe(table, "table")
    labels = list(dict.fromkeys(label for label, _ in table.columns))
    return pd.DataFrame({label: [f"{m:.2f} / {s:.2f}" for m, s in
                                 zip(table[(label, "mean")], table[(label, "sd")])] for label in labels},
                        index=table.index)


def accuracy_row(pair: RegistrationPair, warped: np.ndarray, displacement: np.ndarray,
                 backward: np.ndarray | None = None, scale: float = 255.0) -> dict[str, float]:
    """What an atlas user cares about, against the pair's known warp, on its mask.

    Parameters
    ----------
    pair : RegistrationPair
        The pair registered (study, true displacement and mask).
    warped : numpy.ndarray of float, shape (H, W)
        The deformed template, grey levels within ±1e30.
    displacement : numpy.ndarray of float, shape (2, H, W)
        The estimated displacement, pixels.
    backward : numpy.ndarray of float, shape (2, H, W), optional
        The registration of the study onto the template, pixels.
    scale : float, optional
        Grey-level scale, > 0 (default 255).

    Returns
    -------
    dict of str to float
        "residual (mask)" (mean |warped - study|, grey levels), "RMSE px" (displacement error),
        "min det" (smallest det(I - ∇u)), "folded %" (share of pixels with det ≤ 0) and
        "inverse consistency px" (NaN without ``backward``).

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    Table 1 and Sec. 5.
    """
    check_instance(pair, "pair", RegistrationPair)
    warped = as_finite_array(warped, "warped", shape=pair.study.shape, max_abs=MAX_GREY_LEVEL)
    det = jacobian_determinant(displacement)
    return {"residual (mask)": grey_level_difference(warped, pair.study, pair.mask, scale=scale)[0],
            "RMSE px": displacement_rmse(displacement, pair.true_displacement, pair.mask),
            "min det": float(det.min()), "folded %": 100.0 * float(np.mean(det <= 0)),
            "inverse consistency px": (np.nan if backward is None
                                       else inverse_consistency_error(displacement, backward, pair.mask))}
