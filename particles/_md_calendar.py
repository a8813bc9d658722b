"""Event calendar of the event-driven MD: a small heap for the near future, buckets after.

One predicted collision time per neighbour pair must be kept in time order with three
updates per collision (:mod:`particles._md_kernels`).  An indexed heap of all pending
pairs costs :math:`O(\\log N)` per update, and at large N a cache miss per level.  The
calendar of Paul (J. Comput. Phys. 221, 615 (2007)) makes it :math:`O(1)`: an *epoch*
:math:`[t_b, t_h)` (from one kick to the next in a heated run; a span adapted to the
collision rate in free cooling) is cut into ``nb`` buckets of width
:math:`w = (t_h - t_b)/nb`; a pair due at :math:`t_p` belongs to bucket
:math:`k = \\lfloor (t_p - t_b)/w \\rfloor` (the same rounded formula everywhere, so
the order between buckets is exact).  Pairs of bucket ``k > cur`` sit unsorted in the
doubly linked list of bucket ``k`` (``head``, ``nxt``, ``prv``, ``bkt``; their times in
``ptime``); pairs of buckets up to the current one ``cur`` sit in a small indexed 4-ary
min-heap (``heap`` of pair indices, ``hkey`` their times in heap order, ``where`` the
slot of each pair or -1; every ``hkey`` slot at or beyond the heap size holds ``inf``).
When the heap empties, ``cur`` moves to the next non-empty bucket and its list is
heaped.  Pairs due at or after :math:`t_h` are not queued: the epoch ends with a sweep
over all pairs (the kick, or a rebuild) that starts the next one.  ``nb`` is the power
of two at or above the number of pairs queued at the start of an epoch, so a bucket
holds about one pair and the heap stays small however large N is.

State: ``fstate[F_BASE]``, ``fstate[F_INV_W]``, ``fstate[F_HORIZON]`` (:math:`t_b`,
:math:`1/w`, :math:`t_h`); ``istate[I_HSIZE]``, ``istate[I_CUR]``, ``istate[I_NB]``.
All functions take arrays and scalars only.
"""

from __future__ import annotations

import numpy as np

from ._jit import jit

__all__ = ["F_BASE", "F_INV_W", "F_HORIZON", "I_HSIZE", "I_CUR", "I_NB", "HEAP_PAD",
           "sift_down", "list_push", "calendar_start", "bucket_of"]

# slots of the float and integer state vectors used by the calendar (the MD kernels
# use the others)
F_BASE, F_INV_W, F_HORIZON = 4, 5, 6
I_HSIZE, I_CUR, I_NB = 1, 6, 7
HEAP_PAD = 4
"""Slots of ``hkey`` beyond ``N`` (always ``inf``)."""


@jit
def sift_down(heap, hkey, where, pos, p, kp, size):  # pragma: no cover - compiled
    """Place pair ``p`` with time ``kp`` at slot ``pos`` or below (heap of ``size``).

    The children of slot ``k`` are ``4k + 1 ... 4k + 4``; the earliest is found by a
    tournament (ties to the left) that reads the ``inf`` slots beyond the heap.
    """
    while True:
        c = 4 * pos + 1
        if c >= size:
            break
        h0, h1, h2, h3 = hkey[c], hkey[c + 1], hkey[c + 2], hkey[c + 3]
        c01 = c + (h1 < h0)
        k01 = min(h0, h1)
        c23 = c + 2 + (h3 < h2)
        k23 = min(h2, h3)
        child = c23 if k23 < k01 else c01
        kc = min(k01, k23)
        if kp <= kc:
            break
        q = heap[child]
        heap[pos] = q
        hkey[pos] = kc
        where[q] = pos
        pos = child
    heap[pos] = p
    hkey[pos] = kp
    where[p] = pos


@jit
def list_push(b, p, head, nxt, prv, bkt):  # pragma: no cover - compiled
    """Put pair ``p`` at the front of the list of bucket ``b``."""
    h = head[b]
    nxt[p] = h
    prv[p] = -1
    if h >= 0:
        prv[h] = p
    head[b] = p
    bkt[p] = b


@jit
def calendar_start(size, base, horizon, heap, hkey, where, ptime, head, nxt, prv, bkt,
                   fstate, istate):  # pragma: no cover - compiled
    """Start an epoch ``[base, horizon)`` with the ``size`` pairs of ``heap[:size]``.

    ``heap[:size]``, ``hkey[:size]`` hold the pairs due before ``horizon`` and their
    times (any order); the calendar must be empty (every bucket list empty) and
    ``hkey`` must be ``inf`` from ``size`` on.  The pairs of bucket 0 are heaped, the
    others go to their buckets' lists.
    """
    nb = 1
    while nb < size and nb < head.shape[0]:
        nb *= 2
    fstate[F_BASE] = base
    fstate[F_HORIZON] = horizon
    span = horizon - base
    fstate[F_INV_W] = nb / span if span > 0.0 else 0.0
    istate[I_NB] = nb
    istate[I_CUR] = 0
    h = 0
    for k in range(size):
        q = heap[k]
        tq = hkey[k]
        b = bucket_of(tq, base, nb / span if span > 0.0 else 0.0, horizon, nb)
        if b <= 0:
            heap[h] = q
            hkey[h] = tq
            where[q] = h
            h += 1
        else:
            where[q] = -1
            ptime[q] = tq
            list_push(b, q, head, nxt, prv, bkt)
    for k in range(h, size):
        hkey[k] = np.inf
    istate[I_HSIZE] = h
    for pos in range((h - 2) // 4, -1, -1):
        sift_down(heap, hkey, where, pos, heap[pos], hkey[pos], h)


@jit
def bucket_of(tp, base, inv_w, horizon, nb):  # pragma: no cover - compiled
    """Bucket of a pair due at ``tp`` in the epoch ``[base, horizon)`` of ``nb`` buckets.

    ``int((tp - base) inv_w)`` capped at ``nb - 1``; -1 (not queued) at or after the
    horizon.  The event loop of :mod:`particles._md_kernels` uses the same formula.
    """
    if not tp < horizon:
        return -1
    k = (tp - base) * inv_w
    return nb - 1 if k >= nb - 1 else int(k)
