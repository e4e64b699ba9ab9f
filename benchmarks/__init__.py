"""Benchmarks: speed and vertex counts, measured here and written to docs/benchmarks.md.

``make bench`` runs all of them; ``python -m benchmarks NAME`` runs one part.
"""
