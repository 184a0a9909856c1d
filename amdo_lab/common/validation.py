"""Input validation at the public boundary: clear errors that name the argument.

Nothing is silently dropped, clipped or coerced: a NaN in gives a ``ValueError`` out.

The label rule: a helper's label arguments (``name``, ``what``, ``names``, ``first_name``, ...) only
word its messages, so any string is valid and anything else (None, a number) is refused with a
``TypeError`` naming the label's parameter; the arguments that state a helper's rule (``shape``,
``dtype``, ``bounds``, ``max_abs``, ``minimum``, ...) are refused by name when they cannot state one.
"""

from __future__ import annotations

import numbers
from collections.abc import Iterable, Sequence

import numpy as np

__all__ = [
    "MAX_ITERATIONS",
    "MAX_LEVELS",
    "MAX_SAMPLES",
    "MAX_SIDE",
    "as_bool_mask",
    "as_finite_array",
    "as_image_pair",
    "as_outcomes",
    "as_points",
    "as_probabilities",
    "as_rotation",
    "as_weights",
    "check_axes",
    "check_bool",
    "check_choice",
    "check_dataframe",
    "check_fitted",
    "check_image_shape",
    "check_in_range",
    "check_instance",
    "check_names",
    "check_odd_int",
    "check_overflow",
    "check_same_shape",
    "check_seed",
    "check_sequence_of",
    "check_positive",
    "check_positive_int",
]

# The bounds on counts (CONTRIBUTING.md, "Bounds"): a count beyond them would hang or exhaust memory
# on a laptop instead of failing with a message, so ``check_positive_int(..., maximum=...)`` refuses it
# by name. Each is generous: a hundred times the largest value the notebooks, benchmarks and tests use.

#: Iterations, sweeps, passes, time steps, frames or trials of one call (each costs at least one pass
#: over the data: 100,000 of them run in minutes only on small data).
MAX_ITERATIONS = 100_000
#: Points, samples, particles, lines, features or scenes drawn or processed by one call (each holds a
#: few floats; a million of them fit a laptop's memory with the work arrays around them).
MAX_SAMPLES = 1_000_000
#: Resolution levels (a coarse-to-fine schedule: each halves a scale, so 64 span 1e-19).
MAX_LEVELS = 64
#: Pixels, bins or grid nodes along one axis (a square of 4,096 per side is 16.8 million values).
MAX_SIDE = 4_096


def as_finite_array(
    value: object,
    name: str,
    *,
    ndim: int | None = None,
    shape: Sequence[int | None] | None = None,
    allow_empty: bool = False,
    dtype: type = float,
    max_abs: float | None = None,
    bounds: tuple[float, float] | None = None,
    closed: str = "both",
) -> np.ndarray:
    """Convert ``value`` to a finite numeric array, or raise an error naming ``name``.

    Parameters
    ----------
    value : array_like
        The user's input.
    name : str
        The argument's name, used in error messages.
    ndim : int, optional
        Required number of dimensions.
    shape : sequence of int or None, optional
        Required shape; ``None`` entries accept any length (e.g. ``(None, 3)`` for 3-D points).
    allow_empty : bool
        Whether a zero-size array is accepted.
    dtype : type
        Target dtype (float by default). Booleans and non-numeric inputs raise ``TypeError``; an
        integer ``dtype`` refuses fractional values instead of truncating them.
    max_abs : float, optional
        Largest accepted magnitude. A computation that squares or sums its input overflows
        float64 (about 1.8e308) beyond about 1e150, so such a function passes a bound and refuses
        the input by name instead of returning inf or NaN (the overflow policy of CONTRIBUTING.md).
    bounds : (float, float), optional
        Interval every element must lie in, e.g. ``(0, 1)`` for probabilities or ``(0, np.inf)``
        for lengths; the first element outside is named in the error.
    closed : {"both", "left", "right", "neither"}
        Which ends of ``bounds`` belong to the interval (as in :func:`check_in_range`).

    Returns
    -------
    numpy.ndarray
        A new array of ``dtype`` (the input is never modified).
    """
    _check_rule_arguments(name=name, shape=shape, dtype=dtype, max_abs=max_abs, bounds=bounds)
    check_bool(allow_empty, "allow_empty")
    if ndim is not None:
        check_positive_int(ndim, "ndim", minimum=0, maximum=32)
    check_choice(closed, "closed", ("both", "left", "right", "neither"))
    array = np.asarray(value)
    if array.dtype == object or not np.issubdtype(array.dtype, np.number):
        # booleans are refused too: a mask passed where numbers are expected is a mistake
        raise TypeError(f"{name} must be a numeric array, got dtype {array.dtype}")
    if np.issubdtype(array.dtype, np.complexfloating):
        raise TypeError(f"{name} must be real-valued, got dtype {array.dtype}")
    if shape is not None:
        ndim = len(shape)
    if ndim is not None and array.ndim != ndim:
        expected = f"shape {_format_shape(shape)}" if shape is not None else f"{ndim} dimensions"
        raise ValueError(f"{name} must have {expected}, got shape {array.shape}")
    if shape is not None:
        for axis, (got, want) in enumerate(zip(array.shape, shape)):
            if want is not None and got != want:
                raise ValueError(
                    f"{name} must have shape {_format_shape(shape)}, got {array.shape} "
                    f"(axis {axis} is {got}, expected {want})"
                )
    if array.size == 0 and not allow_empty:
        raise ValueError(f"{name} must not be empty, got shape {array.shape}")
    if np.issubdtype(np.dtype(dtype), np.integer) and np.issubdtype(array.dtype, np.floating):
        # checked before the cast, which would turn NaN into an arbitrary integer and 1.5 into 1
        _check_finite(array, name)
        if np.any(array != np.trunc(array)):
            raise ValueError(f"{name} must hold whole numbers, got a fractional value")
        # and before the cast, which would turn 1e308 into an arbitrary integer
        limit = min(max_abs if max_abs is not None else np.inf, float(np.iinfo(np.dtype(dtype)).max))
        if array.size and np.max(np.abs(array)) > limit:
            raise ValueError(f"{name} must be at most {limit:g} in magnitude, got {np.max(np.abs(array)):g}")
    array = array.astype(dtype, copy=True)
    if np.issubdtype(array.dtype, np.floating):
        _check_finite(array, name)
    if max_abs is not None and array.size and np.max(np.abs(array)) > max_abs:
        raise ValueError(f"{name} must be at most {max_abs:g} in magnitude (larger values overflow in the "
                         f"computation), got {np.max(np.abs(array)):g}")
    if bounds is not None and array.size:
        _check_bounds(array, name, bounds, closed)
    return array


def _check_bounds(array: np.ndarray, name: str, bounds: tuple[float, float], closed: str) -> None:
    """Raise naming ``name`` and its first element outside ``bounds`` (ends per ``closed``)."""
    low, high = bounds
    left_ok = array >= low if closed in ("left", "both") else array > low
    right_ok = array <= high if closed in ("right", "both") else array < high
    outside = ~(left_ok & right_ok)
    if np.any(outside):
        index = tuple(int(i) for i in np.argwhere(outside)[0])
        opening = "[" if closed in ("left", "both") else "("
        ending = "]" if closed in ("right", "both") else ")"
        where = f" at index {index if len(index) > 1 else index[0]}" if array.ndim else ""
        raise ValueError(f"{name} must lie in {opening}{low:g}, {high:g}{ending}, got {array[index]:g}{where}")


def _check_finite(array: np.ndarray, name: str) -> None:
    if not np.all(np.isfinite(array)):
        n_bad = int(np.size(array) - np.count_nonzero(np.isfinite(array)))
        raise ValueError(f"{name} must be finite, got {n_bad} NaN or infinite value(s)")


def _format_shape(shape: Sequence[int | None]) -> str:
    parts = ["n" if s is None else str(s) for s in shape]
    return "(" + ", ".join(parts) + ("," if len(parts) == 1 else "") + ")"


def check_positive(value: object, name: str, *, allow_zero: bool = False) -> float:
    """Return ``value`` as a float after checking it is a finite positive real number.

    Parameters
    ----------
    value : real number
        The user's input (a bool is refused).
    name : str
        The argument's name, used in error messages.
    allow_zero : bool
        Whether 0 is accepted.

    Returns
    -------
    float
        ``value``.
    """
    _check_rule_arguments(name=name)
    check_bool(allow_zero, "allow_zero")
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a real number, got {type(value).__name__}")
    number = float(value)
    if not np.isfinite(number):
        raise ValueError(f"{name} must be finite, got {number}")
    if number < 0 or (number == 0 and not allow_zero):
        bound = "non-negative" if allow_zero else "positive"
        raise ValueError(f"{name} must be {bound}, got {number}")
    return number


def check_positive_int(value: object, name: str, *, minimum: int = 1, maximum: int | None = None) -> int:
    """Return ``value`` as an int after checking it is an integer in ``[minimum, maximum]``.

    Parameters
    ----------
    value : int
        The user's input (a bool or a float is refused, even 2.0).
    name : str
        The argument's name, used in error messages.
    minimum : int
        Smallest accepted value.
    maximum : int, optional
        Largest accepted value: a count of iterations, particles or pixels that a laptop runs in
        minutes. A larger count would hang or exhaust memory instead of failing with a message.

    Returns
    -------
    int
        ``value``.
    """
    _check_rule_arguments(name=name, minimum=minimum)
    for bound, label in ((minimum, "minimum"), (maximum, "maximum")):
        if bound is not None and (isinstance(bound, bool) or not isinstance(bound, numbers.Integral)):
            raise TypeError(f"{label} must be an int, got {type(bound).__name__}")
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} must be an int, got {type(value).__name__}")
    if value < minimum:
        raise ValueError(f"{name} must be at least {minimum}, got {value}")
    if maximum is not None and value > maximum:
        raise ValueError(f"{name} must be at most {maximum:,}, got {value:,}")
    return int(value)


def as_points(value: object, name: str, *, dim: int, allow_empty: bool = True,
              max_abs: float | None = None) -> np.ndarray:
    """Return ``value`` as finite points ``(n, dim)``, or one point ``(dim,)``, or raise naming ``name``.

    Parameters
    ----------
    value : array_like
        The user's input: points as rows.
    name : str
        The argument's name, used in error messages.
    dim : int
        Required length of the last axis (2 for the plane, 3 for space).
    allow_empty : bool
        Whether an empty ``(0, dim)`` set is accepted.
    max_abs : float, optional
        Largest accepted magnitude (see :func:`as_finite_array`).

    Returns
    -------
    numpy.ndarray
        A new float array of the input's shape.
    """
    _check_rule_arguments(max_abs=max_abs, dim=dim)
    points = as_finite_array(value, name, allow_empty=allow_empty, max_abs=max_abs)
    if points.ndim not in (1, 2) or points.shape[-1] != dim:
        raise ValueError(f"{name} must have shape (n, {dim}) or ({dim},), got {points.shape}")
    return points


def as_probabilities(value: object, name: str, *, atol: float = 1e-6) -> np.ndarray:
    """Return ``value`` as a 1-D array of non-negative weights summing to 1 (to ``atol``), or raise.

    Parameters
    ----------
    value : array_like
        The user's input (normalised particle weights, a discrete distribution).
    name : str
        The argument's name, used in error messages.
    atol : float
        Largest accepted deviation of the sum from 1.

    Returns
    -------
    numpy.ndarray
        A new float array.
    """
    check_positive(atol, "atol")
    weights = as_finite_array(value, name, ndim=1)
    if np.any(weights < 0) or not np.isclose(weights.sum(), 1.0, rtol=0.0, atol=atol):
        raise ValueError(f"{name} must be non-negative and sum to 1, got sum {weights.sum():.6g}")
    return weights


def as_rotation(value: object, name: str, *, tol: float = 1e-6) -> np.ndarray:
    """Return ``value`` as a proper rotation ``(d, d)`` (or a stack ``(..., d, d)``), or raise naming ``name``.

    Parameters
    ----------
    value : array_like
        The user's input: orthonormal with determinant +1.
    name : str
        The argument's name, used in error messages.
    tol : float
        Largest accepted deviation of ``R^T R`` from the identity and of ``det R`` from 1.

    Returns
    -------
    numpy.ndarray
        A new float array.
    """
    check_positive(tol, "tol")
    rotation = as_finite_array(value, name)
    if rotation.ndim < 2 or rotation.shape[-1] != rotation.shape[-2]:
        raise ValueError(f"{name} must be a square (d, d) matrix or a stack (..., d, d), got shape {rotation.shape}")
    gram = np.swapaxes(rotation, -1, -2) @ rotation
    gram_error = np.max(np.abs(gram - np.eye(rotation.shape[-1])), initial=0.0)
    if gram_error > tol or np.any(np.abs(np.linalg.det(rotation) - 1.0) > tol):
        raise ValueError(f"{name} must be a rotation (orthonormal, determinant +1), "
                         f"got R^T R off the identity by {gram_error:.3g}")
    return rotation


def as_weights(value: object, name: str, *, n: int) -> np.ndarray:
    """Return ``value`` as ``n`` non-negative weights with a positive sum (not normalised), or raise.

    Parameters
    ----------
    value : array_like
        The user's input.
    name : str
        The argument's name, used in error messages.
    n : int
        Required length.

    Returns
    -------
    numpy.ndarray
        A new float array of shape ``(n,)``.
    """
    _check_rule_arguments(n=n)
    weights = as_finite_array(value, name, shape=(n,), bounds=(0, np.inf))
    with np.errstate(over="ignore"):
        total = weights.sum()
    if not 0 < total < np.inf:
        raise ValueError(f"{name} must be non-negative with a positive, finite sum, got {total:g}")
    return weights


def check_same_shape(first: np.ndarray, second: np.ndarray, first_name: str, second_name: str) -> None:
    """Raise naming both arguments unless the two arrays have the same shape.

    Parameters
    ----------
    first, second : numpy.ndarray
        Arrays already converted by :func:`as_finite_array`.
    first_name, second_name : str
        The arguments' names, used in the error message.
    """
    _check_rule_arguments(first_name=first_name, second_name=second_name)
    if np.shape(first) != np.shape(second):
        raise ValueError(f"{first_name} and {second_name} must have the same shape, "
                         f"got {np.shape(first)} and {np.shape(second)}")


def check_overflow(result: object, names: str) -> None:
    """Raise naming the inputs when a result computed from finite input is not finite (it overflowed).

    Parameters
    ----------
    result : array_like
        The computed values.
    names : str
        The inputs that drove it out of range, as the message should name them ("points and
        transform").
    """
    _check_rule_arguments(names=names)
    if not np.all(np.isfinite(result)):
        raise ValueError(f"{names} are too large: the result overflows a float")


def check_instance(value: object, name: str, expected: type | tuple[type, ...], *, what: str = "") -> object:
    """Return ``value`` after checking it is an instance of ``expected``, or raise a ``TypeError``.

    Parameters
    ----------
    value : object
        The user's input.
    name : str
        The argument's name, used in error messages.
    expected : type or tuple of types
        Accepted type(s).
    what : str, optional
        How the message names the expected type ("a matplotlib Figure"); by default the type names.

    Returns
    -------
    object
        ``value``.
    """
    _check_rule_arguments(name=name, what=what, expected=expected)
    if not isinstance(value, expected):
        types = expected if isinstance(expected, tuple) else (expected,)
        wanted = what or " or ".join(t.__name__ for t in types)
        raise TypeError(f"{name} must be {wanted}, got {type(value).__name__}")
    return value


def check_sequence_of(values: object, name: str, expected: type | tuple[type, ...], *, what: str) -> tuple:
    """Return ``values`` as a tuple after checking it is a non-empty sequence of instances of ``expected``.

    Parameters
    ----------
    values : sequence
        The user's input: a list or tuple (a string is refused).
    name : str
        The argument's name, used in error messages (an element is named ``name[i]``).
    expected : type or tuple of types
        Accepted type(s) of every element.
    what : str
        How the message names one element ("a Mesh or PointCloud").

    Returns
    -------
    tuple
        The elements, in their order.

    Examples
    --------
    >>> check_sequence_of([1.0, 2.0], "scales", float, what="a float")
    (1.0, 2.0)
    """
    _check_rule_arguments(name=name, what=what, expected=expected)
    if isinstance(values, (str, bytes)) or not isinstance(values, Sequence):
        raise TypeError(f"{name} must be a sequence of {what}, got {type(values).__name__}")
    if len(values) == 0:
        raise ValueError(f"{name} must hold at least one element ({what}), got an empty sequence")
    for position, value in enumerate(values):
        check_instance(value, f"{name}[{position}]", expected, what=what)
    return tuple(values)


def as_outcomes(value: object, name: str) -> np.ndarray:
    """Return ``value`` as a non-empty 1-D boolean array of per-item outcomes (True = right), or raise.

    Parameters
    ----------
    value : array_like of bool
        The user's input.
    name : str
        The argument's name, used in error messages.

    Returns
    -------
    numpy.ndarray
        ``value`` as a boolean array (not copied).
    """
    _check_rule_arguments(name=name)
    array = np.asarray(value)
    if array.dtype != bool:
        raise TypeError(f"{name} must be a boolean array (True = right), got dtype {array.dtype}")
    if array.ndim != 1 or array.size == 0:
        raise ValueError(f"{name} must be a non-empty 1-D array of per-item outcomes, got shape {array.shape}")
    return array


def check_seed(value: object, name: str) -> int:
    """Return ``value`` after checking it is a seed: a non-negative int (a ``Generator`` is handled by the caller).

    Parameters
    ----------
    value : int
        The user's input.
    name : str
        The argument's name, used in error messages.

    Returns
    -------
    int
        ``value``.
    """
    _check_rule_arguments(name=name)
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} must be a non-negative int or a numpy.random.Generator, got {type(value).__name__}")
    if value < 0:
        raise ValueError(f"{name} must be non-negative, got {value}")
    return int(value)


def check_odd_int(value: object, name: str, *, minimum: int = 3, maximum: int | None = None) -> int:
    """Return ``value`` as an int after checking it is an odd integer in ``[minimum, maximum]``.

    Windows and kernels centred on a pixel need an odd side (a 3x3 neighbourhood, a 7-tap filter).

    Parameters
    ----------
    value : int
        The user's input.
    name : str
        The argument's name, used in error messages.
    minimum, maximum : int
        Smallest and largest accepted values (``maximum`` optional).

    Returns
    -------
    int
        ``value``.
    """
    number = check_positive_int(value, name, minimum=minimum, maximum=maximum)
    if number % 2 == 0:
        raise ValueError(f"{name} must be odd (a window centred on a pixel), got {number}")
    return number


def check_dataframe(value: object, name: str, *, columns: Iterable[str] = ()) -> object:
    """Return ``value`` after checking it is a pandas DataFrame holding ``columns``.

    Parameters
    ----------
    value : pandas.DataFrame
        The user's input.
    name : str
        The argument's name, used in error messages.
    columns : iterable of str
        Columns the frame must have.

    Returns
    -------
    pandas.DataFrame
        ``value`` (not copied).
    """
    _check_rule_arguments(name=name, columns=columns)
    import pandas as pd  # pandas is a dependency of the package; imported here to keep common light

    if not isinstance(value, pd.DataFrame):
        raise TypeError(f"{name} must be a pandas DataFrame, got {type(value).__name__}")
    columns = list(columns)
    missing = [column for column in columns if column not in value.columns]
    if missing:
        raise ValueError(f"{name} must have columns {sorted(columns)}, missing {missing}")
    return value


def check_choice(value: object, name: str, choices: Iterable[object]) -> object:
    """Return ``value`` after checking it is one of ``choices``.

    Parameters
    ----------
    value : object
        The user's input.
    name : str
        The argument's name, used in error messages.
    choices : iterable
        The accepted values; the message lists them.

    Returns
    -------
    object
        ``value``.
    """
    _check_rule_arguments(name=name, choices=choices)
    options = list(choices)
    if value not in options:
        listed = ", ".join(repr(option) for option in options)
        raise ValueError(f"{name} must be one of {listed}; got {value!r}")
    return value


def check_image_shape(
    shape: object, name: str = "shape", *, minimum: int = 1, axes: str = "rows, cols"
) -> tuple[int, int]:
    """Return an image size as ``(rows, cols)`` Python ints, or raise an error naming ``name``.

    Parameters
    ----------
    shape : pair of int
        The user's input: a tuple, list or array of two ints (a float size would be truncated
        silently, so it is refused).
    name : str
        The argument's name, used in error messages.
    minimum : int
        Smallest number of rows and of columns accepted.
    axes : str
        How the message spells the pair, in the words of the caller's docstring (``"rows, cols"``
        or ``"H, W"``).

    Returns
    -------
    tuple of int
        ``(rows, cols)``.
    """
    _check_rule_arguments(name=name, axes=axes, minimum=minimum)
    if isinstance(shape, (str, bytes)) or not hasattr(shape, "__len__") or len(shape) != 2:
        raise ValueError(f"{name} must be a pair ({axes}), got {shape!r}")
    return (check_positive_int(shape[0], f"{name}[0]", minimum=minimum),
            check_positive_int(shape[1], f"{name}[1]", minimum=minimum))


def check_names(
    values: object, name: str, *, allowed: Iterable[str] | None = None, accept_single: bool = False
) -> tuple[str, ...]:
    """Return ``values`` as a tuple of distinct, non-empty names, or raise an error naming ``name``.

    Parameters
    ----------
    values : sequence of str
        The user's input: pose names, grouping terms, cue names, ...
    name : str
        The argument's name, used in error messages.
    allowed : iterable of str, optional
        The names accepted; the message lists them. ``None`` accepts any non-empty string.
    accept_single : bool
        Whether one bare string stands for a sequence of one name (``"p"`` for ``("p",)``);
        otherwise a string is refused, since iterating it would give its letters.

    Returns
    -------
    tuple of str
        The names, in the order given.
    """
    _check_rule_arguments(name=name, allowed=allowed)
    check_bool(accept_single, "accept_single")
    if isinstance(values, str) and accept_single:
        values = (values,)
    if isinstance(values, str) or not isinstance(values, Iterable):
        raise TypeError(f"{name} must be a sequence of names, got {type(values).__name__}")
    names = tuple(values)
    if not names:
        raise ValueError(f"{name} must hold at least one name, got an empty sequence")
    bad = [value for value in names if not isinstance(value, str) or not value.strip()]
    if bad:
        raise TypeError(f"{name} must hold non-empty strings, got {bad[0]!r}")
    if allowed is not None:
        known = list(allowed)
        unknown = [value for value in names if value not in known]
        if unknown:
            raise ValueError(f"{name} holds unknown name(s) {unknown}; known: {sorted(known)}")
    if len(set(names)) != len(names):
        raise ValueError(f"{name} must not repeat a name, got {names}")
    return names


def check_bool(value: object, name: str) -> bool:
    """Return ``value`` after checking it is a ``bool`` (``'yes'``, ``1`` or ``None`` are refused).

    Parameters
    ----------
    value : bool
        The user's input (``numpy.bool_`` is accepted).
    name : str
        The argument's name, used in error messages.

    Returns
    -------
    bool
        ``value``.
    """
    _check_rule_arguments(name=name)
    if not isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{name} must be True or False, got {type(value).__name__}")
    return bool(value)


def check_in_range(
    value: object,
    name: str,
    low: float,
    high: float,
    *,
    closed: str = "neither",
) -> float:
    """Return ``value`` as a float after checking ``low < value < high`` (ends per ``closed``).

    Parameters
    ----------
    value : real number
        The user's input.
    name : str
        The argument's name, used in error messages.
    low, high : float
        The interval's ends.
    closed : {"neither", "left", "right", "both"}
        Which ends belong to the interval: ``"neither"`` is the open interval, e.g. a probability
        that must not be 0 or 1.

    Returns
    -------
    float
        ``value``.
    """
    _check_rule_arguments(name=name, low=low, high=high)
    check_choice(closed, "closed", ("neither", "left", "right", "both"))
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a real number, got {type(value).__name__}")
    number = float(value)
    if not np.isfinite(number):
        raise ValueError(f"{name} must be finite, got {number}")
    left_ok = number >= low if closed in ("left", "both") else number > low
    right_ok = number <= high if closed in ("right", "both") else number < high
    if not (left_ok and right_ok):
        opening = "[" if closed in ("left", "both") else "("
        ending = "]" if closed in ("right", "both") else ")"
        raise ValueError(f"{name} must be in {opening}{low:g}, {high:g}{ending}, got {number}")
    return number


def as_bool_mask(value: object, name: str, *, shape: Sequence[int] | None = None) -> np.ndarray:
    """Return a copy of ``value`` as a boolean array, after checking its dtype and shape.

    Numbers are refused rather than thresholded: 0/1 floats passed as a mask are often a mistake
    (a probability map, an image) that a silent cast would hide.

    Parameters
    ----------
    value : array_like of bool
        The user's mask.
    name : str
        The argument's name, used in error messages.
    shape : sequence of int, optional
        Required shape.

    Returns
    -------
    numpy.ndarray
        A boolean copy (the caller's array is never modified).
    """
    _check_rule_arguments(name=name, shape=shape)
    array = np.asarray(value)
    if array.dtype != bool:
        raise TypeError(f"{name} must be a boolean array, got dtype {array.dtype}")
    if shape is not None and array.shape != tuple(shape):
        raise ValueError(f"{name} must have shape {tuple(shape)}, got {array.shape}")
    if array.size == 0:
        raise ValueError(f"{name} must not be empty, got shape {array.shape}")
    return array.copy()


def as_image_pair(
    first: object, second: object, names: tuple[str, str] = ("template", "study"), *, ndim: int = 2
) -> tuple[np.ndarray, np.ndarray]:
    """Two finite float images of one shape (e.g. a registration's template and study).

    Parameters
    ----------
    first, second : array_like
        The two images.
    names : tuple of str
        Their argument names, used in error messages.
    ndim : int
        Required number of dimensions of each.

    Returns
    -------
    tuple of numpy.ndarray
        Float copies of ``first`` and ``second``.
    """
    _check_rule_arguments(pair_names=names)
    check_positive_int(ndim, "ndim", maximum=3)
    a = as_finite_array(first, names[0], ndim=ndim)
    b = as_finite_array(second, names[1], ndim=ndim)
    if a.shape != b.shape:
        raise ValueError(f"{names[0]} and {names[1]} must have the same shape, got {a.shape} and {b.shape}")
    return a, b


def check_axes(ax: object, name: str = "ax") -> object:
    """Return ``ax`` after checking it is a matplotlib ``Axes``.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The user's axes.
    name : str
        The argument's name, used in error messages.

    Returns
    -------
    matplotlib.axes.Axes
        ``ax``.
    """
    _check_rule_arguments(name=name)
    from matplotlib.axes import Axes  # here, not at the top: validation must not need matplotlib

    return check_instance(ax, name, Axes, what="a matplotlib Axes")


def check_fitted(estimator: object, attributes: str | Sequence[str]) -> None:
    """Raise scikit-learn's ``NotFittedError`` when ``estimator`` lacks the learned ``attributes``.

    Learned attributes end with an underscore (scikit-learn's convention), so an estimator is
    fitted when they exist. ``NotFittedError`` subclasses ``ValueError``.

    Parameters
    ----------
    estimator : object
        The estimator to check.
    attributes : str or sequence of str
        Learned attributes that exist (and are not None) once it is fitted.
    """
    _check_rule_arguments(attributes=attributes)
    from sklearn.exceptions import NotFittedError

    wanted = [attributes] if isinstance(attributes, str) else list(attributes)
    missing = [a for a in wanted if getattr(estimator, a, None) is None]
    if missing:
        raise NotFittedError(
            f"estimator {type(estimator).__name__} is not fitted yet: call fit(...) before using it "
            f"(attributes missing: {', '.join(missing)})"
        )


#: Parameters of the helpers above that only label a message (CONTRIBUTING.md's label rule).
_LABELS = ("name", "what", "first_name", "second_name", "names", "axes")


def _check_rule_arguments(**arguments: object) -> None:
    """Check the arguments that state a helper's rule or label its messages, by their names.

    The label rule: a label (``name``, ``what``, ``names``, ...) only words a message, so any string
    is valid and anything else is refused with a ``TypeError`` naming the label's parameter (a
    number or None there is a mistake in the calling code that would otherwise surface only when
    the message is formatted, or never). The rule arguments (``shape``, ``dtype``, ``bounds``,
    ``max_abs``, ``minimum``, ``low``/``high``, ``n``, ``choices``, ``columns``, ``allowed``,
    ``attributes``, ``expected``, ``dim``) are refused by name when they cannot state a rule (a string
    as ``choices``, a ``dim`` that is not a positive int).
    """
    for key, value in arguments.items():
        if key in _LABELS and not isinstance(value, str):
            raise TypeError(f"{key} must be a str (it words the error message), got {type(value).__name__}")
        if key == "pair_names" and not (isinstance(value, tuple) and len(value) == 2
                                        and all(isinstance(v, str) for v in value)):
            raise TypeError(f"names must be a pair of str (they word the error messages), got {value!r}")
        if key == "shape" and value is not None and (isinstance(value, (str, bytes)) or not isinstance(
                value, Sequence) or not all(v is None or isinstance(v, numbers.Integral) for v in value)):
            raise TypeError(f"shape must be a sequence of ints (None: any length), got {value!r}")
        if key == "dtype" and not (isinstance(value, type) and np.issubdtype(value, np.number)):
            raise TypeError(f"dtype must be a numeric type (float, int, np.float32, ...), got {value!r}")
        if key == "max_abs" and value is not None:
            check_positive(value, "max_abs")
        if key == "bounds" and value is not None and not (
                isinstance(value, tuple) and len(value) == 2 and value[0] <= value[1]):
            raise TypeError(f"bounds must be a pair (low, high) with low <= high, got {value!r}")
        if key in ("low", "high") and (isinstance(value, bool) or not isinstance(value, numbers.Real)
                                       or np.isnan(value)):
            raise TypeError(f"{key} must be a real number, got {value!r}")
        if key in ("minimum", "n") and (isinstance(value, bool) or not isinstance(value, numbers.Integral)):
            raise TypeError(f"{key} must be an int, got {type(value).__name__}")
        if key in ("choices", "columns", "allowed", "attributes") and not isinstance(value, Iterable) and not (
                key == "allowed" and value is None):
            raise TypeError(f"{key} must be an iterable, got {type(value).__name__}")
        if key == "choices" and isinstance(value, (str, bytes)):  # a string would be split into characters
            raise TypeError(f"choices must be a collection of options, not a string, got {value!r}")
        if key == "dim" and (isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < 1):
            raise TypeError(f"dim must be a positive int, got {value!r}")
        if key == "expected" and not (isinstance(value, type) or (
                isinstance(value, tuple) and value and all(isinstance(v, type) for v in value))):
            raise TypeError(f"expected must be a type or a tuple of types, got {value!r}")
