"""Answers as JSON: how a check cell's grading record carries a value out of the student's kernel.

:meth:`amdo_lab.common.exercises.ExerciseSet.record` encodes the answer (or an "implement it"
function's outputs) with :func:`encode_value`; the grader decodes it with :func:`decode_value`
and judges it in its own process. Arrays, tuples, sets and dicts keep their kind; an object that
cannot be carried comes back as an opaque stand-in that matches nothing.
"""

from __future__ import annotations

import numbers
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

__all__ = ["decode_value", "encode_value"]


def encode_value(value: object) -> object:
    """``value`` as JSON-ready data that :func:`decode_value` turns back (arrays, tuples, sets kept apart)."""
    if value is None or isinstance(value, (bool, str)):
        return value
    if isinstance(value, np.generic):
        return encode_value(value.item())
    if isinstance(value, numbers.Integral):
        return int(value)
    if isinstance(value, numbers.Real):
        value = float(value)
        return value if np.isfinite(value) else {"__float__": repr(value)}
    if isinstance(value, numbers.Complex):
        return {"__complex__": [value.real, value.imag]}
    if isinstance(value, np.ndarray):
        if value.dtype.kind in "biuf":
            return {"__array__": encode_value(value.astype(float).tolist() if value.dtype.kind == "f"
                                              else value.tolist())}
        return {"__repr__": repr(value)}
    if isinstance(value, tuple):
        return {"__tuple__": [encode_value(v) for v in value]}
    if isinstance(value, list):
        return [encode_value(v) for v in value]
    if isinstance(value, (set, frozenset)):
        return {"__set__": sorted((encode_value(v) for v in value), key=repr)}
    if isinstance(value, Mapping):
        return {"__dict__": [[encode_value(k), encode_value(v)] for k, v in value.items()]}
    return {"__repr__": repr(value)[:200]}


def decode_value(data: object) -> object:
    """The value :func:`encode_value` encoded (an unencodable one comes back as its repr in a ``_Opaque``)."""
    if isinstance(data, list):
        return [decode_value(v) for v in data]
    if not isinstance(data, dict):
        return data
    if "__float__" in data:
        return float(data["__float__"])
    if "__complex__" in data:
        return complex(*data["__complex__"])
    if "__array__" in data:
        return np.asarray(decode_value(data["__array__"]), dtype=float)
    if "__tuple__" in data:
        return tuple(decode_value(v) for v in data["__tuple__"])
    if "__set__" in data:
        return {decode_value(v) for v in data["__set__"]}
    if "__dict__" in data:
        return {decode_value(k): decode_value(v) for k, v in data["__dict__"]}
    return _Opaque(str(data.get("__repr__", data)))


@dataclass(frozen=True)
class _Opaque:
    """An answer the record could not carry (an arbitrary object): it matches nothing."""

    text: str
