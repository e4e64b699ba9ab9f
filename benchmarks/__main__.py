"""``python -m benchmarks [PART ...]``: run benchmark parts and write docs/benchmarks.md."""

from __future__ import annotations

import importlib
import platform
import sys
import time

from .common import DOCS

PARTS = ["wavelets", "ordering", "fit", "validity", "peers", "scaling", "readers", "slicing",
         "large", "figures"]


def main(argv: list[str]) -> None:
    parts = argv or PARTS
    sections = []
    for name in parts:
        try:
            module = importlib.import_module(f"benchmarks.bench_{name}")
        except ModuleNotFoundError as exc:
            if exc.name == f"benchmarks.bench_{name}":
                print(f"benchmark part '{name}' does not exist yet; skipped", file=sys.stderr)
                continue
            raise
        t0 = time.perf_counter()
        print(f"== {name}", file=sys.stderr)
        text = module.run()
        print(text)
        sections.append(text + f"\n\n_(part ran in {time.perf_counter() - t0:.1f} s)_\n")
    head = (f"# wavepoly benchmarks\n\nMeasured on {platform.machine()} with "
            f"{platform.python_implementation()} {platform.python_version()}, "
            f"{time.strftime('%Y-%m-%d')}. Regenerate with `make bench`.\n\n")
    if not argv:  # only a full run rewrites the published tables
        DOCS.mkdir(exist_ok=True)
        (DOCS / "benchmarks.md").write_text(head + "\n\n".join(sections))
        print(f"wrote {DOCS / 'benchmarks.md'}", file=sys.stderr)


if __name__ == "__main__":
    main(sys.argv[1:])
