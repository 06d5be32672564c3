"""Directions in Ker A without a basis: sparse projection, for hit-and-run on networks of 10^4 contacts.

The dense route (:class:`~.hit_and_run.HitAndRun` with ``basis="dense"``)
takes an orthonormal basis of ``Ker A`` from the singular value
decomposition: ``O(rows * variables^2)`` time and ``d * variables`` floats,
3.3 s at 2212 contacts (one thread) and minutes and gigabytes at 10^4.  This module never forms a
basis.  ``A A^T`` is sparse (its pattern is the grains' contact graph, each
grain's 2 or 3 balance rows coupled to its neighbours'), so its sparse LU
factorization (SuperLU, ``scipy.sparse.linalg.splu``, fill-reducing column
order) is cheap, and the orthogonal projector onto ``Ker A``,

    P g = g - A^T (A A^T)^(-1) A g,

costs one sparse solve.  A standard normal vector ``g`` of ``R^variables``
projected by ``P`` is a standard normal vector of ``Ker A`` (the projector is
orthogonal), so ``P g / |P g|`` is uniform on the kernel's unit sphere: the
direction law of Smith's hit-and-run (Smith 1984, Oper. Res. 32:1296), which
leaves the uniform measure on the polytope invariant (each move draws from the
uniform measure's exact conditional law on the chosen line, and the direction
is drawn independently of the state) and, every direction having a positive
density on the sphere, is irreducible on the convex body (Belisle, Romeijn and
Smith 1993).  The sampler is therefore exact in distribution without an
orthonormal basis; the length of a direction does not matter (the chord is
found in units of the direction).  Directions are drawn in batches (one
solve with many right-hand sides), independently of the chain's state, so a
batch drawn before its moves changes nothing in the law.

The same factorization projects drifting forces back onto ``A z = b``
(:meth:`KernelProjector.project`).  A rank-deficient ``A A^T`` (a grain whose
contact normals are all parallel) makes SuperLU fail: the walk then falls back
to the dense route (:class:`~.hit_and_run.HitAndRun`, ``basis="auto"``).

Examples
--------
>>> from forcenet.exact.contact_network.geometries import triangle
>>> from forcenet.exact.contact_network.polytope import balance, float_system
>>> A, b, G = float_system(balance(triangle(4).network))
>>> projector = KernelProjector(A)
>>> projector.dimension
6
>>> D = projector.directions(np.random.default_rng(0), 5)
>>> D.shape, bool(abs(A @ D.T).max() < 1e-12)
((5, 26), True)
"""

from __future__ import annotations

import numpy as np
from scipy import linalg, sparse
from scipy.sparse import linalg as sparse_linalg
from threadpoolctl import threadpool_limits

from forcenet.core.errors import ArgumentError

__all__ = ["BATCH", "KernelProjector", "reduced_rows", "independent_rows"]

BATCH = 64  # directions per sparse solve (one call with BATCH right-hand sides)


def reduced_rows(A: sparse.csr_matrix, b: np.ndarray, per: int) -> tuple[sparse.csr_matrix, np.ndarray]:
    """Each grain's ``per`` consecutive rows of ``A z = b`` replaced by an orthonormal basis of their span (a
    small SVD per grain: ``U S V^T z = b_g`` becomes ``V_r^T z = U_r^T b_g / S_r``), the same solutions; a
    grain without contacts (a rattler) or with parallel contacts loses its dependent rows.

    Examples
    --------
    >>> A = sparse.csr_matrix(np.array([[0.0, 0.0], [1.0, 1.0], [0.0, 0.0], [0.0, 0.0]]))
    >>> R, r = reduced_rows(A, np.array([0.0, 2.0, 0.0, 0.0]), 2)
    >>> R.shape, bool(np.allclose(R @ np.array([1.0, 1.0]), r))
    ((1, 2), True)
    """
    rows: list[int] = []
    cols: list[int] = []
    values: list[float] = []
    rhs: list[float] = []
    for first in range(0, A.shape[0], per):
        block = A[first:first + per]
        columns = np.unique(block.indices)
        if columns.size == 0:
            continue
        U, S, Vt = np.linalg.svd(block[:, columns].toarray(), full_matrices=False)
        rank = int((S > 1e-12 * S[0]).sum())
        for r in range(rank):
            rows += [len(rhs)] * columns.size
            cols += columns.tolist()
            values += Vt[r].tolist()
            rhs.append(float(U[:, r] @ b[first:first + per]) / S[r])
    return sparse.csr_matrix((values, (rows, cols)), shape=(len(rhs), A.shape[1])), np.array(rhs)


def independent_rows(A: sparse.csr_matrix, b: np.ndarray, most: int = 6) -> tuple[sparse.csr_matrix, np.ndarray]:
    """``A z = b`` without the rows that depend on others across grains (a zero mode of the whole packing, e.g.
    a sideways translation when no side wall is touched): the null vectors ``y`` of ``A A^T`` (``A^T y = 0``, at
    most ``most``, by shift-invert Lanczos) name them; the row with the largest weight in each (QR with column
    pivoting) is a combination of the others and is dropped; the solutions are the same (``b`` is consistent:
    the balance was checked by linear programming).

    Examples
    --------
    >>> A = sparse.csr_matrix(np.array([[1.0, 1.0, 0.0], [0.0, 1.0, 1.0], [1.0, 2.0, 1.0]]))
    >>> R, r = independent_rows(A, np.array([1.0, 1.0, 2.0]))
    >>> R.shape
    (2, 3)
    """
    rows = A.shape[0]
    if rows < 2:
        return A, b
    gram = (A @ A.T).tocsc()
    scale = float(abs(gram).max())
    if rows <= 2 * most + 1:
        values, vectors = np.linalg.eigh(gram.toarray())
    else:
        values, vectors = sparse_linalg.eigsh(gram, k=most, sigma=-1e-3 * scale, which="LM")
    null = vectors[:, values < 1e-10 * scale]
    if null.shape[1] == 0:
        return A, b
    _, _, pivots = linalg.qr(null.T, pivoting=True, mode="economic")
    keep = np.setdiff1d(np.arange(rows), pivots[:null.shape[1]])
    return A[keep], b[keep]


class KernelProjector:
    """The orthogonal projector onto ``Ker A`` by a sparse LU factorization of ``A A^T`` (module docstring).

    Parameters
    ----------
    A : scipy.sparse matrix
        The balance equations, ``rows x variables``.
    b : numpy.ndarray, optional
        Their right-hand side (for :meth:`project`).
    per : int, optional
        Rows per grain (2, or 3 with torques): each grain's rows are first reduced to a basis of their span
        (:func:`reduced_rows`), so a rattler or a grain with parallel contacts does not make ``A A^T``
        singular; 0: ``A`` as given.

    Attributes
    ----------
    dimension : int
        ``dim Ker A = variables - rows``.

    Raises
    ------
    ArgumentError
        ``A`` (reduced) is not of full row rank (``A A^T`` singular: a dependence between grains); the dense
        route handles it.

    Examples
    --------
    >>> A = sparse.csr_matrix(np.array([[1.0, 1.0, 1.0]]))
    >>> p = KernelProjector(A)
    >>> p.dimension, np.round(p.project(np.array([1.0, 0.0, 0.0]), np.array([1.0])), 12).tolist()
    (2, [1.0, 0.0, 0.0])
    """

    def __init__(self, A: sparse.spmatrix, b: np.ndarray | None = None, per: int = 0) -> None:
        A = sparse.csr_matrix(A)
        b = np.zeros(A.shape[0]) if b is None else np.asarray(b, dtype=float)
        A, b = reduced_rows(A, b, per) if per else (A, b)
        self.A, self.b = independent_rows(A, b) if per else (A, b)
        self.AT = self.A.T.tocsr()
        rows, variables = self.A.shape
        if rows > variables:
            raise ArgumentError("more balance equations than forces: A is not of full row rank")
        gram = (self.A @ self.AT).tocsc()
        try:
            # a symmetric ordering (minimum degree on A A^T's own pattern) and diagonal pivots: little fill
            self.lu = sparse_linalg.splu(gram, permc_spec="MMD_AT_PLUS_A", options={"SymmetricMode": True})
        except RuntimeError as exc:  # "Factor is exactly singular"
            raise ArgumentError(f"A A^T is singular ({exc}): A is not of full row rank") from None
        # SuperLU does not fail on a numerically singular matrix: check the pivots' spread
        pivots = np.abs(self.lu.U.diagonal())
        if rows and (pivots.min() <= 1e-10 * pivots.max()):
            raise ArgumentError("A A^T is numerically singular: A is not of full row rank")
        self.dimension = variables - rows

    @staticmethod
    def one_thread() -> threadpool_limits:
        """A context with BLAS in one thread: SuperLU's solves with many right-hand sides call BLAS, whose threads
        on a busy machine made a 1.5 ms solve take 100 ms (measured, load 15 on 2 cores).

        Examples
        --------
        >>> with KernelProjector.one_thread():
        ...     pass
        """
        return threadpool_limits(1)

    def _solve(self, rhs: np.ndarray) -> np.ndarray:
        return np.asarray(self.lu.solve(np.asfortranarray(rhs)))  # SuperLU copies a C-ordered block: 30x slower

    def project(self, z: np.ndarray, b: np.ndarray | None = None) -> np.ndarray:
        """``z`` moved orthogonally onto ``A z = b`` (removes the rounding drift of many moves).

        Examples
        --------
        >>> p = KernelProjector(sparse.csr_matrix(np.array([[1.0, -1.0]])))
        >>> p.project(np.array([1.0, 0.0]), np.array([0.0])).tolist()
        [0.5, 0.5]
        """
        return z - self.AT @ self._solve(self.A @ z - (self.b if b is None else b))

    def directions(self, rng: np.random.Generator, count: int) -> np.ndarray:
        """``count`` independent standard normal vectors of ``Ker A`` (rows; isotropic in the kernel).

        Examples
        --------
        >>> p = KernelProjector(sparse.csr_matrix(np.array([[1.0, 1.0]])))
        >>> d = p.directions(np.random.default_rng(1), 3)
        >>> bool(np.allclose(d[:, 0], -d[:, 1]))
        True
        """
        g = rng.standard_normal((count, self.A.shape[1]))
        return np.ascontiguousarray(g - (self.AT @ self._solve(self.A @ g.T)).T)

    def fixed(self, rng: np.random.Generator) -> np.ndarray:
        """The variables ``Ker A`` does not move (fixed by balance alone): zero in every one of a batch of random
        kernel vectors (a variable the kernel moves is nonzero in one with probability 1).

        Examples
        --------
        >>> A = sparse.csr_matrix(np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 1.0]]))
        >>> KernelProjector(A).fixed(np.random.default_rng(0)).tolist()
        [True, False, False]
        """
        sample = self.directions(rng, 8)
        return np.abs(sample).max(axis=0) < 1e-9 * max(1.0, float(np.abs(sample).max(initial=0.0)))
