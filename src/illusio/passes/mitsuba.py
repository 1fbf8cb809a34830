"""What every Mitsuba 3 export shares: loading the package (an optional dependency, its
``scalar_rgb`` variant: no system package needed), RGB values and a perspective sensor matching one
of our views. Used by the path-traced references of ibr and the ground truth of radiosity."""

from __future__ import annotations

import importlib.util
import threading

from ..core.errors import InputError
from ..scene.camera import View

__all__ = ["mitsuba_available", "load_mitsuba", "rgb", "sensor", "render"]


def mitsuba_available() -> bool:
    return importlib.util.find_spec("mitsuba") is not None


def load_mitsuba():
    """The mitsuba module set to ``scalar_rgb``; InputError with the install hint when missing."""
    try:
        import mitsuba as mi
    except ImportError:
        raise InputError("path tracing needs the mitsuba package: pip install mitsuba") from None
    mi.set_variant("scalar_rgb")
    # errors only: its warnings are for its own command line ("Received interrupt signal, winding
    # down.." in red on Ctrl-C, which the command line answers in its own one line)
    mi.set_log_level(mi.LogLevel.Error)
    return mi


def load_scene(mi, doc: dict):
    """``mi.load_dict(doc)`` without Mitsuba's pass that merges identical objects: with it, the order
    of the merged shapes varied between processes, and with it which random numbers each path took —
    the same seed gave another image about one run in six (a render of the relit office's edits,
    hashed over twelve runs: 2 differed; 12 of 12 alike without the pass)."""
    return mi.load_dict(doc, optimize=False)


def render(mi, scene, **kwargs):
    """``mi.render(scene, **kwargs)``, interruptible: Mitsuba holds Ctrl-C for itself while it renders
    ("winding down" its blocks, which at thousands of paths a pixel took minutes) and Python's
    handlers run only when the call returns, so the render runs in a worker thread while this one
    waits in short joins, where Ctrl-C and SIGTERM raise at once. The worker's exception, if any, is
    raised here. A render left running by an interrupt ends with the process (the command line
    leaves with os._exit once Mitsuba is loaded: its threads crash the interpreter's own exit)."""
    out: dict = {}

    def work():
        try:
            out["image"] = mi.render(scene, **kwargs)
        except BaseException as exc:  # handed to the waiting thread
            out["error"] = exc

    thread = threading.Thread(target=work, name="mitsuba-render", daemon=True)
    thread.start()
    while thread.is_alive():
        thread.join(0.1)
    if "error" in out:
        raise out["error"]
    return out["image"]


def rgb(values) -> dict:
    return {"type": "rgb", "value": [float(v) for v in values]}


def sensor(mi, view: View, size: tuple[int, int], samples: int, seed: int) -> dict:
    """A perspective sensor of ``view`` at ``size`` (box pixel filter: each pixel its own footprint)."""
    if any(abs(s) > 0 for s in view.camera.shift):
        raise InputError("Mitsuba renders take centred cameras (no lens shift)")
    w, h = size
    return {
        "type": "perspective",
        "fov": float(view.camera.fov_y),
        "fov_axis": "y",
        "near_clip": float(view.camera.near),
        "far_clip": float(view.camera.far),
        "to_world": mi.ScalarTransform4f.look_at(
            origin=[float(v) for v in view.pose.position],
            target=[float(v) for v in view.pose.target],
            up=[float(v) for v in view.pose.up],
        ),
        "film": {"type": "hdrfilm", "width": int(w), "height": int(h), "rfilter": {"type": "box"}},
        "sampler": {"type": "independent", "sample_count": int(samples), "seed": int(seed)},
    }
