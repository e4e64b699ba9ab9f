"""Semi-orthogonal cubic B-spline wavelets (paper §3, eq. 1-5 and 11).

Two flavours behind one interface:

* open curves: endpoint-interpolating cubic B-splines on [0, 1], ``2**j + 3`` coefficients at
  level j (the paper's choice; Stollnitz, DeRose & Salesin 1996, Finkelstein & Salesin 1994);
* closed curves: uniform periodic cubic B-splines, ``2**j`` coefficients at level j, so a closed
  contour has no seam at its start point.

Conventions (those of the paper and of Stollnitz et al.): ``c[j-1] = A[j] c[j]``,
``d[j-1] = B[j] c[j]`` and ``c[j] = P[j] c[j-1] + Q[j] d[j-1]`` (eq. 11), with
``[A; B] = [P | Q]^-1`` (eq. 5). P is knot insertion at every interval midpoint; the columns of Q
span the orthogonal complement of V[j-1] in V[j] with minimal support, found here as null vectors
of ``P^T I`` (I the Gram matrix) and scaled so that every wavelet has norm sqrt(h), h = 2**-j,
which keeps cond([P | Q]) near 11 at every level.

A and B are dense and are never formed. Open levels solve ``[P | Q] x = c`` with a banded LU,
factorized once (at a reference level) and cached, so each level costs O(n); periodic levels are
block-circulant and solve by FFT, O(n log n) with nothing to factor.

Examples
--------
>>> import numpy as np
>>> c = np.random.default_rng(0).normal(size=(2**8 + 3, 2))
>>> coarse, details = decompose(c, 5)
>>> coarse.shape, [d.shape[0] for d in details]
((11, 2), [8, 16, 32, 64, 128])
>>> bool(np.allclose(reconstruct(coarse, details), c))
True
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import scipy.sparse as sp
from scipy.interpolate import BSpline
from scipy.linalg import lapack

from .errors import ParameterError
from .types import FloatArray

#: Coarsest level each flavour can reach: one cubic Bezier piece (4 coefficients) for open
#: curves, 4 periodic coefficients for closed ones.
MIN_LEVEL = {False: 0, True: 2}

_P_INTERIOR = np.array([2.0, 8.0, 12.0, 8.0, 2.0]) / 16.0
_P_PERIODIC = np.array([1.0, 4.0, 6.0, 4.0, 1.0]) / 8.0
_GRAM_INTERIOR = np.array([1.0, 120.0, 1191.0, 2416.0, 1191.0, 120.0, 1.0]) / 5040.0
#: Boundary columns of P for level j >= 3 (x 1/16): (first row, entries); the last three mirror.
_P_BOUNDARY = ((0, (16.0, 8.0)), (1, (8.0, 12.0, 3.0)), (2, (4.0, 11.0, 8.0, 2.0)))


def n_coefficients(level: int, closed: bool = False) -> int:
    """Number of scaling coefficients at ``level``: ``2**level + 3`` open, ``2**level`` closed."""
    return 2**level if closed else 2**level + 3


def level_of(m: int, closed: bool = False) -> int:
    """The level j with ``n_coefficients(j, closed) == m``; `ParameterError` if there is none."""
    base = m if closed else m - 3
    if base < 1 or base & (base - 1):
        shape = "2**j" if closed else "2**j + 3"
        raise ParameterError(f"{m} coefficients is not {shape} for any level j "
                             f"({'closed' if closed else 'open'} curve)")
    return base.bit_length() - 1


def greville(level: int, closed: bool = False) -> FloatArray:
    """Parameter in [0, 1] (open) or [0, 1) (closed) at which each coefficient of ``level`` sits.

    These are the Greville abscissae of the B-spline basis, so ``P[j] @ greville(j-1)`` equals
    ``greville(j)`` (linear precision). Coefficient i of a closed level j sits at i / 2**j.
    """
    if closed:
        return np.arange(2**level) / 2**level
    knots = _open_knots(level)
    return (knots[1:-3] + knots[2:-2] + knots[3:-1]) / 3.0


def _open_knots(level: int) -> FloatArray:
    inner = np.arange(2**level + 1) / 2**level
    return np.concatenate([[0.0] * 3, inner, [1.0] * 3])


# ---------------------------------------------------------------------------------------------
# Synthesis filters P (eq. 3) and the Gram matrix


@lru_cache(maxsize=64)
def synthesis_p(level: int, closed: bool = False) -> sp.csr_matrix:
    """P[j]: (n(j) x n(j-1)) knot-insertion matrix, c[j] = P[j] c[j-1] (eq. 3)."""
    _check_level(level, closed)
    if closed:
        return _periodic_p(level)
    if level <= 2:
        return sp.csr_matrix(_open_p_by_evaluation(level))
    return _open_p(level)


def _open_p(level: int) -> sp.csr_matrix:
    m_fine, m_coarse = n_coefficients(level), n_coefficients(level - 1)
    rows, cols, vals = [], [], []
    for col, (first, entries) in enumerate(_P_BOUNDARY):
        r = first + np.arange(len(entries))
        v = np.asarray(entries) / 16.0
        rows += [r, m_fine - 1 - r]
        cols += [np.full(len(r), col), np.full(len(r), m_coarse - 1 - col)]
        vals += [v, v]
    interior = np.repeat(np.arange(3, m_coarse - 3), 5)
    rows.append(2 * interior - 3 + np.tile(np.arange(5), len(interior) // 5))
    cols.append(interior)
    vals.append(np.tile(_P_INTERIOR, len(interior) // 5))
    return _coo(rows, cols, vals, (m_fine, m_coarse))


def _coo(rows: list, cols: list, vals: list, shape: tuple[int, int]) -> sp.csr_matrix:
    """A CSR matrix from lists of index/value arrays (duplicate entries add up)."""
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                         shape=shape)


def _open_p_by_evaluation(level: int) -> FloatArray:
    """P for small levels, where the boundary columns overlap: solve B_fine P = B_coarse."""
    m_fine = n_coefficients(level)
    x = np.linspace(0.0, 1.0, 2 * m_fine + 1)
    fine = BSpline.design_matrix(x, _open_knots(level), 3).toarray()
    coarse = BSpline.design_matrix(x, _open_knots(level - 1), 3).toarray()
    p = np.linalg.lstsq(fine, coarse, rcond=None)[0]
    return np.round(p * 64.0) / 64.0  # entries are multiples of 1/16: remove rounding noise


def _periodic_p(level: int) -> sp.csr_matrix:
    m_fine, m_coarse = 2**level, 2 ** (level - 1)
    cols = np.repeat(np.arange(m_coarse), 5)
    rows = (2 * cols + np.tile(np.arange(-2, 3), m_coarse)) % m_fine
    vals = np.tile(_P_PERIODIC, m_coarse)
    return sp.csr_matrix((vals, (rows, cols)), shape=(m_fine, m_coarse))  # duplicates add up


@lru_cache(maxsize=64)
def gram(level: int, closed: bool = False) -> sp.csr_matrix:
    """Gram matrix of the level-j scaling functions divided by h = 2**-j (so I[j] = h * gram)."""
    if closed:
        m = 2**level
        offsets = np.arange(-3, 4)
        rows = np.repeat(np.arange(m), 7)
        cols = (rows + np.tile(offsets, m)) % m
        return sp.csr_matrix((np.tile(_GRAM_INTERIOR, m), (rows, cols)), shape=(m, m))
    if level <= 4:
        return sp.csr_matrix(_open_gram_by_quadrature(level))
    base = _open_gram_by_quadrature(4)  # 19 x 19: all boundary patterns, exact
    m, nb = n_coefficients(level), base.shape[0]
    rows = np.repeat(np.arange(m), 7)
    cols = rows + np.tile(np.arange(-3, 4), m)
    keep = (cols >= 0) & (cols < m)
    rows, cols = rows[keep], cols[keep]
    vals = _GRAM_INTERIOR[cols - rows + 3]
    head = np.minimum(rows, cols) < nb // 2
    vals[head] = base[rows[head], cols[head]]
    tail = np.maximum(rows, cols) >= m - nb // 2
    vals[tail] = base[rows[tail] - (m - nb), cols[tail] - (m - nb)]
    return sp.csr_matrix((vals, (rows, cols)), shape=(m, m))


def _open_gram_by_quadrature(level: int) -> FloatArray:
    """Exact Gram matrix (in units of h) by 4-point Gauss-Legendre on each knot interval.

    The knots are integers here (h = 1), so no precision is lost to absolute positions.
    """
    n_int = 2**level
    knots = np.concatenate([[0.0] * 3, np.arange(n_int + 1, dtype=float), [float(n_int)] * 3])
    g, w = np.polynomial.legendre.leggauss(4)
    x = (np.arange(n_int)[:, None] + (g[None, :] + 1.0) / 2.0).ravel()
    weights = np.tile(w / 2.0, n_int)
    basis = BSpline.design_matrix(x, knots, 3).toarray()
    return basis.T @ (basis * weights[:, None])


# ---------------------------------------------------------------------------------------------
# Wavelet filters Q (eq. 4)


def _support_open(level: int) -> list[tuple[int, int]]:
    """(first row, last row) of each minimal-support wavelet column of an open level."""
    n_w, m = 2 ** (level - 1), n_coefficients(level)
    head = {1: [(0, 4)], 2: [(0, 5)], 3: [(0, 7), (1, 8)]}.get(level, [(0, 7), (1, 9), (2, 11)])
    interior = [(2 * k - 3, 2 * k + 7) for k in range(len(head), n_w - len(head))]
    tail = [(m - 1 - b, m - 1 - a) for a, b in reversed(head)]
    return (head + interior + tail)[:n_w] if level > 1 else head


def _null_vector(constraints: sp.csr_matrix, rows: np.ndarray) -> FloatArray:
    """The unique (up to scale) vector on ``rows`` that ``constraints`` maps to zero."""
    sub = constraints[:, rows].toarray()
    sub = sub[np.abs(sub).max(axis=1) > 0]
    _, s, vt = np.linalg.svd(sub)
    if len(s) >= len(rows) and s[-1] > 1e-9 * s[0]:
        raise ArithmeticError("wavelet support admits no null vector")  # pragma: no cover
    return vt[-1]


def _normalized(q: FloatArray, g: FloatArray) -> FloatArray:
    q = q / np.sqrt(q @ g @ q)  # ||psi||^2 = h q^T G q = h
    return q if q[np.argmax(np.abs(q))] > 0 else -q


@lru_cache(maxsize=64)
def synthesis_q(level: int, closed: bool = False) -> sp.csr_matrix:
    """Q[j]: (n(j) x 2**(j-1)) wavelet filter, psi[j-1] = phi[j] Q[j] (eq. 4)."""
    _check_level(level, closed)
    if closed:
        return _periodic_q(level)
    m, n_w = n_coefficients(level), 2 ** (level - 1)
    supports = _support_open(level)
    if level <= 5:
        edge = list(range(n_w))
        vectors = _open_wavelets_by_null_space(level)
    else:  # boundary wavelets do not change with the level; interior ones are translates
        edge = [0, 1, 2, n_w - 3, n_w - 2, n_w - 1]
        level5 = _open_wavelets_by_null_space(5)
        vectors = level5[:3] + level5[-3:]
    rows, cols, vals = [], [], []
    for col, vec in zip(edge, vectors):
        rows.append(np.arange(supports[col][0], supports[col][1] + 1))
        cols.append(np.full(len(vec), col))
        vals.append(vec)
    if level > 5:
        inner = np.repeat(np.arange(3, n_w - 3), 11)
        rows.append(2 * inner - 3 + np.tile(np.arange(11), len(inner) // 11))
        cols.append(inner)
        vals.append(np.tile(_open_wavelets_by_null_space(5)[3], len(inner) // 11))
    return _coo(rows, cols, vals, (m, n_w))


@lru_cache(maxsize=8)
def _open_wavelets_by_null_space(level: int) -> list[FloatArray]:
    """Every wavelet column of a small open level, as the null vector of (P^T I) on its support."""
    constraints = (synthesis_p(level).T @ gram(level)).tocsr()
    out = []
    for a, b in _support_open(level):
        support = np.arange(a, b + 1)
        g = gram(level)[support][:, support].toarray()
        out.append(_normalized(_null_vector(constraints, support), g))
    return out


@lru_cache(maxsize=1)
def chui_wang() -> FloatArray:
    """The interior cubic B-spline wavelet (11 taps), norm sqrt(h), from a periodic level 5."""
    level = 5
    constraints = (synthesis_p(level, True).T @ gram(level, True)).tocsr()
    support = np.arange(0, 11)
    g = gram(level, True)[support][:, support].toarray()
    return _normalized(_null_vector(constraints, support), g)


def _periodic_q(level: int) -> sp.csr_matrix:
    m, n_w = 2**level, 2 ** (level - 1)
    cols = np.repeat(np.arange(n_w), 11)
    rows = (2 * cols + np.tile(np.arange(-2, 9), n_w)) % m
    vals = np.tile(chui_wang(), n_w)
    return sp.csr_matrix((vals, (rows, cols)), shape=(m, n_w))


def _check_level(level: int, closed: bool) -> None:
    if int(level) != level or level < MIN_LEVEL[closed] + 1:
        raise ParameterError(f"level {level} has no coarser level for a "
                             f"{'closed' if closed else 'open'} curve (minimum "
                             f"{MIN_LEVEL[closed] + 1})")


# ---------------------------------------------------------------------------------------------
# Analysis (eq. 5) and synthesis (eq. 11) in O(n)


class _BandedLU:
    """LU factors of a banded matrix (LAPACK gbtrf), reusable for many right-hand sides."""

    def __init__(self, lu: FloatArray, piv: np.ndarray, kl: int, ku: int):
        self.lu, self.piv, self.kl, self.ku = lu, piv, kl, ku

    @classmethod
    def factor(cls, mat: sp.csr_matrix) -> _BandedLU:
        coo = mat.tocoo()
        kl = int(max(0, (coo.row - coo.col).max()))
        ku = int(max(0, (coo.col - coo.row).max()))
        ab = np.zeros((2 * kl + ku + 1, mat.shape[0]))
        ab[kl + ku + coo.row - coo.col, coo.col] = coo.data
        lu, piv, info = lapack.dgbtrf(ab, kl, ku)
        if info != 0:
            raise ArithmeticError("[P|Q] is singular")  # pragma: no cover
        return cls(lu, piv, kl, ku)

    def widened(self, n: int, edge: int) -> _BandedLU:
        """The factors of the same shift-invariant matrix at size ``n`` (see `analysis_solver`)."""
        lu = _stretch(np.ascontiguousarray(self.lu.T), n, edge).T  # Fortran order, as LAPACK
        rel = _stretch(self.piv - np.arange(len(self.piv)), n, edge)
        return _BandedLU(lu, (rel + np.arange(n)).astype(self.piv.dtype), self.kl, self.ku)

    def solve(self, rhs: FloatArray) -> FloatArray:
        x, info = lapack.dgbtrs(self.lu, self.kl, self.ku, rhs, self.piv)
        if info != 0:
            raise ArithmeticError("banded solve failed")  # pragma: no cover
        return x


def _stretch(a: np.ndarray, n: int, edge: int, step: int = 0) -> np.ndarray:
    """Lengthen ``a`` to ``n`` rows by repeating its period-2 middle.

    The first and last ``edge`` rows are kept; the middle repeats rows ``edge`` and ``edge + 1``,
    adding ``step`` per period; the last ``edge`` rows get the total added.
    """
    reps, pairs = n - 2 * edge, (n - 2 * edge) // 2
    out = np.empty((n,) + a.shape[1:], dtype=a.dtype)
    out[:edge], out[n - edge:] = a[:edge], a[-edge:] + step * ((n - len(a)) // 2)
    periods = out[edge:edge + 2 * pairs].reshape((pairs, 2) + a.shape[1:])
    periods[:] = a[edge:edge + 2]
    if reps % 2:
        out[edge + reps - 1] = a[edge]
    if step:
        out[edge:n - edge] += step * (np.arange(reps) // 2).reshape((-1,) + (1,) * (a.ndim - 1))
    return out


class OpenSolver:
    """Solves [P | Q] x = c for one open level; columns interleaved so the matrix is banded."""

    def __init__(self, order: np.ndarray, n_coarse: int, lu: _BandedLU):
        self.order, self.n_coarse, self.lu = order, n_coarse, lu

    @classmethod
    def build(cls, level: int) -> OpenSolver:
        p, q = synthesis_p(level), synthesis_q(level)
        pq = sp.hstack([p, q]).tocsc()
        counts = np.diff(pq.indptr)
        owner = np.repeat(np.arange(pq.shape[1]), counts)
        centre = np.bincount(owner, weights=pq.indices, minlength=pq.shape[1]) / counts
        order = np.argsort(centre, kind="stable")
        return cls(order, p.shape[1], _BandedLU.factor(pq[:, order].tocsr()))

    def widened(self, level: int) -> OpenSolver:
        """This reference level's solver carried to a finer ``level`` without a new factorization.

        Away from the ends, interleaved [P | Q] is invariant under a shift of two rows and two
        columns, and its LU factors converge to that period within about 70 columns (they
        agree to the last bit beyond; `tests/test_wavelets.py` checks it against a direct
        factorization). So the factors of level j are those of the reference level with the
        periodic middle repeated, which costs O(n) with no arithmetic.
        """
        n = n_coefficients(level)
        is_q = self.order >= self.n_coarse
        index = np.where(is_q, self.order - self.n_coarse, self.order)
        n_coarse = n_coefficients(level - 1)
        index = _stretch(index, n, _EDGE, step=1)
        is_q = _stretch(is_q.astype(np.int64), n, _EDGE).astype(bool)
        order = np.where(is_q, index + n_coarse, index)
        return OpenSolver(order, n_coarse, self.lu.widened(n, _EDGE))

    def __call__(self, c: FloatArray) -> tuple[FloatArray, FloatArray]:
        y = self.lu.solve(np.ascontiguousarray(c, dtype=np.float64))
        x = np.empty_like(y)
        x[self.order] = y
        return x[: self.n_coarse], x[self.n_coarse:]


class PeriodicSolver:
    """Solves [P | Q] x = c for one periodic level by FFT: O(n log n), nothing to factor.

    Split c into even and odd rows; each is a sum of two circular convolutions (of the coarse
    and of the detail coefficients), so at every frequency the analysis is a 2 x 2 solve.
    """

    def __init__(self, level: int):
        self.n = 2 ** (level - 1)
        (pe, po), (qe, qo) = (self._polyphase(taps, first) for taps, first in
                              ((_P_PERIODIC, -2), (chui_wang(), -2)))
        det = pe * qo - qe * po
        self.rows = np.array([[qo, -qe], [-po, pe]]) / det  # inverse of [[pe, qe], [po, qo]]

    def _polyphase(self, taps: FloatArray, first: int) -> tuple[np.ndarray, np.ndarray]:
        """Spectra of the even- and odd-row kernels of a filter with taps at 2i + first + t."""
        offsets = first + np.arange(len(taps))
        kernels = np.zeros((2, self.n))
        np.add.at(kernels, (offsets % 2, (offsets // 2) % self.n), taps)  # wrapped taps add up
        return np.fft.rfft(kernels[0]), np.fft.rfft(kernels[1])

    def __call__(self, c: FloatArray) -> tuple[FloatArray, FloatArray]:
        spectra = np.fft.rfft(np.asarray(c, dtype=np.float64).reshape(self.n, 2, -1), axis=0)
        even, odd = spectra[:, 0], spectra[:, 1]
        rows = self.rows[..., None]
        coarse = rows[0, 0] * even + rows[0, 1] * odd
        detail = rows[1, 0] * even + rows[1, 1] * odd
        return (np.fft.irfft(coarse, n=self.n, axis=0), np.fft.irfft(detail, n=self.n, axis=0))


#: Open levels above this one reuse its LU factors (`OpenSolver.widened`).
REFERENCE_LEVEL = 9
#: Columns at each end of the reference factors that hold the boundary transients.
_EDGE = 128


@lru_cache(maxsize=64)
def analysis_solver(level: int, closed: bool) -> OpenSolver | PeriodicSolver:
    if closed:
        return PeriodicSolver(level)
    if level <= REFERENCE_LEVEL:
        return OpenSolver.build(level)
    return analysis_solver(REFERENCE_LEVEL, False).widened(level)


def analyze(c: FloatArray, closed: bool = False) -> tuple[FloatArray, FloatArray]:
    """One analysis step (eq. 5): c[j] -> (c[j-1], d[j-1]) in O(n).

    ``c`` is (n(j), k) for any k (k = 2 for planar control points).
    """
    level = level_of(len(c), closed)
    _check_level(level, closed)
    return analysis_solver(level, closed)(c)


def synthesize(coarse: FloatArray, detail: FloatArray, closed: bool = False) -> FloatArray:
    """One synthesis step (eq. 11): c[j] = P[j] c[j-1] + Q[j] d[j-1]."""
    level = level_of(len(coarse), closed) + 1
    if len(detail) != 2 ** (level - 1):
        raise ParameterError(f"detail has {len(detail)} rows; level {level - 1} needs "
                             f"{2 ** (level - 1)}")
    return synthesis_p(level, closed) @ coarse + synthesis_q(level, closed) @ detail


def decompose(coefficients: FloatArray, levels: int, *, closed: bool = False
              ) -> tuple[FloatArray, list[FloatArray]]:
    """Decompose control points ``levels`` times, like PyWavelets' ``wavedec``.

    Parameters
    ----------
    coefficients : (m, d) control points, m = 2**j + 3 (open) or 2**j (closed).
    levels : number of analysis steps, 0 <= levels <= j - MIN_LEVEL[closed].
    closed : periodic (closed curve) or endpoint-interpolating (open curve) wavelets.

    Returns
    -------
    coarse : (n(j - levels), d) scaling coefficients of the coarsest level.
    details : wavelet coefficients, coarsest level first: details[k] has 2**(j - levels + k) rows.
    """
    c = np.asarray(coefficients, dtype=np.float64)
    if c.ndim != 2:
        raise ParameterError(f"coefficients must be an (m, d) array, got shape {c.shape}")
    top = level_of(len(c), closed)
    if not 0 <= levels <= top - MIN_LEVEL[closed]:
        raise ParameterError(f"cannot decompose level {top} {levels} times "
                             f"(at most {top - MIN_LEVEL[closed]})")
    details: list[FloatArray] = []
    for _ in range(levels):
        c, d = analyze(c, closed)
        details.append(d)
    return c, details[::-1]


def reconstruct(coarse: FloatArray, details: list[FloatArray], *, closed: bool = False
                ) -> FloatArray:
    """Inverse of `decompose`, like PyWavelets' ``waverec`` (eq. 11 applied level by level)."""
    c = np.asarray(coarse, dtype=np.float64)
    for d in details:
        c = synthesize(c, np.asarray(d, dtype=np.float64), closed)
    return c
