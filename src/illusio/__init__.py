"""illusio: perception-driven rendering on one headless OpenGL core.

Quick start::

    from illusio.core import Context, Frame, write_image
    from illusio.scene import load_scene
    from illusio.passes import SceneRenderer
    renderer = SceneRenderer(Context())          # every technique's renderer works the same way
    renderer.prepare(load_scene("living-room"))
    write_image("living-room.png", renderer.render(Frame(size=(960, 600))))
"""

__version__ = "0.1.0"
