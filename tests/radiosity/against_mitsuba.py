"""A scene's radiosity image and Mitsuba's path tracing of the same polygons, for the tests that
compare the two (each one's figures stated where it asserts them)."""

from __future__ import annotations

import numpy as np
import pytest


def radiosity_and_mitsuba(ctx, scene, size, supersample: int, samples: int, seed: int):
    """(radiosity radiance (H, W, 3), Mitsuba's, the non-emitter pixels (H, W) bool) from the
    scene's main camera at ``size``, the radiosity at default parameters, box-filtered over
    ``supersample``², Mitsuba at ``samples`` paths a pixel."""
    pytest.importorskip("mitsuba", reason="the photo extra (pip install mitsuba)")
    from illusio.core.renderer import Frame
    from illusio.radiosity import RadiosityParams, RadiosityRenderer
    from illusio.radiosity.mitsuba import render_mitsuba

    view = scene.camera("main")
    renderer = RadiosityRenderer(ctx)
    try:
        renderer.prepare(scene)
        image, emitter = renderer.radiance(Frame(view, size), RadiosityParams(), supersample)
        polygons = renderer.polygons
    finally:
        renderer.release()
    return image, render_mitsuba(polygons, view, size, samples, seed=seed), ~np.asarray(emitter, bool)
