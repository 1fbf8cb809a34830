"""Every knob of stereoscopic depth of field (Piranda & de Sorbier), with units and ranges. The CLI,
the gallery and the viewer read their defaults from here."""

from __future__ import annotations

from dataclasses import dataclass

from ..core.params import check_ranges, param
from ..passes.settings import RenderSettings
from ..passes.settings import COMPOSITES

__all__ = ["DofParams", "METHODS", "STEREO_OUTPUTS"]

#: accumulation: the reference (the eye moved over the lens, renders averaged); gather: per-pixel
#: convolution with CoC-sized disks, depth aware (the paper's "convolution" method, section 2.2.2);
#: mipmap: each pixel at the mipmap level of its circle (2.2.3); planes: the paper's method (3.1–3.2);
#: planes-improved: the planes' slabs as layers, each blurred by its middle's circle and laid over the
#: ones behind by its own coverage (no banding from the far plane's circle, no foreground leaking)
METHODS = ("accumulation", "gather", "mipmap", "planes", "planes-improved")
#: none: one (cyclopean) view; left / right: one eye; left-right: both, side by side in the texture
#: (the CLI writes them as two files); or a composite of the pair
STEREO_OUTPUTS = ("none", "left", "right", "left-right") + COMPOSITES


@dataclass(frozen=True)
class DofParams:
    """method: one of METHODS. focus_distance: d_f, metres along the view axis to the plane in focus.
    aperture_mm: A, the lens (pupil) diameter; the blur of a point at depth d is
    A·|1/d − 1/d_f|·H / (2 tan(fov/2)) pixels (dof.lens). focal_length_mm: 0 keeps the camera's field
    of view; else the field of view of that lens on a 24 mm high frame. samples: lens positions the
    accumulation method averages. planes_behind, planes_front: m and n of the planes method, spread by
    ``distribution`` between the focal plane and the camera's far and near planes. max_coc: the largest circle of confusion drawn, pixels (the gather
    kernel's diameter). stereo: the output (STEREO_OUTPUTS). eye_separation: metres between the eyes.
    screen_distance: metres to the zero-parallax plane; 0 puts it at the focus distance. seed: the
    rotation of the lens sampling pattern. policy: how the focus is chosen each frame (dof.focus.POLICIES);
    accommodation: seconds the focus takes to follow a policy's choice (exponential, in dioptres).
    settings: how each view is lit."""

    method: str = param("gather", choices=METHODS)
    focus_distance: float = param(2.0, range=(0.05, 1000.0), unit="m", log=True, label="focus distance d_f")
    aperture_mm: float = param(50.0, range=(0.0, 500.0), unit="mm", label="aperture A", flag="aperture",
                               help="lens diameter")
    focal_length_mm: float = param(0.0, range=(0.0, 2000.0), unit="mm", label="focal length (0: the camera's)",
                                   flag="focal-length", help="on a 24 mm frame; 0 keeps the camera's field of view")
    samples: int = param(32, range=(1, 1024), step=1, help="lens positions of the accumulation method")
    planes_behind: int = param(6, range=(1, 64), step=1, label="planes behind (m)")
    planes_front: int = param(4, range=(0, 64), step=1, label="planes in front (n)")
    distribution: str = param("exponential", choices=("exponential", "linear"), help="how the planes are spread")
    max_coc: float = param(24.0, range=(1.0, 64.0), unit="px", label="largest circle of confusion")
    stereo: str = param("none", choices=STEREO_OUTPUTS)
    eye_separation: float = param(0.065, range=(0.0, 1.0), unit="m")
    screen_distance: float = param(0.0, range=(0.0, 1000.0), unit="m", help="zero parallax; 0: at the focus")
    seed: int = param(0, range=(0, 2**31 - 1), step=1)
    policy: str = param("none", choices=("none", "gaze", "largest", "speed", "nearest-exhibit"),
                        help="how each frame's focus is chosen (section 4.2); none: focus distance")
    accommodation: float = param(0.3, range=(0.0, 5.0), unit="s", help="time constant of the focus following a policy")
    settings: RenderSettings = param(default_factory=lambda: RenderSettings(shadows=False))

    __post_init__ = check_ranges

    @property
    def aperture_m(self) -> float:
        return self.aperture_mm / 1000.0
