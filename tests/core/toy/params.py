from dataclasses import dataclass

from illusio.core.params import check_ranges, param


@dataclass(frozen=True)
class ToyParams:
    """brightness: the gradient's scale, no unit."""

    brightness: float = param(0.8, range=(0.0, 1.0), help="the gradient's scale")

    def __post_init__(self):
        check_ranges(self)
