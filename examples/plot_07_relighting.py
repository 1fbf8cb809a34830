"""
Relighting a photograph
=======================

The office's "photograph" is path-traced by Mitsuba (the ``photo`` extra), then relit as Loscos
(1999, chapter 4) does: hierarchical radiosity initialised from the photograph's pixels, the
photographed shadows refined into the mesh and removed from the textures, and the lamps changed.
Here two of the four ceiling lamps are switched off, then every real lamp is switched off and a
virtual lamp hung in the middle of the room.
"""

from _display import display

from illusio.relight import RelightSession, builtin_real_scene

photo = builtin_real_scene("office", size=(200, 150), samples=16)
session = RelightSession(photo)
print("lamps:", ", ".join(session.lamp_names))

# %%
# The photograph, two lamps switched off, and a virtual lamp with every real lamp off.
off = session.image({"lamp-2": 0.0, "lamp-3": 0.0})
session.image({name: 0.0 for name in session.lamp_names})
lit = session.add_lamp((0.0, 2.2, -1.0), size=0.6, exitance=(160.0, 140.0, 110.0))
figure = display(photo.photograph, off, lit, titles=("photograph", "lamp-2 and lamp-3 off", "virtual lamp only"))
