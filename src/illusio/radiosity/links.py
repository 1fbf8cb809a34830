"""Links: light flowing from a source element j to a receiver element i at some level of the two
hierarchies, with the form factor F_ij, the visibility V_ij and its type (VISIBLE, PARTIAL,
INVISIBLE). Stored as flat arrays; the gather of every link at once is one pass over them
(:class:`LinkGather`), or one sparse product (:meth:`Links.matrix`)."""

from __future__ import annotations

import numba
import numpy as np
import scipy.sparse as sp

from .visibility import link_type

__all__ = ["Links", "LinkGather"]


@numba.njit(cache=True)
def _compact(drop, receiver, source, tag, rays, form_factor, visibility):
    """Move the entries where not ``drop`` to the front of the six arrays, in order, in place; return
    the entries where ``drop`` (fresh arrays, in order). ``tag`` and ``rays`` may be empty (the store
    has none): they are skipped and come back empty. One pass from the first removed entry and no
    fresh memory for the kept links: ten masked copies of 217k links, and the page faults of their new
    arrays, cost 5× as much (a drag removes the object's links, the newest, at the end)."""
    gone = 0
    first = len(drop)
    for k in range(len(drop)):
        if drop[k]:
            gone += 1
            first = min(first, k)
    has_tag, has_rays = len(tag) > 0, len(rays) > 0
    gone_r, gone_s = np.empty(gone, np.int64), np.empty(gone, np.int64)
    gone_t, gone_x = np.empty(gone if has_tag else 0, np.int64), np.empty(gone if has_rays else 0, np.int64)
    gone_f, gone_v = np.empty(gone), np.empty(gone)
    a, b = first, 0  # the links before the first removed one stay where they are
    for k in range(first, len(drop)):
        if drop[k]:
            gone_r[b], gone_s[b], gone_f[b], gone_v[b] = receiver[k], source[k], form_factor[k], visibility[k]
            if has_tag:
                gone_t[b] = tag[k]
            if has_rays:
                gone_x[b] = rays[k]
            b += 1
        else:
            receiver[a], source[a], form_factor[a], visibility[a] = (
                receiver[k],
                source[k],
                form_factor[k],
                visibility[k],
            )
            if has_tag:
                tag[a] = tag[k]
            if has_rays:
                rays[a] = rays[k]
            a += 1
    return gone_r, gone_s, gone_t, gone_x, gone_f, gone_v


@numba.njit(parallel=True, cache=True)
def _scatter_gather(receiver, source, weight, b, out, bounds):
    """out[receiver[k]] += weight[k]·b[source[k]] in link order: each row sums its links in the order
    a CSR product of :meth:`Links.matrix` does (same bits). One thread per range of receivers
    [bounds[t], bounds[t + 1]): each reads every link's receiver and sums only its own rows', so
    no two threads write one row and the bits do not depend on the number of ranges."""
    for t in numba.prange(len(bounds) - 1):
        lo, hi = bounds[t], bounds[t + 1]
        for k in range(len(receiver)):
            r = receiver[k]
            if r < lo or r >= hi:
                continue
            j, w = source[k], weight[k]
            for c in range(b.shape[1]):
                out[r, c] += w * b[j, c]


#: links a range of receivers of the gather takes at least (fewer: one range; each range's thread
#: reads every link's receiver, which pays off only over enough links)
LINKS_PER_RANGE = 50_000


def receiver_ranges(receiver: np.ndarray, n: int, ranges: int) -> np.ndarray:
    """(ranges + 1,) int64 bounds cutting the elements 0…n into ``ranges`` ranges that receive about
    as many links each (quantiles of a sample of ``receiver``): the gather's threads' shares."""
    ranges = max(1, min(ranges, len(receiver) // LINKS_PER_RANGE))
    bounds = np.zeros(ranges + 1, np.int64)
    bounds[-1] = n
    if ranges > 1:
        sample = np.sort(receiver[:: max(1, len(receiver) // 4096)])
        bounds[1:-1] = sample[(np.arange(1, ranges) * len(sample)) // ranges]
    return bounds


def _stored(values, n: int, dtype) -> np.ndarray | None:
    """``values`` as a store of ``dtype``, or None where there are none for these ``n`` links."""
    return None if values is None or len(values) != n else np.array(values, dtype).reshape(-1)


class LinkGather:
    """K·B for the K of :meth:`Links.matrix` without building K: one pass over the links per product.
    A drag changes the links each move and its solve takes ~4 products: building the CSR matrix (a
    counting sort and scipy's checks) cost as much as the products. Holds views of the links' ends
    (valid until the links change, as the operator is: copies were 8 bytes a link on the solve's peak
    at RenderPark's element count) and its own F·V."""

    def __init__(self, links: Links, n: int):
        self.shape = (n, n)
        self._receiver, self._source = links.receiver, links.source
        self._weight = links.form_factor * links.visibility
        self._bounds = receiver_ranges(self._receiver, n, numba.get_num_threads())

    def __matmul__(self, b: np.ndarray) -> np.ndarray:
        b = np.asarray(b, np.float64)
        flat = b.ndim == 1
        b = np.ascontiguousarray(b.reshape(len(b), -1))
        out = np.zeros((self.shape[0], b.shape[1]))
        _scatter_gather(self._receiver, self._source, self._weight, b, out, self._bounds)
        return out[:, 0] if flat else out


class Links:
    """The links as six arrays of one length, read as ``receiver``, ``source``, ``form_factor``,
    ``visibility``, ``tag`` and ``rays`` (views of buffers with room to grow: an edit appends and removes in
    place, without the fresh memory a copy per edit would fault in; read them again after an edit).
    ``tag``: an int32 per link that a cache keyed on links may set (corner_cache.CornerGather: the
    link's block of form factors), carried through :meth:`remove` and :meth:`take`, -1 for links
    added since; ``tag_owner`` says which cache set the tags (another reads them as -1). ``rays``: what
    the link's rays gave when it was last recast (:meth:`Visibility.recast`), NO_RAYS (-1) for none.
    Neither is stored until a link has one (a build's links never do: 12 of their 36 bytes a link);
    until then each reads as a fresh array of -1."""

    def __init__(self, receiver=(), source=(), form_factor=(), visibility=(), tag=None, tag_owner=None, rays=None):
        #: the most links refinement may make (radiosity.refine stops with an InputError past it); None: no bound
        self.budget: int | None = None
        self._n = len(receiver)
        # elements and blocks in 32 bits (24 bytes a link, 36 with tags and rays): millions of links
        # at RenderPark's scale
        self._receiver = np.array(receiver, np.int32).reshape(-1)
        self._source = np.array(source, np.int32).reshape(-1)
        self._form_factor = np.array(form_factor, np.float64).reshape(-1)
        self._visibility = np.array(visibility, np.float64).reshape(-1)
        self._tag = _stored(tag, self._n, np.int32)
        self.tag_owner = tag_owner
        self._rays = _stored(rays, self._n, np.int64)

    receiver = property(lambda self: self._receiver[: self._n])
    source = property(lambda self: self._source[: self._n])
    form_factor = property(lambda self: self._form_factor[: self._n])
    visibility = property(lambda self: self._visibility[: self._n])

    @property
    def rays(self) -> np.ndarray:
        return np.full(self._n, -1, np.int64) if self._rays is None else self._rays[: self._n]

    @property
    def tag(self) -> np.ndarray:
        return np.full(self._n, -1, np.int32) if self._tag is None else self._tag[: self._n]

    @tag.setter
    def tag(self, value) -> None:
        if self._tag is None:
            self._tag = np.full(len(self._receiver), -1, np.int32)
        self._tag[: self._n] = value

    def __len__(self) -> int:
        return self._n

    def item_bytes(self) -> int:
        """Bytes a link takes in the store: its arrays' item sizes, tags and rays where stored."""
        stored = [self._receiver, self._source, self._form_factor, self._visibility, self._tag, self._rays]
        return sum(a.itemsize for a in stored if a is not None)

    @property
    def type(self) -> np.ndarray:
        return link_type(self.visibility)

    def extend(self, receiver, source, form_factor, visibility, rays=None) -> None:
        k = len(receiver)
        if self._rays is None and rays is not None and np.any(np.asarray(rays) != -1):
            self._rays = np.full(len(self._receiver), -1, np.int64)
        if self._n + k > len(self._receiver):
            capacity = max(self._n + k, int(len(self._receiver) * 1.5) + 16)
            for name in ("_receiver", "_source", "_form_factor", "_visibility", "_tag", "_rays"):
                old = getattr(self, name)
                if old is None:
                    continue
                grown = np.empty(capacity, old.dtype)
                grown[: self._n] = old[: self._n]
                setattr(self, name, grown)
        end = self._n + k
        self._receiver[self._n : end], self._source[self._n : end] = receiver, source
        self._form_factor[self._n : end], self._visibility[self._n : end] = form_factor, visibility
        if self._tag is not None:
            self._tag[self._n : end] = -1
        if self._rays is not None:
            self._rays[self._n : end] = -1 if rays is None else rays
        self._n = end

    def take(self, keep: np.ndarray) -> Links:
        """The links where ``keep`` (a mask or indices)."""
        return Links(
            self.receiver[keep],
            self.source[keep],
            self.form_factor[keep],
            self.visibility[keep],
            None if self._tag is None else self.tag[keep],
            self.tag_owner,
            None if self._rays is None else self.rays[keep],
        )

    def remove(self, drop: np.ndarray) -> Links:
        """Remove the links where ``drop`` (a mask) and return them (both in link order)."""
        none = np.empty(0, np.int64)
        r, s, t, x, f, v = _compact(
            np.asarray(drop, np.bool_),
            self.receiver,
            self.source,
            none.astype(np.int32) if self._tag is None else self.tag,
            none if self._rays is None else self.rays,
            self.form_factor,
            self.visibility,
        )
        self._n -= len(r)
        return Links(r, s, f, v, t if len(t) else None, self.tag_owner, x if len(x) else None)

    def matrix(self, n: int) -> sp.csr_matrix:
        """K with K[i, j] = Σ F_ij·V_ij over the links from j to i: the gather is H = K·B, stated as a
        sparse matrix (the solver uses :meth:`gather_operator`, which builds nothing). Each row holds
        its links in link order, a pair's duplicates as entries the product sums."""
        order = np.argsort(self.receiver, kind="stable")
        indptr = np.r_[0, np.cumsum(np.bincount(self.receiver, minlength=n))]
        return sp.csr_matrix(((self.form_factor * self.visibility)[order], self.source[order], indptr), shape=(n, n))

    def gather_operator(self, n: int) -> LinkGather:
        """The gather H = K·B as an operator (``@``), equal to :meth:`matrix` with nothing built."""
        return LinkGather(self, n)

    def received_by(self, element: int) -> Links:
        return self.take(self.receiver == element)
