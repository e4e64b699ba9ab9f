"""Errors that wavepoly raises for bad input: one clear line, never a traceback at the CLI."""

from __future__ import annotations


class WavepolyError(Exception):
    """Base class: the message is a complete, user-facing sentence."""


class DataError(WavepolyError, ValueError):
    """The input points or file are unusable (empty, NaN, unreadable, wrong columns, ...)."""


class ParameterError(WavepolyError, ValueError):
    """A parameter is out of its domain (a tolerance <= 0, a wrong level count, ...)."""


def check_tolerance(tolerance: float, name: str = "tolerance") -> float:
    """Return ``tolerance`` as a float, or raise `ParameterError` unless it is finite and > 0."""
    try:
        value = float(tolerance)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be a number, got {tolerance!r}") from None
    if not value > 0 or value == float("inf"):
        raise ParameterError(f"{name} must be a finite number > 0, got {tolerance!r}")
    return value
