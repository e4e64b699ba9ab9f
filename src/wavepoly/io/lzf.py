"""LZF decompression (Marc Lehmann's liblzf format), for PCD files saved ``binary_compressed``.

The Point Cloud Library compresses PCD data with liblzf; the format is a stream of literal
runs and back references, decoded here by a compiled loop (numba) instead of a C extension
that would need a compiler on the user's machine.

References
----------
.. [1] M. Lehmann, liblzf 3.6, ``lzf_d.c`` (the reference decoder).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..errors import DataError


def decompress(data: bytes, size: int, source: str = "data") -> bytes:
    """The ``size`` bytes that ``data`` (LZF) decompresses to; `DataError` if it is corrupt."""
    out = np.empty(size, dtype=np.uint8)
    written = _decode(np.frombuffer(data, dtype=np.uint8), out)
    if written < 0:
        raise DataError(f"{source}: the compressed data is corrupt (LZF)")
    if written != size:
        raise DataError(f"{source}: the compressed data holds {written} bytes, "
                        f"the header says {size}")
    return out.tobytes()


@njit(cache=True, nogil=True)
def _decode(src: np.ndarray, out: np.ndarray) -> int:  # pragma: no cover - compiled
    """Decode ``src`` into ``out``; the bytes written, or -1 on a corrupt stream."""
    ip, op, n_in, n_out = 0, 0, len(src), len(out)
    while ip < n_in:
        ctrl = int(src[ip])
        ip += 1
        if ctrl < 32:  # a literal run of ctrl + 1 bytes
            run = ctrl + 1
            if ip + run > n_in or op + run > n_out:
                return -1
            out[op:op + run] = src[ip:ip + run]
            ip += run
            op += run
        else:  # a back reference: length and distance
            length = ctrl >> 5
            ref = op - ((ctrl & 0x1F) << 8) - 1
            if length == 7:
                if ip >= n_in:
                    return -1
                length += int(src[ip])
                ip += 1
            if ip >= n_in:
                return -1
            ref -= int(src[ip])
            ip += 1
            length += 2
            if ref < 0 or op + length > n_out:
                return -1
            for _ in range(length):  # byte by byte: the copy may overlap itself
                out[op] = out[ref]
                op += 1
                ref += 1
    return op
