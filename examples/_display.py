"""Shared by the examples: linear float images drawn with matplotlib (sRGB-encoded), side by side."""

import matplotlib.pyplot as plt

from illusio.core.images import linear_to_srgb


def display(*images, titles=()):
    fig, axes = plt.subplots(1, len(images), figsize=(4.2 * len(images), 3.2), squeeze=False)
    for k, (ax, image) in enumerate(zip(axes[0], images)):
        ax.imshow(linear_to_srgb(image.clip(0, 1)), cmap="gray" if image.ndim == 2 else None)
        ax.set_axis_off()
        if k < len(titles):
            ax.set_title(titles[k])
    fig.tight_layout()
    return fig
