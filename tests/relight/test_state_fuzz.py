"""Fuzzing the saved relighting session reader (``relight prepare``'s .npz: arrays and a JSON record)."""

from __future__ import annotations

import io

import numpy as np
import pytest
from hypothesis import given, seed
from hypothesis import strategies as st

from illusio.relight.session import RelightSession
from tests.conftest import SESSION_SEED
from tests.fuzz.harness import FUZZ, MUTATIONS, must_refuse, must_refuse_or_succeed, mutate


@pytest.fixture(scope="module")
def saved(sessions, tmp_path_factory):
    """A prepared session's file, and its arrays."""
    path = tmp_path_factory.mktemp("session") / "office.npz"
    sessions("baseline").save(path)
    with np.load(path, allow_pickle=False) as archive:
        arrays = {k: archive[k] for k in archive.files}
    return path.read_bytes(), arrays


def archive_bytes(arrays) -> bytes:
    out = io.BytesIO()
    np.savez(out, **arrays)
    return out.getvalue()


def readable(ctx):
    def check(session):
        try:
            image = session.image({})
            assert image.shape == session.real.photograph.shape and np.isfinite(image).all()
        finally:
            session.release()

    return lambda path: RelightSession.load(path, ctx), check


def with_bad_array(arrays, name, bad):
    """``arrays`` with ``name`` replaced by a bad one (or left out)."""
    a = arrays[name]
    replaced = {
        "nan": np.full(a.shape, np.nan) if a.dtype.kind == "f" else np.full(a.shape, -1, np.int64),
        "empty": a[:0],
        "scalar": np.float64(3.0),
        "string": np.array("x"),
        "wrong-shape": a.reshape(-1)[: max(a.size // 2, 1)],
        "huge-index": np.full_like(a, 2**30) if a.dtype.kind in "iu" else a * 1e30,
        "missing": None,
    }[bad]
    changed = {k: v for k, v in arrays.items() if k != name}
    if replaced is not None:
        changed[name] = replaced
    return changed


BAD_ARRAYS = st.sampled_from(["nan", "empty", "scalar", "string", "wrong-shape", "huge-index", "missing"])


@seed(SESSION_SEED)
@FUZZ
@given(
    where=st.sampled_from(["bytes", "record", "array"]),
    mutations=MUTATIONS,
    bad=BAD_ARRAYS,
    pick=st.integers(0, 1 << 16),
)
def test_mutated_sessions_are_read_or_refused(ctx, saved, where, mutations, bad, pick, tmp_path_factory):
    """Bytes of the file, the JSON record inside it, or one of its arrays made wrong: each ends in
    an InputError or a session whose image is finite and the photograph's size."""
    data, arrays = saved
    if where == "bytes":
        data = mutate(data, mutations)
    elif where == "record":
        text = mutate(str(arrays["record"]).encode(), mutations).decode("utf-8", "replace")
        data = archive_bytes({**arrays, "record": np.array(text)})
    else:
        names = sorted(k for k in arrays if k != "record")
        data = archive_bytes(with_bad_array(arrays, names[pick % len(names)], bad))
    path = tmp_path_factory.mktemp("mutated") / "office.npz"
    path.write_bytes(data)
    read, check = readable(ctx)
    must_refuse_or_succeed(read, path, check)


# what the fuzzer found: NaN corners crashed the ray caster (a segmentation fault); the others ended
# in IndexError, ValueError or TypeError after loading, or a wrong image
KEPT = [
    ("hierarchy.corners", "nan"),
    ("hierarchy.child", "nan"),
    ("hierarchy.parent", "nan"),
    ("links.receiver", "empty"),
    ("session.has_d", "nan"),
    ("basis_mesh.faces", "huge-index"),
    ("hierarchy.polygon", "huge-index"),
    ("solution.group", "huge-index"),
    ("session.corner_d", "empty"),
    ("basis", "wrong-shape"),
]


@pytest.mark.parametrize("name, bad", KEPT)
def test_kept_session_cases_are_refused(ctx, saved, name, bad, tmp_path):
    path = tmp_path / "office.npz"
    path.write_bytes(archive_bytes(with_bad_array(saved[1], name, bad)))
    assert must_refuse(lambda p: RelightSession.load(p, ctx), path)


def test_a_session_of_another_format_is_refused_with_the_command_that_prepares_it(ctx, saved, tmp_path):
    """The format is versioned, not patched: a file of the previous format (or a later one) is
    refused in one line naming both formats and the command that prepares the scene again."""
    import json

    from illusio.core.errors import InputError
    from illusio.relight.state import FORMAT

    _, arrays = saved
    record = json.loads(str(arrays["record"]))
    assert record["format"] == FORMAT == "illusio-relight-session/2"
    record["format"] = "illusio-relight-session/1"
    path = tmp_path / "old.npz"
    path.write_bytes(archive_bytes({**arrays, "record": np.array(json.dumps(record))}))
    with pytest.raises(InputError, match=r"session/1.*session/2.*illusio relight prepare"):
        RelightSession.load(path, ctx)
