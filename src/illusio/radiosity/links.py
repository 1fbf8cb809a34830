"""Links: light flowing from a source element j to a receiver element i at some level of the two
hierarchies, with the form factor F_ij, the visibility V_ij and its type (VISIBLE, PARTIAL,
INVISIBLE). Stored as flat arrays; the gather of every link at once is one sparse product."""

from __future__ import annotations

from dataclasses import dataclass, field

import numba
import numpy as np
import scipy.sparse as sp

from .visibility import link_type

__all__ = ["Links"]


@numba.njit(cache=True)
def _rows(receiver, n):
    """(indptr (n + 1,), order): the links sorted by receiver, stably, by counting."""
    indptr = np.zeros(n + 1, np.int64)
    for r in receiver:
        indptr[r + 1] += 1
    for i in range(n):
        indptr[i + 1] += indptr[i]
    fill = indptr[:-1].copy()
    order = np.empty(len(receiver), np.int64)
    for k in range(len(receiver)):
        order[fill[receiver[k]]] = k
        fill[receiver[k]] += 1
    return indptr, order


@dataclass(eq=False)
class Links:
    """``tag``: an int64 per link that a cache keyed on links may set (corner_cache.CornerGather: the
    link's block of form factors), carried through :meth:`remove` and :meth:`take`, -1 for links
    added since; ``tag_owner`` says which cache set the tags (another reads them as -1)."""

    receiver: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    source: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    form_factor: np.ndarray = field(default_factory=lambda: np.zeros(0))
    visibility: np.ndarray = field(default_factory=lambda: np.zeros(0))
    tag: np.ndarray | None = None
    tag_owner: object = None

    def __post_init__(self) -> None:
        if self.tag is None or len(self.tag) != len(self.receiver):
            self.tag = np.full(len(self.receiver), -1, np.int64)

    def __len__(self) -> int:
        return len(self.receiver)

    @property
    def type(self) -> np.ndarray:
        return link_type(self.visibility)

    def extend(self, receiver, source, form_factor, visibility) -> None:
        self.receiver = np.r_[self.receiver, np.asarray(receiver, np.int64)]
        self.source = np.r_[self.source, np.asarray(source, np.int64)]
        self.form_factor = np.r_[self.form_factor, form_factor]
        self.visibility = np.r_[self.visibility, visibility]
        self.tag = np.r_[self.tag, np.full(len(self.receiver) - len(self.tag), -1, np.int64)]

    def take(self, keep: np.ndarray) -> "Links":
        """The links where ``keep`` (a mask or indices)."""
        return Links(self.receiver[keep], self.source[keep], self.form_factor[keep], self.visibility[keep],
                     self.tag[keep], self.tag_owner)

    def remove(self, drop: np.ndarray) -> "Links":
        """Remove the links where ``drop`` (a mask) and return them."""
        gone = self.take(drop)
        keep = ~drop
        self.receiver, self.source = self.receiver[keep], self.source[keep]
        self.form_factor, self.visibility = self.form_factor[keep], self.visibility[keep]
        self.tag = self.tag[keep]
        return gone

    def matrix(self, n: int) -> sp.csr_matrix:
        """K with K[i, j] = Σ F_ij·V_ij over the links from j to i: the gather is H = K·B. Built by a
        counting sort on the receivers (the links of a row in link order, a pair's duplicates left as
        entries the product sums): scipy's COO conversion sorted and summed them, 3× the time."""
        indptr, order = _rows(self.receiver, n)
        data = (self.form_factor * self.visibility)[order]
        return sp.csr_matrix((data, self.source[order], indptr), shape=(n, n))

    def received_by(self, element: int) -> "Links":
        return self.take(self.receiver == element)
