"""Global interference of a cam surface: where the closed outline crosses itself.

The local undercut tests compare a radius of curvature with the roller
radius (or with zero for a flat face) at the sampled angles. The outline that
a cutter would actually leave is the boundary of the region the computed
envelope encloses once: where the envelope folds over into a loop (the
swallowtail of an undercut, Norton §8.7) that loop is cut away and
the follower does not follow its law there. This module finds those loops on
the sampled outline itself, so it does not depend on the curvature formulas.

Two steps, both vectorised:

1. :func:`polyline_crossings` finds every proper crossing of two
   non-adjacent segments of a closed polyline. Candidate pairs come from a
   uniform grid of cells about two segments wide: each segment is entered in
   every cell its bounding box touches, and only segments sharing a cell are
   tested. Two segments that cross share the cell of their crossing point, so
   no crossing is missed. Only occupied cells are kept (sorted keys), so time
   and memory grow as n log n with the number of points.
2. :func:`loop_pieces` cuts the outline at the crossings and asks, for each
   piece, how many times the whole outline winds round a point just inside it
   (on the material side). A piece of the real surface has the solid cam
   (winding number 1) on that side; a piece of a loop does not.
"""

from __future__ import annotations

import numpy as np

__all__ = ["loop_pieces", "polyline_crossings", "winding_number"]

_BLOCK = 1 << 20  # complex numbers held at once by winding_number


def polyline_crossings(z: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Proper crossings of the closed polyline ``z[0] → z[1] → … → z[-1] → z[0]``.

    Parameters
    ----------
    z : ndarray of complex, shape (n,)
        Vertices. Repeated consecutive vertices are allowed (they are merged).

    Returns
    -------
    tau_a, tau_b : ndarray
        Position of each crossing along the polyline in vertex units: vertex
        ``k`` is at ``k``, the point ``t`` of the way along segment ``k`` is at
        ``k + t``. ``tau_a < tau_b``; one entry per crossing, sorted by ``tau_a``.
    point : ndarray of complex
        The crossing points.

    Notes
    -----
    A crossing is counted when each segment's end points lie strictly on
    opposite sides of the other's line, with a point exactly on a line counted
    on the negative side, so a polyline that crosses another part of itself
    exactly at a vertex is counted once. One that only touches another part is
    counted an even number of times (none or two at the point of contact), and
    :func:`loop_pieces` finds no loop there.

    Examples
    --------
    A figure of eight crosses itself once, at the origin:

    >>> eight = np.array([-1 - 1j, 1 + 1j, 1 - 1j, -1 + 1j])
    >>> tau_a, tau_b, point = polyline_crossings(eight)
    >>> tau_a.tolist(), tau_b.tolist(), point.tolist()
    ([0.5], [2.5], [0j])
    """
    z = np.asarray(z, dtype=complex).ravel()
    empty = np.empty(0), np.empty(0), np.empty(0, dtype=complex)
    keep = _distinct(z)
    if keep.size < 4:
        return empty
    vertex_tau = keep.astype(float)
    span = np.diff(np.append(vertex_tau, keep[0] + z.size))  # vertex units along each segment
    start = z[keep]
    end = np.roll(start, -1)
    i, j = _candidate_pairs(start, end)
    if i.size == 0:
        return empty
    ai, ei = start[i], end[i] - start[i]
    aj, ej = start[j], end[j] - start[j]
    d1 = _cross(ei, aj - ai)  # where segment j's ends lie against segment i's line
    d2 = _cross(ei, aj + ej - ai)
    d3 = _cross(ej, ai - aj)  # and segment i's ends against segment j's line
    d4 = _cross(ej, ai + ei - aj)
    hit = ((d1 > 0.0) != (d2 > 0.0)) & ((d3 > 0.0) != (d4 > 0.0))
    i, j, d3, d4 = i[hit], j[hit], d3[hit], d4[hit]
    d1, d2 = d1[hit], d2[hit]
    t = d3 / (d3 - d4)  # fraction along segment i
    u = d1 / (d1 - d2)  # fraction along segment j
    point = start[i] + t * (end[i] - start[i])
    tau_a = vertex_tau[i] + t * span[i]
    tau_b = vertex_tau[j] + u * span[j]
    order = np.argsort(tau_a, kind="stable")
    return tau_a[order], tau_b[order], point[order]


def _distinct(z: np.ndarray) -> np.ndarray:
    """Indices of the vertices that differ from the one before (cyclically).

    A zero-length segment would touch its neighbours' neighbours, so repeated
    vertices are merged before anything else.
    """
    if z.size < 2:
        return np.arange(z.size)
    keep = np.flatnonzero(z != np.roll(z, 1))
    return keep if keep.size else np.array([0])


def _cross(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """z-component of p × q for planar vectors stored as complex numbers."""
    return p.real * q.imag - p.imag * q.real


#: A segment whose bounding box covers more grid cells than this is "long".
_LONG_CELLS = 64
#: Most pairs tested for long segments before they are gridded like the rest.
_LONG_PAIRS = 4_000_000
#: Grid entries allowed per segment on average (the cells grow until they fit).
_ENTRIES_PER_SEGMENT = 16


def _candidate_pairs(start: np.ndarray, end: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Pairs (i < j) of non-adjacent segments whose bounding boxes may meet.

    Segments are entered in every cell of a grid that their bounding box covers and
    paired within each cell. A segment much longer than the cell (its box covers
    more than :data:`_LONG_CELLS` cells; a coarse stretch of the outline) is paired
    with every other segment instead, so that a few long segments among many short
    ones cost O(n) each rather than millions of grid entries.
    """
    n = start.size
    length = np.abs(end - start)
    lo = np.minimum(start.real, end.real) + 1j * np.minimum(start.imag, end.imag)
    hi = np.maximum(start.real, end.real) + 1j * np.maximum(start.imag, end.imag)
    origin = complex(lo.real.min(), lo.imag.min())
    extent = max(hi.real.max() - origin.real, hi.imag.max() - origin.imag)
    # About two typical segments per cell (a typical segment then touches at most four
    # cells, so the grid holds O(n) entries and each cell a few: O(n log n) in all, the
    # sort). Only occupied cells exist (their keys are sorted, no dense array).
    cell = max(2.0 * float(np.median(length)), extent * 2.0**-40)
    if not cell > 0.0:
        return np.empty(0, dtype=np.intp), np.empty(0, dtype=np.intp)
    while True:
        ix0 = np.floor((lo.real - origin.real) / cell).astype(np.int64)
        iy0 = np.floor((lo.imag - origin.imag) / cell).astype(np.int64)
        nx = np.floor((hi.real - origin.real) / cell).astype(np.int64) - ix0 + 1
        ny = np.floor((hi.imag - origin.imag) / cell).astype(np.int64) - iy0 + 1
        long = nx * ny > _LONG_CELLS
        if long.sum() * n > _LONG_PAIRS:  # many long segments (no cam outline): grid them all
            long[:] = False
        if int((nx * ny)[~long].sum()) <= _ENTRIES_PER_SEGMENT * n:
            break
        cell *= 2.0  # a few very long segments among short ones: coarser cells
    # One entry per (short segment, cell of its bounding box).
    short = np.flatnonzero(~long)
    count = (nx * ny)[short]
    segment = np.repeat(short, count)
    k = np.arange(segment.size) - np.repeat(np.cumsum(count) - count, count)
    cx = ix0[segment] + k % nx[segment]
    cy = iy0[segment] + k // nx[segment]
    key = cx * (int(iy0.max() + ny.max()) + 1) + cy
    order = np.argsort(key, kind="stable")
    key, segment, cx, cy = key[order], segment[order], cx[order], cy[order]
    # Pair each entry with the later entries of its cell.
    group_end = np.searchsorted(key, key, side="right")
    partners = group_end - np.arange(key.size) - 1
    first = np.repeat(np.arange(key.size), partners)
    second = first + 1 + np.arange(first.size) - np.repeat(np.cumsum(partners) - partners, partners)
    i = np.minimum(segment[first], segment[second])
    j = np.maximum(segment[first], segment[second])
    # Two boxes may share several cells: keep the pair in one of them only, the cell
    # at the lower-left corner of the boxes' overlap.
    once = (cx[first] == np.maximum(ix0[i], ix0[j])) & (cy[first] == np.maximum(iy0[i], iy0[j]))
    i, j = i[once], j[once]
    if long.any():  # each long segment against every other (a long pair once)
        li = np.repeat(np.flatnonzero(long), n)
        lj = np.tile(np.arange(n), int(long.sum()))
        take = ~long[lj] | (lj > li)
        li, lj = li[take], lj[take]
        i, j = np.r_[i, np.minimum(li, lj)], np.r_[j, np.maximum(li, lj)]
    apart = (j - i > 1) & (j - i < n - 1)  # segments that share no vertex
    return i[apart], j[apart]


def _merged_units(z: np.ndarray, tau: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The polyline without repeated vertices, and ``tau`` counted along it."""
    keep = _distinct(z)
    ends = np.append(keep, keep[0] + z.size)
    tau = np.mod(tau - keep[0], z.size) + keep[0]
    return z[keep], np.interp(tau, ends, np.arange(keep.size + 1.0))


def winding_number(z: np.ndarray, q: np.ndarray) -> np.ndarray:
    """How many times the closed polyline ``z`` winds counter-clockwise round each point ``q``.

    Examples
    --------
    >>> square = np.array([0, 1, 1 + 1j, 1j])
    >>> winding_number(square, np.array([0.5 + 0.5j, 2.0])).tolist()
    [1, 0]
    """
    q = np.asarray(q)
    turn = np.empty(q.shape)
    block = max(1, _BLOCK // max(z.size, 1))  # points per block, to bound the memory
    for first in range(0, q.size, block):
        rel = z[None, :] - q[first : first + block, None]
        turn[first : first + block] = np.angle(np.roll(rel, -1, axis=1) / rel).sum(axis=1)
    return np.rint(turn / (2.0 * np.pi)).astype(int)


def loop_pieces(
    z: np.ndarray, tau_a: np.ndarray, tau_b: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Cut the closed polyline at its crossings and say which pieces lie in a loop.

    Parameters
    ----------
    z : ndarray of complex
        The closed polyline (as for :func:`polyline_crossings`).
    tau_a, tau_b : ndarray
        Its crossings, from :func:`polyline_crossings`.

    Returns
    -------
    piece_start, piece_end : ndarray
        Each piece runs from ``piece_start`` to ``piece_end`` (vertex units,
        ``piece_end`` may exceed ``n`` for the piece that wraps round).
    in_loop : ndarray of bool
        True for a piece that is not on the boundary of the region the outline
        encloses once: on its material side the winding number (counted in the
        outline's own sense) is not 1.

    Examples
    --------
    A counter-clockwise square with a small clockwise loop at one corner:

    >>> z = np.array([0, 2, 2 + 2.5j, 2.5 + 2.5j, 2.5 + 2j, 2j])
    >>> start, end, in_loop = loop_pieces(z, *polyline_crossings(z)[:2])
    >>> start.tolist(), end.tolist(), in_loop.tolist()
    ([1.8, 4.2], [4.2, 7.8], [True, False])
    """
    n = z.size
    if tau_a.size == 0:
        return np.array([0.0]), np.array([float(n)]), np.array([False])
    cuts = np.sort(np.concatenate((tau_a, tau_b)))
    piece_start = cuts
    piece_end = np.append(cuts[1:], cuts[0] + n)
    # Probe each piece in the middle of a segment (away from corners) where it can.
    corners, (lo, hi) = _merged_units(z, np.stack((piece_start, piece_end)))
    hi = lo + np.mod(hi - lo, corners.size)
    probe = np.floor(0.5 * (lo + hi)) + 0.5
    probe = np.where((probe > lo) & (probe < hi), probe, 0.5 * (lo + hi))
    k = np.floor(probe).astype(np.intp) % corners.size
    direction = corners[(k + 1) % corners.size] - corners[k]
    middle = corners[k] + (probe - np.floor(probe)) * direction
    area = 0.5 * _cross(corners, np.roll(corners, -1)).sum()
    sense = 1.0 if area >= 0.0 else -1.0
    # The material side is on the left of a counter-clockwise outline.
    scale = np.abs(corners - corners.mean()).max()
    inside = middle + sense * 1e-9 * scale * 1j * direction / np.abs(direction)
    # A piece of no length (two crossings at one point, where corners touch) holds no surface.
    in_loop = (sense * winding_number(corners, inside) != 1) & (hi > lo)
    return piece_start, piece_end, in_loop
