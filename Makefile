# One command each, on a fresh clone: `make demo`, `make test`, `make bench`.
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed-stamp

OTR2 := benchmarks/peers/build/otr2
CGAL_HEADER := /usr/include/CGAL/Optimal_transportation_reconstruction_2.h

.PHONY: demo test bench lint clean otr2

$(STAMP): pyproject.toml
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e ".[test,dask,gis]"
	touch $(STAMP)

demo: $(STAMP)
	$(VENV)/bin/wavepoly demo --out wavepoly-demo

test: $(STAMP)
	$(PY) -m ruff check src tests benchmarks
	$(PY) -m pytest -n 2 --dist worksteal -q

bench: $(STAMP) otr2
	$(PY) -m pip install --quiet -e ".[test,dask,gis,bench]"
	$(PY) -m benchmarks

# CGAL's OTR2 peer (header-only; Debian's libcgal-dev). Installed when missing and possible;
# otherwise the benchmark reports OTR2 as not built and goes on.
otr2:
	@test -f $(CGAL_HEADER) || { echo "bench: installing libcgal-dev for the OTR2 peer"; \
	  (apt-get install -y -q libcgal-dev || (apt-get update -q && apt-get install -y -q \
	  libcgal-dev)) >/dev/null 2>&1 || echo "bench: cannot install libcgal-dev; OTR2 skipped"; }
	@if test -f $(CGAL_HEADER); then mkdir -p $(dir $(OTR2)) && \
	  $(MAKE) --no-print-directory $(OTR2); fi

$(OTR2): benchmarks/peers/otr2.cpp
	$(CXX) -O2 -DNDEBUG -std=c++17 $< -o $@ -lgmp -lmpfr || \
	  echo "bench: OTR2 driver did not compile; OTR2 skipped"

lint: $(STAMP)
	$(PY) -m ruff check src tests benchmarks

clean:
	rm -rf $(VENV) wavepoly-demo benchmarks/peers/build .pytest_cache .ruff_cache .hypothesis
