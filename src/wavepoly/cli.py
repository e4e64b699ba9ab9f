"""The ``wavepoly`` command: a thin shell over the public API.

Exit codes: 0 success, 1 bad data (unreadable file, NaN, too few points...), 2 bad usage
(unknown option, a tolerance <= 0...). Errors are one line on stderr; ``--debug`` shows the
traceback.
"""

from __future__ import annotations

import os
import signal
import sys
import warnings
from pathlib import Path
from typing import Annotated

import numpy as np
import typer

import wavepoly
from wavepoly import ParameterError, WavepolyError
from wavepoly.console import BIG_FILE, Progress, Reading

app = typer.Typer(add_completion=False, no_args_is_help=True, pretty_exceptions_enable=False,
                  help="Concise polygons within a guaranteed tolerance from scanned points "
                       "(B-spline wavelets).")
_state = {"debug": False, "stdout_is_output": False}

#: The path that stands for standard input (an input) or standard output (``-o``).
STDIO = "-"

FormatOpt = Annotated[str | None, typer.Option("--format", "-f",
                                               help="Input format, overriding the extension.")]
ForceOpt = Annotated[bool, typer.Option("--force", help="Replace read-only outputs.")]
ColumnsOpt = Annotated[str | None, typer.Option(
    "--columns", help="0-based coordinate columns, e.g. '0,1' or '1,2,3': of text and .npy "
                      "tables, PLY vertex properties, LAS dimensions (x y z first) or PCD "
                      "fields.")]


def _version(value: bool) -> None:
    if value:
        typer.echo(f"wavepoly {wavepoly.__version__}")
        raise typer.Exit()


@app.callback()
def main_options(
    debug: Annotated[bool, typer.Option("--debug", help="Show tracebacks on errors.")] = False,
    version: Annotated[bool, typer.Option("--version", callback=_version, is_eager=True,
                                          help="Print the version and exit.")] = False,
) -> None:
    _state["debug"] = debug


def _columns(text: str | None) -> tuple[int, ...] | None:
    if text is None:
        return None
    try:
        return tuple(int(c) for c in text.replace(" ", "").split(","))
    except ValueError:
        raise ParameterError(f"--columns takes numbers like '0,1', got {text!r}") from None


def _read(path: Path, fmt: str | None, columns: str | None) -> np.ndarray:
    """The points of ``path`` ('-': standard input), the readers' notes said."""
    source: object = path
    if str(path) == STDIO:
        if not fmt:
            raise ParameterError("reading standard input ('-') needs --format (xy, xyz, ply...)")
        source = sys.stdin.buffer
    with warnings.catch_warnings(record=True) as caught, Reading(path):
        warnings.simplefilter("always", wavepoly.ReadNote)
        points = wavepoly.read_points(source, format=fmt, columns=_columns(columns))
    for w in caught:
        if issubclass(w.category, wavepoly.ReadNote):
            _say(f"note: {w.message}")
        else:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    return points


def _say(text: str) -> None:
    """A message: on standard output, or on standard error when that carries the output."""
    typer.echo(text, err=_state["stdout_is_output"])


def _write(output: Path, output_format: str | None, formats: tuple[str, ...], write) -> str:
    """``write(target, fmt)`` to ``output`` or, for '-', to standard output in
    ``output_format``; returns the name to report."""
    if str(output) != STDIO:
        write(output, None)
        return str(output)
    write(sys.stdout.buffer, output_format)
    return "standard output"


def _output_format(output: Path, output_format: str | None, formats: tuple[str, ...]
                   ) -> str | None:
    """The format of '-o -' (required, one of ``formats``); messages move to standard error."""
    if str(output) != STDIO:
        return None
    if not output_format or output_format.lower() not in formats:
        raise ParameterError(f"-o - (standard output) needs --output-format, one of "
                             f"{', '.join(formats)}")
    _state["stdout_is_output"] = True
    return output_format.lower()


def _check_units(units: str) -> None:
    if units.lower() not in wavepoly.UNITS:
        raise ParameterError(f"--units must be one of {', '.join(wavepoly.UNITS)}, "
                             f"not {units!r}")


OutputFormatOpt = Annotated[str | None, typer.Option(
    "--output-format", help="Format of '-o -' (standard output): geojson, svg, csv...")]
CrsOpt = Annotated[str | None, typer.Option(
    "--crs", help="Coordinate reference system of georeferenced points (EPSG:NNNN), written "
                  "to a .gpkg output (the gis extra).")]
UnitsOpt = Annotated[str, typer.Option(
    help="Length unit of the coordinates for DXF and SVG: mm, cm, m, in or unitless.")]


@app.command()
def info(path: Annotated[Path, typer.Argument(help="Point file.")], fmt: FormatOpt = None,
         columns: ColumnsOpt = None) -> None:
    """Point count, dimensions, bounding box and a suggested tolerance."""
    pts = _read(path, fmt, columns)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    planar = pts.shape[1] == 2 or np.ptp(pts[:, 2]) <= FLAT * max(np.ptp(pts, axis=0).max(),
                                                                 1e-300)
    dims = pts[:, :2] if planar else pts
    spacing = wavepoly.median_spacing(dims) if len(pts) > 1 else 0.0
    _say(f"file:       {path}")
    _say(f"format:     {fmt or wavepoly.detect_format(path)}")
    _say(f"points:     {len(pts)}")
    _say(f"dimensions: {pts.shape[1]}")
    axes = "xyz"[: pts.shape[1]]
    for k, a in enumerate(axes):
        _say(f"{a}:          {lo[k]:.6g} .. {hi[k]:.6g}  (extent {hi[k] - lo[k]:.6g})")
    where = "in x, y" if planar else "in 3D: a cloud to slice"
    _say(f"spacing:    {spacing:.4g} (median nearest-neighbour distance {where})")
    _say(f"suggested tolerance: {2 * spacing:.3g} (twice the spacing)")


#: A third coordinate whose extent is below this fraction of the largest is a planar slice.
FLAT = 1e-6


@app.command()
def order(
    path: Annotated[Path, typer.Argument(help="Point file (2D, or planar 3D).")],
    radius: Annotated[float, typer.Option("--radius", "-r", help="Neighbourhood radius.")],
    plot: Annotated[Path | None, typer.Option(help="Write a figure of the ordering.")] = None,
    output: Annotated[Path | None, typer.Option(
        "--output", "-o", help="Write the ordered contours: .csv .geojson .svg")] = None,
    seed: int = 0, fmt: FormatOpt = None, columns: ColumnsOpt = None, force: ForceOpt = False,
) -> None:
    """Order and thin unorganized points into contours (paper §2)."""
    _check_outputs([path], [(plot, FIGURE_FORMATS), (output, ORDERED_FORMATS)], force)
    pts = wavepoly.as_planar(_read(path, fmt, columns), str(path))
    ordering = wavepoly.order_points(pts, radius, seed=seed)
    _say(wavepoly.ordering_summary(ordering, len(pts)))
    for note in ordering.notes:
        _say(f"note: {note}")
    for k, c in enumerate(ordering.contours):
        _say(f"contour {k}: {'closed' if c.closed else 'open'}, {len(c.members)} points "
             f"-> {len(c.points)} ordered")
    if output:
        wavepoly.write_ordering(output, ordering)
        _say(f"wrote {output}")
    if plot:
        from wavepoly.plot import plot_ordering, save_figure

        save_figure(plot_ordering(pts, ordering), plot)
        _say(f"wrote {plot}")


@app.command(name="fit")
def fit_command(
    path: Annotated[Path, typer.Argument(help="Point file (2D, or planar 3D).")],
    tolerance: Annotated[float, typer.Option("--tolerance", "-t",
                                             help="Shape tolerance (the points' units).")],
    output: Annotated[Path, typer.Option("--output", "-o",
                                         help="Polygons: .geojson .svg .dxf .csv")],
    relative_tolerance: Annotated[str, typer.Option(
        help="Relative shape error threshold (eq. 7), or 'auto'.")] = "0.05",
    radius: Annotated[float | None, typer.Option(help="Ordering radius (default: tolerance).")
                      ] = None,
    plot: Annotated[Path | None, typer.Option(help="Write a figure of the fit (PNG).")] = None,
    report: Annotated[Path | None, typer.Option(help="Write a JSON report.")] = None,
    seed: int = 0, fmt: FormatOpt = None, columns: ColumnsOpt = None, force: ForceOpt = False,
    output_format: OutputFormatOpt = None, units: UnitsOpt = "unitless", crs: CrsOpt = None,
) -> None:
    """Fit concise polygons within the tolerance (ordering, wavelets, reconstruction).

    '-' reads standard input (with --format) and '-o -' writes standard output (with
    --output-format); messages then go to standard error."""
    out_fmt = _output_format(output, output_format, wavepoly.POLYGON_FORMATS)
    _check_units(units)
    _check_outputs([path], [(output, wavepoly.POLYGON_FORMATS), (plot, FIGURE_FORMATS),
                            (report, REPORT_FORMATS)], force)
    rel = _relative_tolerance(relative_tolerance)
    pts = wavepoly.validate_points(wavepoly.as_planar(_read(path, fmt, columns), str(path)),
                                   source=str(path), min_points=3)
    with Progress("fitting contours") as progress:
        result = wavepoly.fit(pts, tolerance, relative_tolerance=rel, radius=radius, seed=seed,
                              progress=progress)
    doc = wavepoly.fit_report(result, str(path)) if report else None
    figure = None
    if plot:  # everything is made before the first file is written
        from wavepoly.plot import plot_fit, save_figure

        figure = plot_fit(pts, result)
    written = _write(output, out_fmt, wavepoly.POLYGON_FORMATS, lambda target, f:
                     wavepoly.write_polygons(target, result, f, units=units, crs=crs))
    for line in wavepoly.fit_summary(result):
        _say(line)
    _say(f"wrote {written}")
    if report:
        wavepoly.write_report(report, doc)
        _say(f"wrote {report}")
    if plot:
        save_figure(figure, plot)
        _say(f"wrote {plot}")


def _check_outputs(inputs: list[Path], outputs: list[tuple[Path | None, tuple[str, ...]]],
                   force: bool = False) -> None:
    """Before any work: every output has a known extension, a folder that exists, is not an
    input (nor another output), and is not a read-only file (unless ``force``); nothing is
    written otherwise."""
    sources = {p.resolve() for p in inputs if p.exists()}
    seen: set[Path] = set()
    for out, formats in outputs:
        if out is None or str(out) == STDIO:
            continue
        if out.suffix.lstrip(".").lower() not in formats:
            raise ParameterError(f"{out}: output must end in one of "
                                 f"{', '.join('.' + f for f in formats)}")
        folder = out.parent if str(out.parent) else Path(".")
        if not folder.is_dir():
            raise ParameterError(f"{out}: folder {folder} does not exist")
        target = out.resolve()
        if target in sources:
            raise ParameterError(f"{out}: is the input file; refusing to overwrite it")
        if target in seen:
            raise ParameterError(f"{out}: given as two outputs")
        if out.is_dir():
            raise ParameterError(f"{out}: is a folder")
        read_only = out.exists() and (not out.stat().st_mode & 0o222  # no write bit, even
                                      or not os.access(out, os.W_OK))  # for root
        if read_only and not force:
            raise ParameterError(f"{out}: exists and is read-only (--force replaces it)")
        seen.add(target)


FIGURE_FORMATS = ("png", "svg", "pdf")
ORDERED_FORMATS = ("csv", "geojson", "json", "svg")
REPORT_FORMATS = ("json",)


def _relative_tolerance(text: str) -> float | None:
    """``--relative-tolerance``: a number, or 'auto' (None: the fit chooses the level)."""
    if text.strip().lower() == "auto":
        return None
    try:
        return float(text)
    except ValueError:
        raise ParameterError(f"--relative-tolerance must be a number or 'auto', "
                             f"got {text!r}") from None


@app.command(name="slice")
def slice_command(
    paths: Annotated[list[Path], typer.Argument(
        help="3D cloud (.ply .pts .xyz .las .laz .conf ...); several files, a folder or a "
             "quoted pattern ('tiles/*.laz') are sliced as one cloud.")],
    tolerance: Annotated[float, typer.Option("--tolerance", "-t",
                                             help="Shape tolerance (the cloud's units).")],
    output: Annotated[Path, typer.Option("--output", "-o",
                                         help="Layer model: .cli .svg .geojson .stl")],
    layer: Annotated[float | None, typer.Option("--layer", help="Uniform layer thickness.")
                     ] = None,
    adaptive: Annotated[bool, typer.Option(help="Adaptive layer thickness.")] = False,
    min_layer: Annotated[float | None, typer.Option(help="Thinnest adaptive layer.")] = None,
    max_layer: Annotated[float | None, typer.Option(help="Thickest adaptive layer.")] = None,
    band: Annotated[float | None, typer.Option(help="Use only slab points within band/2 of "
                                                    "each layer's mid-plane.")] = None,
    from_mesh: Annotated[bool, typer.Option(
        "--from-mesh", help="Slice a PLY/OBJ/OFF's faces: exact sections, simplified.")] = False,
    separate_bodies: Annotated[bool, typer.Option(
        "--separate-bodies", help="STL: one closed body per layer, not their union.")] = False,
    axis: Annotated[str, typer.Option(help="Slicing axis: x, y, z or 'ax,ay,az'.")] = "z",
    workers: Annotated[int | None, typer.Option(
        help="Processes (default: all cores); with the dask extra, a local Dask cluster of "
             "that many workers.")] = None,
    scheduler: Annotated[str | None, typer.Option(
        help="Fit the layers on the Dask cluster of this scheduler (tcp://host:8786; also "
             "from DASK_SCHEDULER_ADDRESS).")] = None,
    units: Annotated[str, typer.Option(
        help="Length unit of the coordinates: mm, cm, m, in, unitless (.cli $$UNITS, SVG "
             "size), or millimetres per unit as a number.")] = "unitless",
    output_format: OutputFormatOpt = None, crs: CrsOpt = None,
    plot: Annotated[Path | None, typer.Option(help="Write figures (PNG): the 3D layer model, "
                                                   "and a contact sheet next to it.")] = None,
    report: Annotated[Path | None, typer.Option(help="Write a JSON report.")] = None,
    fmt: FormatOpt = None, columns: ColumnsOpt = None, force: ForceOpt = False,
) -> None:
    """Slice a 3D cloud (or, with --from-mesh, its faces) into layers whose contours are its
    cross-sections within the tolerance; write the layer model ('-o -': to standard output,
    with --output-format cli, svg or geojson)."""
    out_fmt = _output_format(output, output_format, ("cli", "svg", "geojson"))
    layer_units = _layer_units(units)
    sources = wavepoly.expand_sources(paths)
    _check_outputs(sources, [(output, wavepoly.LAYER_FORMATS), (plot, FIGURE_FORMATS),
                             (report, REPORT_FORMATS)], force)
    if (layer is None) == (not adaptive):
        raise ParameterError("give either --layer THICKNESS or --adaptive")
    direction = axis if axis.lower() in ("x", "y", "z") else _vector(axis)
    scheduler = scheduler or wavepoly.scheduler_from_environment()
    if from_mesh or adaptive:
        if scheduler:
            raise ParameterError("--scheduler fits uniform layers (--layer) of a cloud; "
                                 "adaptive layers and --from-mesh run here")
        if from_mesh and len(sources) > 1:
            raise ParameterError(f"--from-mesh slices one mesh file, got {len(sources)}")
    if from_mesh:
        if adaptive:
            raise ParameterError("--from-mesh slices uniform layers (--layer); adaptive "
                                 "layers need the cloud")
        result = wavepoly.slice_mesh(wavepoly.read_mesh(sources[0]), tolerance,
                                     axis=direction, layer_thickness=layer)
    elif adaptive:
        pts = (_read(sources[0], fmt, columns) if len(sources) == 1 else
               wavepoly.read_cloud(sources, fmt=fmt, columns=_columns(columns)))
        pts = wavepoly.validate_points(pts, source=str(sources[0]) if len(sources) == 1 else
                                       f"{len(sources)} files", min_points=3)
        with Progress("fitting layers") as progress:
            result = wavepoly.slice_cloud(pts, tolerance, axis=direction, adaptive=True,
                                          min_layer=min_layer, max_layer=max_layer, band=band,
                                          progress=progress)
    else:
        if not scheduler and workers is not None and wavepoly.dask_available():
            scheduler = "local"
        size = sum(p.stat().st_size for p in sources if p.is_file())
        if size >= BIG_FILE:
            where = f"on {scheduler}" if scheduler else "here"
            typer.echo(f"reading and planning {len(sources)} file(s) ({size / 2**20:.0f} MB) "
                       f"{where}", err=True)
        with Progress("fitting layers") as progress:
            result = wavepoly.slice_tiles(sources, tolerance, axis=direction,
                                          layer_thickness=layer, band=band,
                                          scheduler=scheduler, workers=workers, fmt=fmt,
                                          columns=_columns(columns), progress=progress)
    source = str(sources[0]) if len(sources) == 1 else [str(p) for p in sources]
    doc = wavepoly.slice_report(result, source) if report else None
    figures = None
    if plot:  # everything is made before the first file is written
        from wavepoly.plot import plot_contact_sheet, plot_layer_model, save_figure

        figures = (plot_layer_model(result), plot_contact_sheet(result))
    written = _write(output, out_fmt, wavepoly.LAYER_FORMATS, lambda target, f:
                     wavepoly.write_layers(target, result, f, units=layer_units,
                                           separate=separate_bodies, crs=crs))
    _say(wavepoly.slice_summary(result))
    for note in result.notes:
        _say(f"note: {note}")
    _say(f"wrote {written}")
    if report:
        wavepoly.write_report(report, doc)
        _say(f"wrote {report}")
    if plot:
        save_figure(figures[0], plot)
        sheet = plot.with_name(plot.stem + "-layers" + plot.suffix)
        save_figure(figures[1], sheet)
        _say(f"wrote {plot} and {sheet}")


def _layer_units(text: str) -> str | float:
    """--units of slice: a unit's name, or millimetres per unit."""
    if text.lower() in wavepoly.UNITS:
        return text.lower()
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not value > 0 or value == float("inf"):
        raise ParameterError(f"--units must be one of {', '.join(wavepoly.UNITS)} or a number "
                             f"of millimetres per unit, not {text!r}")
    return value


def _vector(text: str) -> tuple[float, float, float]:
    try:
        values = tuple(float(v) for v in text.split(","))
    except ValueError:
        values = ()
    if len(values) != 3:
        raise ParameterError(f"--axis takes x, y, z or three numbers 'ax,ay,az', got {text!r}")
    return values  # type: ignore[return-value]


@app.command()
def demo(out: Annotated[Path, typer.Option("--out", help="Output folder.")] = Path(
        "wavepoly-demo")) -> None:
    """Fit built-in glyph outlines (noisy scan-like samples) and write polygons and figures."""
    from wavepoly.demo import run_demo

    run_demo(out, echo=typer.echo)


class _Terminated(BaseException):
    """SIGTERM, raised in the main thread so that work stops and outputs stay unwritten."""


class _Interrupted(BaseException):
    """Ctrl-C. Not KeyboardInterrupt: typer returns normally from one (exit 0, as if done)."""


def _on_sigterm(signum, frame) -> None:
    raise _Terminated()


def _on_sigint(signum, frame) -> None:
    raise _Interrupted()


#: Exit codes of a run stopped by a signal: 128 + the signal's number, as shells report them.
EXIT_INTERRUPTED = 128 + signal.SIGINT
EXIT_TERMINATED = 128 + signal.SIGTERM


def main() -> None:
    """Entry point: run the app, turning wavepoly errors into one line and an exit code.

    Ctrl-C exits 130 and SIGTERM 143, each with a one-line message; worker processes are
    stopped and no output (nor temporary file) is left behind.
    """
    signal.signal(signal.SIGTERM, _on_sigterm)
    signal.signal(signal.SIGINT, _on_sigint)  # also when the caller started us ignoring it
    try:
        app(standalone_mode=False)
    except _Terminated:
        typer.echo("terminated (SIGTERM): work stopped, workers ended", err=True)
        sys.exit(EXIT_TERMINATED)
    except (_Interrupted, KeyboardInterrupt):
        typer.echo("interrupted (Ctrl-C): work stopped, workers ended", err=True)
        sys.exit(EXIT_INTERRUPTED)
    except WavepolyError as exc:
        if _state["debug"]:
            raise
        typer.echo(f"error: {exc}", err=True)
        sys.exit(2 if isinstance(exc, ParameterError) else 1)
    except typer.Exit as exc:
        sys.exit(exc.exit_code)
    except typer.Abort as exc:
        if isinstance(exc.__cause__, KeyboardInterrupt):
            typer.echo("interrupted (Ctrl-C): work stopped, workers ended", err=True)
            sys.exit(EXIT_INTERRUPTED)
        typer.echo("aborted", err=True)
        sys.exit(1)
    except Exception as exc:  # usage errors of the (vendored) click, and anything unexpected
        if hasattr(exc, "show") and isinstance(getattr(exc, "exit_code", None), int):
            exc.show()
            sys.exit(exc.exit_code)
        if _state["debug"]:
            raise
        typer.echo(f"error: {type(exc).__name__}: {exc} (run with --debug for details)", err=True)
        sys.exit(1)


__all__ = ["app", "main"]
