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
    the entries where ``drop`` (fresh arrays, in order). One pass from the first removed entry and no
    fresh memory for the kept links: ten masked copies of 217k links, and the page faults of their new
    arrays, cost 5× as much (a drag removes the object's links, the newest, at the end)."""
    gone = 0
    first = len(drop)
    for k in range(len(drop)):
        if drop[k]:
            gone += 1
            first = min(first, k)
    gone_r, gone_s, gone_t = np.empty(gone, np.int64), np.empty(gone, np.int64), np.empty(gone, np.int64)
    gone_x, gone_f, gone_v = np.empty(gone, np.int64), np.empty(gone), np.empty(gone)
    a, b = first, 0  # the links before the first removed one stay where they are
    for k in range(first, len(drop)):
        if drop[k]:
            gone_r[b], gone_s[b], gone_t[b], gone_x[b] = receiver[k], source[k], tag[k], rays[k]
            gone_f[b], gone_v[b] = form_factor[k], visibility[k]
            b += 1
        else:
            receiver[a], source[a], tag[a], rays[a] = receiver[k], source[k], tag[k], rays[k]
            form_factor[a], visibility[a] = form_factor[k], visibility[k]
            a += 1
    return gone_r, gone_s, gone_t, gone_x, gone_f, gone_v


@numba.njit(cache=True)
def _scatter_gather(receiver, source, weight, b, out):
    """out[receiver[k]] += weight[k]·b[source[k]] in link order: each row sums its links in the order
    a CSR product of :meth:`Links.matrix` does (same bits)."""
    for k in range(len(receiver)):
        r, j, w = receiver[k], source[k], weight[k]
        for c in range(b.shape[1]):
            out[r, c] += w * b[j, c]


class LinkGather:
    """K·B for the K of :meth:`Links.matrix` without building K: one pass over the links per product.
    A drag changes the links each move and its solve takes ~4 products: building the CSR matrix (a
    counting sort and scipy's checks) cost as much as the products. Holds copies of the links."""

    def __init__(self, links: Links, n: int):
        self.shape = (n, n)
        self._receiver, self._source = links.receiver.copy(), links.source.copy()
        self._weight = links.form_factor * links.visibility

    def __matmul__(self, b: np.ndarray) -> np.ndarray:
        b = np.asarray(b, np.float64)
        flat = b.ndim == 1
        b = np.ascontiguousarray(b.reshape(len(b), -1))
        out = np.zeros((self.shape[0], b.shape[1]))
        _scatter_gather(self._receiver, self._source, self._weight, b, out)
        return out[:, 0] if flat else out


class Links:
    """The links as six arrays of one length, read as ``receiver``, ``source``, ``form_factor``,
    ``visibility``, ``tag`` and ``rays`` (views of buffers with room to grow: an edit appends and removes in
    place, without the fresh memory a copy per edit would fault in; read them again after an edit).
    ``tag``: an int32 per link that a cache keyed on links may set (corner_cache.CornerGather: the
    link's block of form factors), carried through :meth:`remove` and :meth:`take`, -1 for links
    added since; ``tag_owner`` says which cache set the tags (another reads them as -1). ``rays``: what
    the link's rays gave when it was last recast (:meth:`Visibility.recast`), NO_RAYS (-1) for none."""

    def __init__(self, receiver=(), source=(), form_factor=(), visibility=(), tag=None, tag_owner=None, rays=None):
        #: the most links refinement may make (radiosity.refine stops with an InputError past it); None: no bound
        self.budget: int | None = None
        self._n = len(receiver)
        # elements and blocks in 32 bits (36 bytes a link): millions of links at RenderPark's scale
        self._receiver = np.array(receiver, np.int32).reshape(-1)
        self._source = np.array(source, np.int32).reshape(-1)
        self._form_factor = np.array(form_factor, np.float64).reshape(-1)
        self._visibility = np.array(visibility, np.float64).reshape(-1)
        self._tag = np.full(self._n, -1, np.int32) if tag is None or len(tag) != self._n else np.array(tag, np.int32)
        self.tag_owner = tag_owner
        self._rays = (
            np.full(self._n, -1, np.int64) if rays is None or len(rays) != self._n else np.array(rays, np.int64)
        )

    receiver = property(lambda self: self._receiver[: self._n])
    source = property(lambda self: self._source[: self._n])
    form_factor = property(lambda self: self._form_factor[: self._n])
    visibility = property(lambda self: self._visibility[: self._n])
    rays = property(lambda self: self._rays[: self._n])

    @property
    def tag(self) -> np.ndarray:
        return self._tag[: self._n]

    @tag.setter
    def tag(self, value) -> None:
        self._tag[: self._n] = value

    def __len__(self) -> int:
        return self._n

    @property
    def type(self) -> np.ndarray:
        return link_type(self.visibility)

    def extend(self, receiver, source, form_factor, visibility, rays=None) -> None:
        k = len(receiver)
        if self._n + k > len(self._receiver):
            capacity = max(self._n + k, int(len(self._receiver) * 1.5) + 16)
            for name in ("_receiver", "_source", "_form_factor", "_visibility", "_tag", "_rays"):
                old = getattr(self, name)
                grown = np.empty(capacity, old.dtype)
                grown[: self._n] = old[: self._n]
                setattr(self, name, grown)
        end = self._n + k
        self._receiver[self._n : end], self._source[self._n : end] = receiver, source
        self._form_factor[self._n : end], self._visibility[self._n : end] = form_factor, visibility
        self._tag[self._n : end] = -1
        self._rays[self._n : end] = -1 if rays is None else rays
        self._n = end

    def take(self, keep: np.ndarray) -> Links:
        """The links where ``keep`` (a mask or indices)."""
        return Links(
            self.receiver[keep],
            self.source[keep],
            self.form_factor[keep],
            self.visibility[keep],
            self.tag[keep],
            self.tag_owner,
            self.rays[keep],
        )

    def remove(self, drop: np.ndarray) -> Links:
        """Remove the links where ``drop`` (a mask) and return them (both in link order)."""
        r, s, t, x, f, v = _compact(
            np.asarray(drop, np.bool_),
            self.receiver,
            self.source,
            self.tag,
            self.rays,
            self.form_factor,
            self.visibility,
        )
        self._n -= len(r)
        return Links(r, s, f, v, t, self.tag_owner, x)

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
