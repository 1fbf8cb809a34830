"""Every knob of stereoscopic depth of field (Piranda & de Sorbier), with units and ranges. The CLI,
the gallery and the viewer read their defaults from here."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from ..core.params import check_ranges, param
from ..passes.settings import COMPOSITES, RenderSettings
from ..scene.camera import Screen

__all__ = ["DofParams", "METHODS", "STEREO_OUTPUTS"]

#: accumulation: the reference (the eye moved over the lens, renders averaged); gather: per-pixel
#: convolution with CoC-sized disks, depth aware (the paper's "convolution" method, section 2.2.2),
#: estimated from ``gather_taps`` points of each disk (0: every pixel of the kernel);
#: mipmap: each pixel at the mipmap level of its circle (2.2.3); planes: the paper's method (3.1–3.2).
#: (A layered "planes-improved" variant was dropped in issue 32: slower than the planes and, at strong
#: blur, farther from the accumulation than the unblurred image; seams at its slab boundaries.)
METHODS = ("accumulation", "gather", "mipmap", "planes")
#: none: one (cyclopean) view; left / right: one eye; left-right: both, side by side in the texture
#: (the CLI writes them as two files); or a composite of the pair
STEREO_OUTPUTS = ("none", "left", "right", "left-right") + COMPOSITES


@dataclass(frozen=True)
class DofParams:
    """method: one of METHODS. focus_distance: d_f, metres along the view axis to the plane in focus.
    aperture_mm: A, the lens (pupil) diameter; the blur of a point at depth d is
    A·abs(1/d − 1/d_f)·H / (2 tan(fov/2)) pixels (dof.lens). focal_length_mm: 0 keeps the camera's field
    of view; else the field of view of that lens on a 24 mm high frame. samples: lens positions the
    accumulation method averages. planes_behind, planes_front: m and n of the planes method, spread by
    ``distribution`` between the focal plane and the camera's far and near planes. max_coc: the largest circle of
    confusion drawn, pixels (the gather
    kernel's diameter). gather_taps: points per pixel of the sampled gather (0: the exact
    gather over every pixel of the kernel). stereo: the output (STEREO_OUTPUTS). eye_separation: metres between the
    eyes.
    screen_distance: metres to the zero-parallax plane, the screen
    the eyes converge on while they accommodate at the focus (the paper's premise: that conflict is
    what the blur softens); default the physical screen's viewing distance (core Screen, 1 m);
    0 puts it at the focus distance. seed: the
    rotation of the lens sampling pattern. policy: how the focus is chosen each frame (dof.focus.POLICIES);
    accommodation: seconds the focus takes to follow a policy's choice (exponential, in dioptres).
    settings: how each view is lit."""

    PANEL: ClassVar[str] = "Depth of field"  # its options' panel in --help

    method: str = param("gather", choices=METHODS, group="method")
    focus_distance: float = param(2.0, range=(0.05, 1000.0), unit="m", log=True, label="focus distance d_f")
    aperture_mm: float = param(
        50.0, range=(0.0, 500.0), unit="mm", label="aperture A", flag="aperture", help="lens diameter"
    )
    focal_length_mm: float = param(
        0.0,
        range=(0.0, 2000.0),
        unit="mm",
        label="focal length (0: the camera's)",
        flag="focal-length",
        help="on a 24 mm frame; 0 keeps the camera's field of view",
    )
    samples: int = param(32, range=(1, 1024), step=1, help="lens positions of the accumulation method", group="method")
    planes_behind: int = param(6, range=(1, 64), step=1, label="planes behind (m)")
    planes_front: int = param(4, range=(0, 64), step=1, label="planes in front (n)")
    distribution: str = param("exponential", choices=("exponential", "linear"), help="how the planes are spread")
    plane_scale: float = param(
        0.0,
        range=(0.0, 1000.0),
        unit="m",
        label="z0",
        help="scale of the planes' law e^(−x/z0)/z0 (Piranda & de Sorbier 3.1); 0: the focus distance",
    )
    gather_taps: int = param(
        32,
        range=(0, 128),
        step=1,
        label="gather points",
        help="points per pixel of the gather's disk (each read at the mipmap level of its "
        "share); 0: every pixel of the kernel's square, exact and slow",
        group="method",
    )
    max_coc: float = param(24.0, range=(1.0, 64.0), unit="px", label="largest circle of confusion")
    stereo: str = param("none", choices=STEREO_OUTPUTS, group="output")
    eye_separation: float = param(0.065, range=(0.0, 1.0), unit="m", group="output")
    screen_distance: float = param(
        Screen().viewing_distance_cm / 100,
        range=(0.0, 1000.0),
        unit="m",
        help="zero parallax: the screen the eyes converge on, whatever the focus "
        "(the viewer's distance of the physical screen model, 1:1 with the scene); "
        "0: at the focus",
        group="output",
    )
    seed: int = param(0, range=(0, 2**31 - 1), step=1, group="advanced")
    policy: str = param(
        "none",
        choices=("none", "gaze", "largest", "speed", "nearest-exhibit"),
        help="how each frame's focus is chosen (section 4.2); none: focus distance",
    )
    accommodation: float = param(0.3, range=(0.0, 5.0), unit="s", help="time constant of the focus following a policy")
    settings: RenderSettings = param(default_factory=lambda: RenderSettings(shadows=False), group="advanced")

    #: fields that leave the default view's image unchanged, and why (tests/core/test_technique_contract.py)
    NOT_VISIBLE_BY_DEFAULT: ClassVar[dict[str, str]] = {
        "samples": "only the accumulation method",
        "planes_behind": "only the planes method",
        "planes_front": "only the planes method",
        "distribution": "only the planes method",
        "plane_scale": "only the planes method",
        "eye_separation": "only a stereo output",
        "screen_distance": "only a stereo output",
        "seed": "only the accumulation method's lens positions",
        "accommodation": "only with a focus policy, from one frame to the next",
        "settings.shadow_tile_size": "shadows are off by default",
        "settings.forward": "the same image by design; speed only",
    }

    __post_init__ = check_ranges

    @property
    def aperture_m(self) -> float:
        return self.aperture_mm / 1000.0
