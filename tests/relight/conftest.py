"""The relighting tests' shared fixtures: the built-in real scene photographed once, and one
prepared session per method."""

import dataclasses

import pytest

from illusio.radiosity import HierarchyParams
from illusio.relight import RelightParams, RelightSession, builtin_real_scene

COARSE = RelightParams(hierarchy=HierarchyParams(epsilon=3e-4, clusters=False))


@pytest.fixture(scope="module")
def photograph():
    """The built-in real scene, photographed once for the module."""
    pytest.importorskip("mitsuba", reason="the built-in photograph is rendered by Mitsuba (photo extra)")
    return builtin_real_scene("office", (96, 72), samples=16)


def prepared(ctx, real, method, **changes):
    return RelightSession(real, dataclasses.replace(COARSE, method=method, **changes), ctx)


@pytest.fixture(scope="module")
def sessions(ctx, photograph):
    """One session per method (and RelightParams changes, as keywords), prepared on first use and
    released with the module."""
    made: dict = {}

    def get(method, **changes):
        key = (method, *sorted(changes.items()))
        if key not in made:
            made[key] = prepared(ctx, photograph, method, **changes)
        return made[key]

    yield get
    for s in made.values():
        s.release()
