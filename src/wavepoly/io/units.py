"""Length units of the written files: what DXF, SVG and CLI call them.

A scan's coordinates carry no unit, so none is claimed unless the user names one: an unlabelled
drawing is read at the reader's default, a wrong label is scaled by 1000 without a word.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..errors import ParameterError


@dataclass(frozen=True)
class Unit:
    """millimetres: one unit in mm (the CLI header); dxf: the $INSUNITS code; svg: the CSS
    unit of width and height ('' when none), and how many of them make one unit."""

    millimetres: float
    dxf: int
    svg: str
    svg_scale: float = 1.0


#: The units a user can name (``--units``); "unitless" claims none.
UNITS = {"unitless": Unit(1.0, 0, ""), "mm": Unit(1.0, 4, "mm"), "cm": Unit(10.0, 5, "cm"),
         "m": Unit(1000.0, 6, "cm", 100.0), "in": Unit(25.4, 1, "in")}


def unit_of(name: str) -> Unit:
    """The `Unit` called ``name``, or a `ParameterError` listing the known ones."""
    unit = UNITS.get(str(name).lower())
    if unit is None:
        raise ParameterError(f"units must be one of {', '.join(UNITS)}, not {name!r}")
    return unit
