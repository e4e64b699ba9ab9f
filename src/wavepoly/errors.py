"""Errors that wavepoly raises for bad input: one clear line, never a traceback at the CLI."""

from __future__ import annotations


class WavepolyError(Exception):
    """Base class: the message is a complete, user-facing sentence."""


class DataError(WavepolyError, ValueError):
    """The input points or file are unusable (empty, NaN, unreadable, wrong columns, ...)."""


class ParameterError(WavepolyError, ValueError):
    """A parameter is out of its domain (a tolerance <= 0, a wrong level count, ...)."""


class EngineError(WavepolyError):
    """Where the work should run is not available (a Dask scheduler out of reach, an extra
    not installed)."""


class ReadNote(UserWarning):
    """A remark of a reader about the file it read (points it dropped, and why): a warning,
    which the command line prints as a note."""
