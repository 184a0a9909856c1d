"""What the bad-input test shares with the per-subpackage tables: a case, and the spoiled values."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class Case:
    """One public callable: how to call it validly, and the kind of each argument to spoil."""

    function: Callable[..., object]
    valid: dict[str, object]
    kinds: dict[str, str]
    #: the word an error must contain for each argument (default: the argument's own name)
    names: dict[str, str] = field(default_factory=dict)
    #: (argument, spoiled label) pairs that are valid input for this callable
    accept: frozenset[tuple[str, str]] = frozenset()
    #: For an operation with a known answer: ``check(result, arguments)`` returns what is wrong with a
    #: returned result (or None), so a call that returns a finite but wrong answer counts as a silent
    #: accept; it must pass on the valid call.
    check: Callable[[object, dict], str | None] | None = None


#: A finite value far out of any range: a function must either refuse it by name or return finite
#: output (the overflow policy of CONTRIBUTING.md), never NaN or inf.
HUGE = 1e308
#: Counts far beyond any maximum: a count argument must refuse them by name (a documented maximum
#: that fits the method), not hang, exhaust memory or return a degenerate result.
HUGE_COUNTS = (("a billion", 10**9), ("2**63", 2**63))
#: Spoiled labels that are finite input: a call that returns finite output for them is sensible.
FINITE_LABELS = frozenset({"huge", "huge inside", "huge everywhere"})


def all_finite(value: object, depth: int = 0) -> bool:
    """Whether every number in ``value`` (arrays, numbers, containers, dataclasses, tables) is finite."""
    if depth > 4 or value is None or isinstance(value, (str, bytes, bool)):
        return True
    if isinstance(value, (int, float, np.number)):
        return bool(np.isfinite(value))
    if isinstance(value, np.ndarray):
        return not np.issubdtype(value.dtype, np.number) or bool(np.all(np.isfinite(value)))
    if hasattr(value, "select_dtypes"):  # a pandas DataFrame
        return bool(np.all(np.isfinite(value.select_dtypes("number").to_numpy(dtype=float))))
    if isinstance(value, dict):
        return all(all_finite(v, depth + 1) for v in value.values())
    if isinstance(value, (list, tuple)):
        return all(all_finite(v, depth + 1) for v in value)
    if dataclasses.is_dataclass(value):
        return all(all_finite(getattr(value, f.name), depth + 1) for f in dataclasses.fields(value))
    return True


def rotation_problem(rotation: object, angle: float | None = None, axis: object = None) -> str | None:
    """What is wrong with ``rotation`` as a proper rotation by ``angle`` about ``axis`` (None if nothing)."""
    r = np.asarray(rotation, dtype=float)
    if not np.allclose(r.T @ r, np.eye(len(r)), atol=1e-9) or not np.isclose(np.linalg.det(r), 1.0, atol=1e-9):
        return "not a proper rotation"
    if angle is not None:
        cos_angle = np.cos(float(angle))
        turned = (np.trace(r) - (len(r) - 2)) / 2  # 2-D: trace = 2 cos; 3-D: trace = 1 + 2 cos
        if not np.isclose(turned, cos_angle, atol=1e-9):
            return f"turns by arccos {turned:.6g}, expected cos {cos_angle:.6g}"
    if axis is not None:
        unit = np.asarray(axis, dtype=float) / np.max(np.abs(axis))
        if not np.allclose(r @ unit, unit, atol=1e-9 * np.linalg.norm(unit)):
            return "moves its own axis"
    return None


def spoil(kind: str, valid: object) -> list[tuple[str, object]]:
    """Bad values of one kind of argument, each with a label."""
    common = [("None", None), ("a string", "abc")]
    if kind in ("array", "image", "points", "bool_array"):
        array = np.asarray(valid)
        bad = common + [("a bool", True), ("an empty array", np.empty((0,) + array.shape[1:], array.dtype)),
                        ("one more axis", array[None])]
        if array.ndim >= 1:
            bad.append(("a wrong trailing axis", np.zeros(array.shape[:-1] + (array.shape[-1] + 1,), array.dtype)))
        if kind == "bool_array":
            return bad + [("numbers for a mask", array.astype(float))]
        with_nan, with_inf, with_huge = array.astype(float), array.astype(float), array.astype(float)
        with_nan.flat[0], with_inf.flat[-1], with_huge.flat[-1] = np.nan, np.inf, HUGE
        everywhere = np.full(array.shape, HUGE)  # a sum or a norm of it overflows even if one element does not
        return bad + [("NaN inside", with_nan), ("inf inside", with_inf), ("huge inside", with_huge),
                      ("huge everywhere", everywhere)]
    if kind == "count":
        return common + [("zero", 0), ("negative", -1), ("a float", 2.5), ("a bool", True), *HUGE_COUNTS]
    if kind in ("positive", "non_negative"):
        bad = common + [("negative", -1.0), ("NaN", math.nan), ("inf", math.inf), ("a bool", True), ("huge", HUGE)]
        return bad + ([("zero", 0.0)] if kind == "positive" else [])
    if kind == "real":
        return common + [("NaN", math.nan), ("inf", math.inf), ("a bool", True), ("huge", HUGE)]
    if kind == "probability":
        return common + [("below 0", -0.1), ("above 1", 1.5), ("NaN", math.nan), ("a bool", True)]
    if kind == "flag":
        return [("None", None), ("a string", "yes"), ("an int", 1)]
    if kind == "seed":
        return common + [("negative", -1), ("a float", 1.5), ("a bool", True)]
    if kind == "name":
        return [("None", None), ("a number", 3)]
    if kind == "object":
        return common + [("a number", 3)]
    if kind == "record":  # a record the caller may have edited: the object's spoils, then each field spoiled
        return common + [("a number", 3)] + spoil_fields(valid)
    raise ValueError(f"unknown kind {kind!r}")


#: The prefix of a spoiled field's label ("field background: NaN inside"), counted by the test.
FIELD = "field "


def spoil_fields(record: object) -> list[tuple[str, object]]:
    """``record`` with one field at a time set to None, a string, and (numeric fields) NaN or NaN inside.

    Built with ``dataclasses.replace``, as a user edits a record; a spoiled value the record's own
    constructor refuses is left out (it cannot reach the function).
    """
    spoiled = []
    for item in dataclasses.fields(record):
        value = getattr(record, item.name)
        bad = [("None", None), ("a string", "abc")]
        if isinstance(value, np.ndarray) and np.issubdtype(value.dtype, np.number) and value.size:
            with_nan = value.astype(float)
            with_nan.flat[0] = np.nan
            bad.append(("NaN inside", with_nan))
        elif isinstance(value, (int, float, np.number)) and not isinstance(value, bool):
            bad += [("NaN", math.nan), ("negative", -abs(float(value)) - 1.0)]
        for label, spoilt in bad:
            try:
                spoiled.append((f"{FIELD}{item.name}: {label}", dataclasses.replace(record, **{item.name: spoilt})))
            except (TypeError, ValueError):
                continue  # refused by the record itself
    return spoiled
