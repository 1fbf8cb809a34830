"""Mutating valid files into bad ones, and the property every reader must keep on them.

A reader, given any bytes, either returns a valid result or raises :class:`IllusioError` — never
another exception and never a hang (each case runs under an alarm). Cases are built by hypothesis
from valid seed files: truncation, byte flips, inserted or deleted bytes, and token swaps that put
huge, negative, NaN, infinite or empty values where numbers were.
"""

from __future__ import annotations

import os
import signal
from contextlib import contextmanager
from pathlib import Path

from hypothesis import HealthCheck, settings
from hypothesis import strategies as st

from illusio.core.errors import IllusioError

# Examples per reader: a few dozen in CI; ILLUSIO_FUZZ_EXAMPLES=N for a longer run.
EXAMPLES = int(os.environ.get("ILLUSIO_FUZZ_EXAMPLES", "40"))
FUZZ = settings(
    max_examples=EXAMPLES,
    deadline=None,
    database=None,
    derandomize=False,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow, HealthCheck.data_too_large],
)
CASE_SECONDS = 20  # a case slower than this is a hang
CORPUS = Path(__file__).parent / "corpus"

NASTY_TOKENS = [
    b"-1",
    b"0",
    b"1",
    b"2147483648",
    b"99999999999",
    b"-99999999",
    b"nan",
    b"inf",
    b"-inf",
    b"1e309",
    b"",
    b"x",
    b"0.5",
    b"3",
    b"\xff",
    b"4294967295",
    b"-0",
    b"1e-320",
]


class Hang(Exception):
    pass


@contextmanager
def time_limit(seconds: int = CASE_SECONDS):
    def on_alarm(signum, frame):
        raise Hang(f"no answer in {seconds} s")

    previous = signal.signal(signal.SIGALRM, on_alarm)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def _truncate(data: bytes, at: int) -> bytes:
    return data[: at % (len(data) + 1)]


def _flip(data: bytes, at: int, value: int) -> bytes:
    if not data:
        return data
    i = at % len(data)
    return data[:i] + bytes([value]) + data[i + 1 :]


def _insert(data: bytes, at: int, chunk: bytes) -> bytes:
    i = at % (len(data) + 1)
    return data[:i] + chunk + data[i:]


def _delete(data: bytes, at: int, length: int) -> bytes:
    i = at % (len(data) + 1)
    return data[:i] + data[i + length :]


def _token(data: bytes, at: int, token: bytes) -> bytes:
    """Replace the whitespace-separated token number ``at`` (text formats)."""
    parts = data.split(b" ")
    if len(parts) < 2:
        parts = data.split(b"\n")
        sep = b"\n"
    else:
        sep = b" "
    i = at % len(parts)
    keep_newline = b"\n" if parts[i].endswith(b"\n") else b""
    parts[i] = token + keep_newline
    return sep.join(parts)


def _swap_lines(data: bytes, a: int, b: int) -> bytes:
    lines = data.split(b"\n")
    i, j = a % len(lines), b % len(lines)
    lines[i], lines[j] = lines[j], lines[i]
    return b"\n".join(lines)


MUTATION = st.one_of(
    st.tuples(st.just("truncate"), st.integers(0, 1 << 20)),
    st.tuples(st.just("flip"), st.integers(0, 1 << 20), st.integers(0, 255)),
    st.tuples(st.just("insert"), st.integers(0, 1 << 20), st.binary(min_size=1, max_size=16)),
    st.tuples(st.just("delete"), st.integers(0, 1 << 20), st.integers(1, 64)),
    st.tuples(st.just("token"), st.integers(0, 1 << 20), st.sampled_from(NASTY_TOKENS)),
    st.tuples(st.just("swap-lines"), st.integers(0, 1 << 10), st.integers(0, 1 << 10)),
    st.tuples(st.just("empty")),
)
MUTATIONS = st.lists(MUTATION, min_size=1, max_size=4)

_APPLY = {
    "truncate": _truncate,
    "flip": _flip,
    "insert": _insert,
    "delete": _delete,
    "token": _token,
    "swap-lines": _swap_lines,
    "empty": lambda data: b"",
}


def mutate(data: bytes, mutations) -> bytes:
    for name, *args in mutations:
        data = _APPLY[name](data, *args)
    return data


def must_refuse_or_succeed(read, path: Path, check) -> object | None:
    """``read(path)`` under a time limit: an IllusioError (returned as None) or a result that
    ``check`` accepts (it asserts). Any other exception propagates and fails the case."""
    with time_limit():
        try:
            result = read(path)
        except IllusioError as exc:
            message = exc.one_line()
            assert message and "Traceback" not in message
            return None
    check(result)
    return result


def must_refuse(read, path: Path) -> str:
    """``read(path)`` raises IllusioError (under a time limit); its one-line message."""
    with time_limit():
        try:
            read(path)
        except IllusioError as exc:
            return exc.one_line()
    raise AssertionError(f"{path.name} was read as if it were good")


def corpus_cases(reader: str) -> list[Path]:
    """The kept cases a fuzzer once found for ``reader`` (tests/fuzz/corpus/READER/*): each is a bad
    file that some version read wrongly or crashed on, and each must be refused."""
    folder = CORPUS / reader
    return sorted(p for p in folder.iterdir() if p.is_file()) if folder.is_dir() else []
