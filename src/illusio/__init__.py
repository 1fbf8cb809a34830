"""illusio: perception-driven rendering on one headless OpenGL core.

Quick start::

    from illusio.core import Context, write_image
    from illusio.scene import load_scene
    from illusio.passes import SceneRenderer
    image = SceneRenderer(Context()).render(load_scene("living-room"), size=(960, 600))
    write_image("living-room.png", image)
"""

__version__ = "0.1.0"
