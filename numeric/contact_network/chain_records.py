"""Checkpoint records of the contact-network sampler: finished blocks of one chain, finished chains of many.

A chain of :class:`~forcenet.numeric.contact_network.hit_and_run.HitAndRun`
records its states in blocks whose boundaries depend on the request alone
(:func:`block_rows`); after each block the forces are projected back onto
``A z = b`` and the block is saved in the request's
:class:`~forcenet.core.checkpoints.CheckpointStore` (atomic, checksummed
files), together with everything the chain needs to go on: the forces ``z``
after the block and the state of its random generator (PCG64: 128-bit state
and increment, the buffered 32-bit half).  A rerun of the same request
reloads the longest run of finished blocks, restores ``z`` and the
generator and continues: the states are bit for bit those of an
uninterrupted run with the same seed (the burn-in's rounding directions are
recomputed from the seed, a deterministic step).

The records are the store's int64 arrays: float64 samples travel as their
bit patterns (``ndarray.view``), never rounded.  Every record of a request
has one shape, declared to the store (:func:`block_shape`), so a record of
another shape is named and recomputed like a damaged one.

Examples
--------
>>> import tempfile, numpy as np
>>> rng = np.random.default_rng(5)
>>> record = encode_block(np.ones((2, 3)), np.arange(3.0), rng, rows=2)
>>> record.shape == block_shape(2, 3)
True
>>> rows, z, state = decode_block(record, 2, 3, 2)
>>> rows.tolist(), z.tolist(), state == rng.bit_generator.state
([[1.0, 1.0, 1.0], [1.0, 1.0, 1.0]], [0.0, 1.0, 2.0], True)
"""

from __future__ import annotations

import hashlib
from typing import Any

import numpy as np

from forcenet.core.checkpoints import CheckpointStore
from forcenet.exact.contact_network.model import ContactNetwork

__all__ = ["RECORD_VALUES", "PROJECT_MOVES", "STATE_WORDS", "block_rows", "block_shape", "encode_block",
           "decode_block", "network_digest", "chain_store"]

RECORD_VALUES = 2**21  # floats of one record at most (16 MiB): a block of a 10^4-contact network is ~200 states
PROJECT_MOVES = 2**20  # moves between two projections onto A z = b (the rounding drift stays ~1e-13)
STATE_WORDS = 6  # PCG64: state (2 words), increment (2 words), has_uint32, uinteger
_MASK = (1 << 64) - 1


def block_rows(samples: int, thin: int, dimension: int, variables: int, rows: int | None = None) -> int:
    """Recorded states per block: the chain projects and checkpoints after each (a function of the request only).

    At most :data:`PROJECT_MOVES` moves and :data:`RECORD_VALUES` floats per block; ``rows`` overrides.

    Examples
    --------
    >>> block_rows(4000, 20, 230, 2212), block_rows(10, 1, 3, 15), block_rows(10, 1, 3, 15, rows=4)
    (227, 10, 4)
    """
    if rows is not None:
        return max(1, min(samples, rows))
    by_moves = PROJECT_MOVES // max(1, dimension * thin)
    by_size = RECORD_VALUES // max(1, variables)
    return max(1, min(samples, by_moves, by_size))


def block_shape(rows: int, variables: int) -> tuple[int]:
    """The one shape of every block record: ``rows`` states (the last block padded), ``z``, the generator.

    Examples
    --------
    >>> block_shape(10, 15)
    (171,)
    """
    return (rows * variables + variables + STATE_WORDS,)


def _words(value: int) -> list[int]:
    """A 128-bit unsigned integer as two int64 words (two's complement bit patterns)."""
    return [int(np.uint64(w).view(np.int64)) for w in ((value >> 64) & _MASK, value & _MASK)]


def _unwords(hi: int, lo: int) -> int:
    return (int(np.int64(hi).view(np.uint64)) << 64) | int(np.int64(lo).view(np.uint64))


def encode_block(states: np.ndarray, z: np.ndarray, rng: np.random.Generator, rows: int) -> np.ndarray:
    """One block's record: its states (padded to ``rows``), the forces after it and the generator's state.

    Examples
    --------
    >>> encode_block(np.zeros((1, 2)), np.zeros(2), np.random.default_rng(0), rows=3).shape
    (14,)
    """
    variables = z.shape[0]
    padded = np.zeros((rows, variables))
    padded[:states.shape[0]] = states
    state = rng.bit_generator.state
    words = [*_words(state["state"]["state"]), *_words(state["state"]["inc"]), int(state["has_uint32"]),
             int(state["uinteger"])]
    return np.concatenate([padded.ravel().view(np.int64), np.ascontiguousarray(z, dtype=np.float64).view(np.int64),
                           np.array(words, dtype=np.int64)])


def decode_block(record: np.ndarray, count: int, variables: int,
                 rows: int) -> tuple[np.ndarray, np.ndarray, dict[str, Any]]:
    """``(states, z, generator state)`` of a record of :func:`encode_block` (its first ``count`` states).

    Examples
    --------
    >>> rng = np.random.default_rng(1)
    >>> decode_block(encode_block(np.ones((1, 2)), np.ones(2), rng, 1), 1, 2, 1)[2]["bit_generator"]
    'PCG64'
    """
    values = np.ascontiguousarray(record, dtype=np.int64)
    states = values[:rows * variables].view(np.float64).reshape(rows, variables)[:count].copy()
    z = values[rows * variables:rows * variables + variables].view(np.float64).copy()
    w = [int(x) for x in values[-STATE_WORDS:]]
    state = {"bit_generator": "PCG64", "state": {"state": _unwords(w[0], w[1]), "inc": _unwords(w[2], w[3])},
             "has_uint32": w[4], "uinteger": w[5]}
    return states, z, state


def network_digest(network: ContactNetwork) -> str:
    """A short digest of what determines the forces (grains, contacts, loads, friction, radii).

    Examples
    --------
    >>> from forcenet.exact.contact_network.geometries import triangle
    >>> network_digest(triangle(3).network) == network_digest(triangle(3).network), len(network_digest(triangle(3).network))
    (True, 16)
    """
    text = repr((network.grains, network.contacts, network.loads, network.friction, network.radii))
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def chain_store(directory: str, network: ContactNetwork, key: tuple[Any, ...],
                shape: tuple[int, ...]) -> CheckpointStore:
    """The store of one sampling request: its folder named by the network's digest and the request's ``key``
    (seed, samples, burn-in, thin, block or chain layout: everything the states depend on).

    Examples
    --------
    >>> import tempfile
    >>> from forcenet.exact.contact_network.geometries import triangle
    >>> store = chain_store(tempfile.mkdtemp(), triangle(3).network, (1, 100, None, 1, 100), (5,))
    >>> store.request["route"].startswith("network-hit-and-run-")
    True
    """
    request = hashlib.sha256(repr(key).encode()).hexdigest()[:12]
    return CheckpointStore(directory, f"network-hit-and-run-{network_digest(network)}-{request}", network.grains,
                           shape=shape)
