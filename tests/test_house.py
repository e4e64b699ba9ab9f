"""The house's rules, checked on the source: which rooms may import which."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src" / "wavepoly"
STAGES = ["ordering", "wavelets", "levels", "reconstruction", "simplify"]
GROUND = ["types", "errors"]
UPPER = {"io", "cli", "plot", "demo"}


def _modules(room: str) -> list[Path]:
    path = SRC / room
    return sorted(path.rglob("*.py")) if path.is_dir() else [path.with_suffix(".py")]


def _imported_rooms(path: Path) -> set[str]:
    """First-level wavepoly rooms that ``path`` imports (relative or absolute)."""
    package = path.relative_to(SRC).parts[:-1]
    rooms = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = list(package[: len(package) - node.level + 1])
                parts = base + (node.module.split(".") if node.module else [])
                names = [parts[0]] if parts else [a.name for a in node.names]
            elif node.module and node.module.split(".")[0] == "wavepoly":
                names = node.module.split(".")[1:2] or [a.name for a in node.names]
            else:
                continue
            rooms.update(names)
        elif isinstance(node, ast.Import):
            rooms.update(a.name.split(".")[1] for a in node.names
                         if a.name.startswith("wavepoly."))
    return rooms


@pytest.mark.parametrize("stage", STAGES)
def test_stages_never_import_io_cli_plot_or_demo(stage):
    for path in _modules(stage):
        assert not (_imported_rooms(path) & UPPER), path


@pytest.mark.parametrize("room", GROUND)
def test_the_ground_floor_imports_no_other_room(room):
    for path in _modules(room):
        assert not (_imported_rooms(path) - {room}), path


def test_no_module_is_over_500_lines():
    for path in SRC.rglob("*.py"):
        assert len(path.read_text().splitlines()) <= 500, path


def test_cli_and_demo_use_public_names_only():
    for name in ("cli.py", "demo.py"):
        tree = ast.parse((SRC / name).read_text())
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom):
                assert node.level == 0, f"{name}: relative import of {node.module}"
                assert not any(a.name.startswith("_") for a in node.names), name
            if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name):
                if node.value.id == "wavepoly":
                    assert not node.attr.startswith("_") or node.attr == "__version__", name


def test_the_shared_data_can_be_pointed_at(tmp_path):
    """WAVEPOLY_SHARED_DATA moves the tests' (and benchmarks') shared scans."""
    import os
    import subprocess
    import sys

    root = Path(__file__).resolve().parents[1]
    code = "import tests.conftest as c, benchmarks.common as b; print(c.SHARED); print(b.SHARED)"
    out = subprocess.run([sys.executable, "-c", code], cwd=root, capture_output=True, text=True,
                         env={**os.environ, "WAVEPOLY_SHARED_DATA": str(tmp_path)}, check=True)
    assert out.stdout.split() == [str(tmp_path)] * 2
