"""Formula parsing and sum-to-zero design matrices (the fixed part of eq. 2)."""

from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations

import numpy as np
import pandas as pd

from amdo_lab.common import as_finite_array, check_dataframe, check_instance, check_positive_int

__all__ = ["DesignMatrix", "parse_formula", "group_indices", "PAPER_FORMULA",
           "SIZE_FORMULA"]

#: Eq. (2): main effects U, M, D, F; interactions UM, UF, UD, MF, MD, DF and MDF.
PAPER_FORMULA = "Y ~ U + M + D + F + U:M + U:F + U:D + M:F + M:D + D:F + M:D:F"
#: The starting model of Sec. 6: eq. (2) without MDF plus image size S and its two-way terms.
SIZE_FORMULA = ("Y ~ U + M + D + F + S + U:M + U:F + U:D + M:F + M:D + D:F"
                " + S:U + S:M + S:D + S:F")


def parse_formula(formula: str) -> tuple[str, list[tuple[str, ...]]]:
    """Split ``"Y ~ A * B + C"`` into the response and the ordered list of terms.

    ``A * B`` expands to ``A + B + A:B``; ``A:B`` is the interaction alone; ``1`` (the intercept,
    always present) is dropped. Terms are ordered by interaction order, then by first appearance;
    duplicates are dropped.

    Parameters
    ----------
    formula : str
        A formula ``"response ~ term + term + ..."`` with exactly one ``~``.

    Returns
    -------
    response : str
        The name left of ``~``.
    terms : list of tuple of str
        Each term as the tuple of the variables it multiplies, e.g. ``("M", "D")`` for ``M:D``.

    References
    ----------
    Givens et al. (2004), AMDO, LNCS 3179, eq. (2) (the fixed part: U, M, D, F and their interactions).
    """
    if not isinstance(formula, str) or formula.count("~") != 1:
        raise ValueError(f"fixed must be a formula 'response ~ terms', got {formula!r}")
    lhs, rhs = (part.strip() for part in formula.split("~"))
    if not lhs:
        raise ValueError(f"fixed must name a response, got {formula!r}")
    terms: list[tuple[str, ...]] = []
    for chunk in rhs.split("+"):
        chunk = chunk.strip()
        if chunk == "1":  # the intercept, always present
            continue
        if "*" in chunk:
            names = [c.strip() for c in chunk.split("*")]
            expanded = [combo for r in range(1, len(names) + 1) for combo in combinations(names, r)]
        else:
            expanded = [tuple(c.strip() for c in chunk.split(":"))]
        for term in expanded:
            if any(not name for name in term):  # an empty term (no term at all) or an empty variable name
                raise ValueError(f"fixed has an empty term or variable name: {formula!r}")
            if term not in terms:
                terms.append(term)
    terms.sort(key=len)  # stable: keeps first-appearance order within an order
    return lhs, terms


@dataclass(frozen=True)
class DesignMatrix:
    """A fixed-effects design matrix with its term structure.

    Parameters
    ----------
    matrix : ndarray, shape (n, n_columns)
        The design X; column 0 is the intercept, then one block of columns per term.
    column_names : tuple of str
        One name per column, e.g. ``"(Intercept)"``, ``"M[l2]"``, ``"M[l2]:D[fixed]"``.
    term_columns : dict
        Term name (``"M:D"``) -> slice of its columns in ``matrix``.
    levels : dict
        Variable -> tuple of its levels in coding order (None for a numeric variable).

    References
    ----------
    Givens et al. (2004), AMDO, LNCS 3179, eq. (2): X beta is the fixed part of the linear predictor.
    """

    matrix: np.ndarray                 # (n, n_columns), first column the intercept
    column_names: tuple[str, ...]
    term_columns: dict                 # term name -> slice of columns
    levels: dict                       # variable -> tuple of levels (None for numeric)


def _variable_coding(column: pd.Series, name: str, levels=None) -> tuple[np.ndarray, list[str], tuple | None]:
    """Sum-to-zero (effect) coding of a factor, or the numeric column itself."""
    is_factor = isinstance(column.dtype, pd.CategoricalDtype) or not pd.api.types.is_numeric_dtype(column)
    if not is_factor:
        values = as_finite_array(column.to_numpy(dtype=float), f"column {name!r}")
        return values[:, None], [name], None
    if column.isna().any():
        raise ValueError(f"column {name!r} has missing values")
    if levels is None:
        if isinstance(column.dtype, pd.CategoricalDtype):
            levels = tuple(column.cat.categories)
            used = set(column.unique())
            missing = [lev for lev in levels if lev not in used]
            if missing:
                raise ValueError(f"factor {name!r} has levels with no rows: {missing}")
        else:
            levels = tuple(sorted(column.unique(), key=str))
    check_positive_int(len(levels), f"the levels of factor {name!r} {list(levels)}", minimum=2)
    codes = pd.Categorical(column, categories=list(levels)).codes
    if np.any(codes < 0):
        raise ValueError(f"factor {name!r} has values outside its levels {list(levels)}")
    contrast = np.vstack([np.eye(len(levels) - 1), -np.ones(len(levels) - 1)])
    return contrast[codes], [f"{name}[{lev}]" for lev in levels[:-1]], tuple(levels)


def _build_design(table: pd.DataFrame, terms: list[tuple[str, ...]], levels: dict | None = None) -> DesignMatrix:
    """Intercept plus one block of sum-to-zero coded columns per term (row-wise products of codings).

    A factor with L levels gets L-1 columns: level j < L-1 is the unit vector e_j, the last level is
    -1 in every column (effect coding), so each main effect sums to zero over its levels, as SAS's
    Type III tests assume. A numeric column enters as it is.

    Parameters
    ----------
    table : pandas.DataFrame
        One row per observation; text and categorical columns are factors (a categorical column's
        categories fix its level order and must all occur), numeric columns are covariates.
    terms : list of tuple of str
        Terms as :func:`parse_formula` returns them (the callers parse a checked formula).
    levels : dict, optional
        Factor name -> the levels to code it with (e.g. those of a fit, to code new data alike).

    Returns
    -------
    DesignMatrix
        The matrix of shape (len(table), 1 + total columns of the terms) and its column names,
        term slices and levels.

    References
    ----------
    Givens et al. (2004), AMDO, LNCS 3179, eq. (2) (the fixed effects of the model).
    """
    variables = sorted({v for term in terms for v in term})
    check_dataframe(table, "table (the terms of fixed)", columns=variables)  # names both: either may be wrong
    levels = dict(levels or {})
    codings = {}
    for v in variables:
        block, names, lev = _variable_coding(table[v], v, levels.get(v))
        codings[v] = (block, names)
        levels[v] = lev
    n = len(table)
    blocks, names, term_columns = [np.ones((n, 1))], ["(Intercept)"], {"(Intercept)": slice(0, 1)}
    start = 1
    for term in terms:
        block, block_names = np.ones((n, 1)), [""]
        for v in term:
            coding, coding_names = codings[v]
            block = (block[:, :, None] * coding[:, None, :]).reshape(n, -1)
            block_names = [f"{a}:{b}" if a else b for a in block_names for b in coding_names]
        blocks.append(block)
        names += block_names
        term_columns[":".join(term)] = slice(start, start + block.shape[1])
        start += block.shape[1]
    return DesignMatrix(np.hstack(blocks), tuple(names), term_columns, levels)


def group_indices(table: pd.DataFrame, term: str) -> np.ndarray:
    """Integer level index (0..q-1) of a grouping term such as ``"t"`` or ``"t:p"``.

    Parameters
    ----------
    table : pandas.DataFrame
        Holds every column the term names, without missing values.
    term : str
        One column (``"p"``) or several joined by ``:`` (``"t:p"``: one level per pair).

    Returns
    -------
    ndarray of int, shape (len(table),)
        The row's level of the term, numbered in sorted order of the levels.

    References
    ----------
    Givens et al. (2004), AMDO, LNCS 3179, eq. (2): the random intercepts of training set t, probe p and their interaction.
    """
    check_instance(term, "term", str, what="a grouping term such as 't' or 't:p'")
    names = [s.strip() for s in term.split(":")]
    check_dataframe(table, f"table (random term {term!r})", columns=names)  # names both: either may be wrong
    for v in names:
        if table[v].isna().any():
            raise ValueError(f"random term column {v!r} has missing values")
    if len(names) == 1:
        return pd.factorize(table[names[0]], sort=True)[0]
    keys = pd.MultiIndex.from_frame(table[names].astype(str))
    return pd.factorize(keys, sort=True)[0]


