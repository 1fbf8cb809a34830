"""The built-in scenes, built from procedural shapes and textures (no data files).

Units are metres; y up; each scene has a ``main`` camera. Names: cornell-box, living-room, office, museum,
turntable. Tags techniques rely on: ``host`` (a surface that can show an autostereogram: the TV
screen, a wall), ``screen``, ``lamp``, ``exhibit``, ``subject``.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ...core.errors import InputError
from ..camera import Camera, Pose, View
from ..mesh import Mesh
from ..scene import Action, AreaLight, Curve, Material, Node, PointLight, Scene
from ..transforms import compose, rotate_euler, scale, translate
from . import shapes, textures

__all__ = ["SCENES", "builtin_scene", "turntable"]


def _place(
    scene: Scene,
    name: str,
    mesh: Mesh,
    at=(0, 0, 0),
    rotate=(0, 0, 0),
    size=1.0,
    material: Material | None = None,
    tags=(),
) -> Node:
    m = compose(translate(at), rotate_euler(rotate), scale(size))
    return scene.add(Node(name, mesh, m, material or Material(), tuple(tags)))


def _legs(scene: Scene, prefix: str, centre, width: float, depth: float, height: float, material: Material, thick=0.05):
    cx, cy, cz = centre
    for k, (sx, sz) in enumerate(((-1, -1), (1, -1), (1, 1), (-1, 1))):
        x = cx + sx * (width / 2 - thick)
        z = cz + sz * (depth / 2 - thick)
        _place(
            scene, f"{prefix}-leg-{k}", shapes.box((thick, height, thick)), (x, cy + height / 2, z), material=material
        )


def living_room() -> Scene:
    s = Scene("living-room", ambient=(0.05, 0.045, 0.04), background=(0.0, 0.0, 0.0))
    wood = Material(texture=textures.planks(), colour=(1, 1, 1), specular=0.08, shininess=40)
    wall = Material(texture=textures.wallpaper(), colour=(1, 1, 1))
    dark_wood = Material(colour=(0.16, 0.09, 0.05), specular=0.1, shininess=30)
    _place(s, "floor", shapes.plane((6.0, 5.0), uv_scale=1.6), (0, 0, 0), material=wood)
    _place(
        s,
        "back-wall",
        shapes.plane((6.0, 2.7), uv_scale=1.0),
        (0, 1.35, -2.5),
        rotate=(90, 0, 0),
        material=wall,
        tags=("wall", "host"),
    )
    _place(
        s,
        "left-wall",
        shapes.plane((5.0, 2.7), uv_scale=1.0),
        (-3.0, 1.35, 0),
        rotate=(90, 90, 0),
        material=wall,
        tags=("wall",),
    )
    _place(
        s,
        "right-wall",
        shapes.plane((5.0, 2.7), uv_scale=1.0),
        (3.0, 1.35, 0),
        rotate=(90, -90, 0),
        material=wall,
        tags=("wall",),
    )
    _place(
        s,
        "ceiling",
        shapes.plane((6.0, 5.0)),
        (0, 2.7, 0),
        rotate=(180, 0, 0),
        material=Material(colour=(0.85, 0.84, 0.8)),
    )
    _place(s, "skirting", shapes.box((6.0, 0.1, 0.02)), (0, 0.05, -2.49), material=Material(colour=(0.9, 0.88, 0.84)))
    # TV cabinet, TV set on a stand, screen as its own node
    _place(s, "cabinet", shapes.box((1.8, 0.5, 0.45), uv_scale=0.6), (0, 0.25, -2.2), material=dark_wood)
    _place(
        s,
        "cabinet-top",
        shapes.box((1.84, 0.03, 0.48), uv_scale=0.6),
        (0, 0.515, -2.2),
        material=Material(texture=textures.planks(256, 3, 5), colour=(0.7, 0.6, 0.5), specular=0.15),
    )
    black = Material(colour=(0.02, 0.02, 0.02), specular=0.3, shininess=60)
    _place(s, "tv-foot", shapes.box((0.45, 0.02, 0.25)), (0, 0.54, -2.22), material=black)
    _place(s, "tv-neck", shapes.box((0.06, 0.14, 0.04)), (0, 0.62, -2.26), material=black)
    _place(s, "tv-body", shapes.box((1.32, 0.78, 0.06)), (0, 1.08, -2.24), material=black, tags=("tv",))
    _place(
        s,
        "tv-screen",
        shapes.plane((1.24, 0.70)),
        (0, 1.08, -2.2095),
        rotate=(90, 0, 0),
        material=Material(colour=(0.05, 0.06, 0.07), specular=0.5, shininess=120, emission=(0.02, 0.025, 0.03)),
        tags=("tv", "screen", "host"),
    )
    # sofa facing the TV
    fabric = Material(texture=textures.fabric(), colour=(1, 1, 1))
    _place(s, "sofa-base", shapes.box((2.1, 0.4, 0.9)), (0, 0.2, 1.5), material=fabric)
    _place(s, "sofa-back", shapes.superquadric((0.2, 0.2), (1.05, 0.35, 0.12)), (0, 0.72, 1.88), material=fabric)
    for side in (-1, 1):
        _place(
            s,
            f"sofa-arm-{'lr'[side > 0]}",
            shapes.superquadric((0.25, 0.25), (0.11, 0.3, 0.45)),
            (side * 1.0, 0.45, 1.5),
            material=fabric,
        )
    for k, x in enumerate((-0.47, 0.47)):
        _place(
            s,
            f"sofa-cushion-{k}",
            shapes.superquadric((0.3, 0.3), (0.44, 0.09, 0.38)),
            (x, 0.48, 1.42),
            material=fabric,
        )
    # coffee table and rug
    _place(
        s,
        "rug",
        shapes.box((2.4, 0.01, 1.6)),
        (0, 0.005, 0.3),
        material=Material(texture=textures.fabric(128, (0.45, 0.08, 0.06), 9), colour=(1, 1, 1)),
    )
    glass = Material(colour=(0.35, 0.38, 0.4), specular=0.6, shininess=150)
    _place(s, "coffee-table-top", shapes.box((1.0, 0.04, 0.55)), (0, 0.42, 0.3), material=glass)
    _legs(s, "coffee-table", (0, 0, 0.3), 1.0, 0.55, 0.40, Material(colour=(0.1, 0.1, 0.1), specular=0.4), 0.04)
    # floor lamp with a glowing shade and a warm light inside it
    metal = Material(colour=(0.6, 0.55, 0.45), specular=0.5, shininess=80)
    lamp_xz = (-2.2, -1.7)
    _place(s, "lamp-base", shapes.cylinder(0.18, 0.03), (lamp_xz[0], 0, lamp_xz[1]), material=metal)
    _place(s, "lamp-pole", shapes.cylinder(0.015, 1.4, 16), (lamp_xz[0], 0.03, lamp_xz[1]), material=metal)
    _place(
        s,
        "lamp-shade",
        shapes.cone(0.26, 0.32, 0.16),
        (lamp_xz[0], 1.3, lamp_xz[1]),
        material=Material(colour=(0.9, 0.8, 0.6), emission=(0.9, 0.7, 0.4)),
        tags=("lamp",),
    )
    s.lights.append(PointLight((lamp_xz[0], 1.45, lamp_xz[1]), (1.0, 0.78, 0.5), 7.0, name="floor-lamp"))
    _place(
        s,
        "ceiling-light",
        shapes.box((0.5, 0.03, 0.5)),
        (0.3, 2.685, 0.0),
        material=Material(emission=(1.0, 0.97, 0.92)),
        tags=("lamp",),
    )
    s.lights.append(
        AreaLight((0.3, 2.665, 0.0), (0.5, 0, 0), (0, 0, 0.5), (1.0, 0.97, 0.92), 22.0, samples=2, name="ceiling")
    )
    s.cameras["main"] = View(Pose((2.5, 1.75, 2.4), (-0.4, 0.75, -1.4)), Camera(62.0, 0.05, 30.0))
    s.cameras["tv"] = View(Pose((0.0, 1.08, 0.4), (0.0, 1.08, -2.2)), Camera(40.0, 0.05, 30.0))
    return s


def office() -> Scene:
    s = Scene("office", ambient=(0.07, 0.07, 0.075), background=(0.0, 0.0, 0.0))
    carpet = Material(
        texture=np.repeat(0.25 + 0.25 * textures.value_noise(128, 16, 4, 3)[..., None], 3, axis=2)
        * np.array([0.9, 0.95, 1.0], np.float32),
        colour=(1, 1, 1),
    )
    wall = Material(colour=(0.78, 0.78, 0.74))
    _place(s, "floor", shapes.plane((8.0, 6.0), uv_scale=1.0), material=carpet)
    _place(
        s,
        "ceiling",
        shapes.plane((8.0, 6.0)),
        (0, 3.0, 0),
        rotate=(180, 0, 0),
        material=Material(colour=(0.85, 0.85, 0.85)),
    )
    _place(
        s,
        "back-wall",
        shapes.plane((8.0, 3.0)),
        (0, 1.5, -3.0),
        rotate=(90, 0, 0),
        material=wall,
        tags=("wall", "host"),
    )
    _place(s, "left-wall", shapes.plane((6.0, 3.0)), (-4.0, 1.5, 0), rotate=(90, 90, 0), material=wall, tags=("wall",))
    _place(s, "right-wall", shapes.plane((6.0, 3.0)), (4.0, 1.5, 0), rotate=(90, -90, 0), material=wall, tags=("wall",))
    _place(s, "front-wall", shapes.plane((8.0, 3.0)), (0, 1.5, 3.0), rotate=(90, 180, 0), material=wall, tags=("wall",))
    _place(
        s,
        "whiteboard",
        shapes.box((2.2, 1.1, 0.03)),
        (0.5, 1.5, -2.98),
        material=Material(colour=(0.95, 0.95, 0.95), specular=0.3, shininess=60),
    )
    _place(
        s,
        "door",
        shapes.box((0.95, 2.1, 0.04)),
        (-4.0 + 0.02, 1.05, 1.6),
        rotate=(0, 90, 0),
        material=Material(colour=(0.45, 0.3, 0.18)),
    )
    top = Material(colour=(0.75, 0.62, 0.45), specular=0.15, shininess=40)
    steel = Material(colour=(0.3, 0.3, 0.32), specular=0.4, shininess=60)
    for k, (x, z) in enumerate(((-1.7, -0.6), (1.7, -0.3))):
        _place(s, f"table-{k}-top", shapes.box((1.6, 0.04, 0.8)), (x, 0.74, z), material=top, tags=("table",))
        _legs(s, f"table-{k}", (x, 0, z), 1.6, 0.8, 0.72, steel)
        _place(
            s,
            f"monitor-{k}",
            shapes.box((0.6, 0.36, 0.03)),
            (x, 1.0, z - 0.2),
            material=Material(colour=(0.03, 0.03, 0.03)),
        )
        _place(
            s,
            f"monitor-{k}-screen",
            shapes.plane((0.56, 0.32)),
            (x, 1.0, z - 0.184),
            rotate=(90, 0, 0),
            material=Material(colour=(0.1, 0.1, 0.1), emission=(0.12, 0.2, 0.35)),
            tags=("screen",),
        )
        _place(s, f"monitor-{k}-stand", shapes.box((0.05, 0.16, 0.05)), (x, 0.84, z - 0.22), material=steel)
        _place(
            s,
            f"keyboard-{k}",
            shapes.box((0.45, 0.02, 0.15)),
            (x, 0.77, z + 0.12),
            material=Material(colour=(0.12, 0.12, 0.12)),
        )
    # a chair at the first table
    seat = Material(colour=(0.15, 0.2, 0.4))
    cx, cz = -1.6, 0.35
    _place(s, "chair-seat", shapes.box((0.46, 0.06, 0.46)), (cx, 0.46, cz), material=seat)
    _place(s, "chair-back", shapes.box((0.46, 0.5, 0.05)), (cx, 0.78, cz + 0.22), rotate=(-8, 0, 0), material=seat)
    _legs(s, "chair", (cx, 0, cz), 0.46, 0.46, 0.43, steel, 0.03)
    # four rectangular ceiling lamps: glowing panels with an area light each
    for k, (x, z) in enumerate(((-2.0, -1.8), (2.0, -1.8), (-2.0, 0.4), (2.0, 0.4))):
        _place(
            s,
            f"lamp-{k}",
            shapes.box((1.2, 0.04, 0.6)),
            (x, 2.97, z),
            material=Material(colour=(1, 1, 1), emission=(1.0, 1.0, 0.97)),
            tags=("lamp",),
        )
        s.lights.append(
            AreaLight((x, 2.945, z), (1.2, 0, 0), (0, 0, 0.6), (1.0, 0.98, 0.94), 6.0, samples=2, name=f"lamp-{k}")
        )
    s.cameras["main"] = View(Pose((3.5, 1.7, 2.7), (-0.6, 1.15, -0.9)), Camera(65.0, 0.05, 30.0))
    s.cameras["top"] = View(Pose((0.0, 2.9, 2.9), (0.0, 0.5, -0.5)), Camera(70.0, 0.05, 30.0))
    return s


def museum() -> Scene:
    s = Scene("museum", ambient=(0.06, 0.055, 0.05), background=(0.0, 0.0, 0.0))
    floor = Material(texture=textures.tiles(), colour=(1, 1, 1), specular=0.2, shininess=50)
    wall = Material(colour=(0.62, 0.5, 0.42))
    _place(s, "floor", shapes.plane((14.0, 10.0), uv_scale=2.0), material=floor)
    _place(
        s,
        "ceiling",
        shapes.plane((14.0, 10.0)),
        (0, 5.0, 0),
        rotate=(180, 0, 0),
        material=Material(colour=(0.8, 0.8, 0.78)),
    )
    _place(
        s,
        "back-wall",
        shapes.plane((14.0, 5.0)),
        (0, 2.5, -5.0),
        rotate=(90, 0, 0),
        material=wall,
        tags=("wall", "host"),
    )
    _place(s, "left-wall", shapes.plane((10.0, 5.0)), (-7.0, 2.5, 0), rotate=(90, 90, 0), material=wall, tags=("wall",))
    _place(
        s, "right-wall", shapes.plane((10.0, 5.0)), (7.0, 2.5, 0), rotate=(90, -90, 0), material=wall, tags=("wall",)
    )
    stone = Material(colour=(0.85, 0.83, 0.78), specular=0.1)
    for k, x in enumerate((-5.5, 5.5)):
        for j, z in enumerate((-3.5, 0.0, 3.5)):
            _place(s, f"column-{k}-{j}", shapes.cylinder(0.3, 5.0, 32), (x, 0, z), material=stone)
    # paintings on the back wall
    for k, x in enumerate((-3.6, 0.0, 3.6)):
        art = np.stack([textures.value_noise(128, 3, 20 + 3 * k + c, 4) for c in range(3)], axis=-1)
        _place(
            s,
            f"frame-{k}",
            shapes.box((1.8, 1.3, 0.06)),
            (x, 2.4, -4.97),
            material=Material(colour=(0.35, 0.25, 0.08), specular=0.3),
        )
        _place(
            s,
            f"painting-{k}",
            shapes.plane((1.6, 1.1)),
            (x, 2.4, -4.935),
            rotate=(90, 0, 0),
            material=Material(texture=art**1.5, colour=(1, 1, 1)),
        )
    plinth = Material(colour=(0.92, 0.92, 0.9), specular=0.05)
    exhibits = [
        ("torus-knot", shapes.torus_knot(), 0.42, Material(colour=(0.8, 0.6, 0.2), specular=0.5, shininess=90)),
        ("blob", shapes.blob(), 0.38, Material(colour=(0.45, 0.28, 0.16), specular=0.35, shininess=40)),
        ("gear", shapes.gear(), 0.42, Material(colour=(0.55, 0.57, 0.6), specular=0.6, shininess=100)),
        (
            "superquadric",
            shapes.superquadric((0.3, 0.6)),
            0.38,
            Material(colour=(0.15, 0.35, 0.55), specular=0.4, shininess=60),
        ),
        ("torus", shapes.torus(), 0.33, Material(colour=(0.6, 0.1, 0.1), specular=0.4, shininess=70)),
    ]
    spots = [(-3.4, -2.2), (0.0, -2.4), (3.4, -2.2), (-1.7, 1.0), (1.7, 1.0)]
    for (name, mesh, size, mat), (x, z) in zip(exhibits, spots):
        _place(s, f"plinth-{name}", shapes.box((0.7, 1.0, 0.7)), (x, 0.5, z), material=plinth)
        lo, hi = mesh.bounds
        rot = (90, 0, 0) if name == "gear" else (0, 25, 0)
        lift = (hi - lo)[2 if name == "gear" else 1] / 2 * size
        _place(
            s,
            f"exhibit-{name}",
            mesh,
            (x, 1.0 + lift + 0.01, z),
            rotate=rot,
            size=size,
            material=mat,
            tags=("exhibit",),
        )
        s.lights.append(PointLight((x, 3.4, z + 0.6), (1.0, 0.95, 0.85), 5.0, name=f"spot-{name}"))
    s.lights.append(
        AreaLight((0, 4.98, 0), (4.0, 0, 0), (0, 0, 2.0), (0.95, 0.97, 1.0), 0.9, samples=2, name="skylight")
    )
    s.cameras["main"] = View(Pose((0.3, 2.4, 6.6), (0.0, 1.1, -1.2)), Camera(58.0, 0.05, 40.0))
    return s


def futuristic() -> Scene:
    """Figure 11's scene: a ship (object 0) flying a loop over a city of towers, a robot (object 1)
    standing guard and a projectile (object 2) the robot fires at the ship (action "fire" along the
    curve "shot", from wherever the robot stands)."""
    s = Scene("futuristic", ambient=(0.05, 0.055, 0.07), background=(0.02, 0.02, 0.05))
    _place(
        s,
        "ship",
        shapes.superquadric((0.3, 0.6), (2.2, 0.5, 0.9)),
        (0, 6, 0),
        material=Material(colour=(0.75, 0.78, 0.82), specular=0.6, shininess=80),
        tags=("actor",),
    )
    # the robot near the camera (12 m) and the ship's loop beyond it (to 28 m): the focus jumps by
    # metres when it fires (it stood at 27 m, beside the ship's far side, and the jump was 1 m)
    _place(
        s,
        "robot",
        shapes.superquadric((0.5, 0.8), (0.7, 1.6, 0.7)),
        (4.0, 1.6, 8.0),
        material=Material(colour=(0.7, 0.35, 0.1), specular=0.4, shininess=50),
        tags=("actor",),
    )
    _place(
        s,
        "projectile",
        shapes.sphere(0.18, 24, 12),
        (4.0, 3.4, 8.0),
        material=Material(colour=(1.0, 0.3, 0.1), emission=(2.0, 0.5, 0.1)),
        tags=("actor",),
    )
    _place(
        s,
        "ground",
        shapes.plane((60.0, 60.0), uv_scale=6.0),
        material=Material(texture=textures.tiles(), colour=(0.6, 0.65, 0.75), specular=0.2, shininess=40),
    )
    rng = np.random.default_rng(11)
    k = 0
    while k < 14:  # towers around the square, none between the camera and the robot
        angle, radius = rng.uniform(0, 2 * np.pi), rng.uniform(10, 24)
        x, z = radius * np.cos(angle), radius * np.sin(angle)
        if (abs(x) < 10 and z > -14) or (abs(x - 4) < 4 and z > 0):
            continue
        height = rng.uniform(3, 12)
        _place(
            s,
            f"tower-{k}",
            shapes.box((2.0, height, 2.0)),
            (x, height / 2, z),
            material=Material(colour=tuple(rng.uniform(0.3, 0.6, 3)), specular=0.3, shininess=30),
        )
        k += 1
    s.curves["flight"] = Curve(
        "flight",
        [[-12, 6, 4], [-12, 8, -12], [12, 8, -12], [12, 6, 4], [12, 4, 16], [-12, 5, 16], [-12, 6, 4]],
        "bezier",
    )
    s.curves["shot"] = Curve("shot", [[0, 1.8, 0], [-3, 5, -6], [-7, 7, -14]], "polyline")  # away from the camera
    s.actions["fire"] = Action("fire", "projectile", "shot")
    s.lights.append(PointLight((8, 18, 10), (1.0, 0.95, 0.9), 900.0, name="sun"))
    s.lights.append(PointLight((-10, 8, -6), (0.5, 0.6, 1.0), 120.0, shadows=False, name="sky"))
    s.cameras["main"] = View(Pose((-2.0, 4.0, 20.0), (2.0, 4.0, -4.0)), Camera(55.0, 0.1, 200.0))
    return s


def turntable(
    mesh: Mesh | None = None, colour=(0.75, 0.72, 0.68), azimuth: float = 30.0, elevation: float = 22.0
) -> Scene:
    """One shape (default: the torus knot) normalised to 1 m, resting on a checkered floor."""
    from ..mesh import as_mesh

    mesh = (shapes.torus_knot() if mesh is None else as_mesh(mesh)).normalised(1.0)
    s = Scene("turntable", ambient=(0.08, 0.08, 0.09), background=(0.05, 0.05, 0.06))
    _place(
        s,
        "floor",
        shapes.plane((8.0, 8.0), uv_scale=1.0),
        material=Material(texture=textures.checker(256, 2, (0.6, 0.6, 0.58), (0.35, 0.35, 0.34)), colour=(1, 1, 1)),
    )
    _place(s, "subject", mesh, material=Material(colour=colour, specular=0.25, shininess=50), tags=("subject",))
    s.lights.append(
        AreaLight((1.5, 3.0, 1.5), (0.8, 0, 0), (0, 0, 0.8), (1.0, 0.97, 0.92), 35.0, samples=2, name="key")
    )
    s.lights.append(PointLight((-2.5, 1.8, 1.0), (0.75, 0.85, 1.0), 2.5, shadows=False, name="fill"))
    height = float(mesh.bounds[1][1])
    target = (0.0, height / 2, 0.0)
    s.cameras["main"] = View(Pose.orbit(target, 2.6, azimuth, elevation), Camera(40.0, 0.05, 30.0))
    s.cameras["front"] = View(Pose.orbit(target, 2.6, 0.0, 5.0), Camera(40.0, 0.05, 30.0))
    return s


# The Cornell box as published by the Cornell Program of Computer Graphics (geometry in mm, x to the
# left of the camera, z into the box), with the RGB reflectances and lamp radiance commonly derived
# from its measured spectra (those of Mitsuba's built-in Cornell box).
_CORNELL_WHITE, _CORNELL_RED, _CORNELL_GREEN = (
    (0.885809, 0.698859, 0.666422),
    (0.570068, 0.0430135, 0.0443706),
    (0.105421, 0.37798, 0.076425),
)
_CORNELL_LAMP_RADIANCE = (18.387, 13.9873, 6.75357)
_CORNELL_QUADS = {
    "floor": ([[552.8, 0, 0], [0, 0, 0], [0, 0, 559.2], [549.6, 0, 559.2]], _CORNELL_WHITE),
    "ceiling": ([[556.0, 548.8, 0], [556.0, 548.8, 559.2], [0, 548.8, 559.2], [0, 548.8, 0]], _CORNELL_WHITE),
    "back-wall": ([[549.6, 0, 559.2], [0, 0, 559.2], [0, 548.8, 559.2], [556.0, 548.8, 559.2]], _CORNELL_WHITE),
    "right-wall": ([[0, 0, 559.2], [0, 0, 0], [0, 548.8, 0], [0, 548.8, 559.2]], _CORNELL_GREEN),
    "left-wall": ([[552.8, 0, 0], [549.6, 0, 559.2], [556.0, 548.8, 559.2], [556.0, 548.8, 0]], _CORNELL_RED),
}
_CORNELL_BLOCKS = {
    "short-block": ([130.0, 65.0], [82.0, 225.0], [240.0, 272.0], [290.0, 114.0], 165.0),
    "tall-block": ([423.0, 247.0], [265.0, 296.0], [314.0, 456.0], [472.0, 406.0], 330.0),
}


def _quads_mesh(quads: list, name: str, outward_from=None, inward_to=None) -> Mesh:
    """Quads (each 4 corners) as a triangle mesh, each turned to face away from ``outward_from`` or
    towards ``inward_to`` (the published corner orders are not all counter-clockwise)."""
    verts, faces = [], []
    for q in quads:
        q = np.asarray(q, np.float64)
        n = np.cross(q[2] - q[0], q[3] - q[1])
        centre = q.mean(axis=0)
        towards = (centre - outward_from) if outward_from is not None else (inward_to - centre)
        if n @ towards < 0:
            q = q[::-1]
        b = len(verts)
        verts += list(q)
        faces += [(b, b + 1, b + 2), (b, b + 2, b + 3)]
    return Mesh(np.array(verts), np.array(faces), name=name)


def cornell_box() -> Scene:
    s = Scene("cornell-box", ambient=(0.0, 0.0, 0.0), background=(0.0, 0.0, 0.0))
    mm = 0.001
    inside = np.array([278.0, 274.4, 279.6]) * mm
    for name, (quad, colour) in _CORNELL_QUADS.items():
        s.add(
            Node(
                name,
                _quads_mesh([np.asarray(quad) * mm], name, inward_to=inside),
                material=Material(colour=colour),
                tags=("wall",),
            )
        )
    for name, (a, b, c, d, height) in _CORNELL_BLOCKS.items():
        bottom = [np.array([x, 0.0, z]) * mm for x, z in (a, b, c, d)]
        top = [p + np.array([0, height * mm, 0]) for p in bottom]
        quads = [top] + [[bottom[k], bottom[(k + 1) % 4], top[(k + 1) % 4], top[k]] for k in range(4)]
        s.add(
            Node(
                name,
                _quads_mesh(quads, name, outward_from=np.mean(bottom + top, axis=0)),
                material=Material(colour=_CORNELL_WHITE),
            )
        )
    radiance = np.asarray(_CORNELL_LAMP_RADIANCE)
    # the published lamp lies in the ceiling's plane; 0.5 mm below it, so the two never fight for a pixel
    s.lights.append(
        AreaLight(
            (0.278, 0.5483, 0.2795),
            (0.13, 0, 0),
            (0, 0, 0.105),
            tuple(radiance / radiance.max()),
            float(radiance.max()),
            samples=4,
            name="lamp",
        )
    )
    fov = float(np.degrees(2 * np.arctan(12.5 / 35.0)))
    s.cameras["main"] = View(Pose((0.278, 0.273, -0.8), (0.278, 0.273, 0.0)), Camera(fov, 0.05, 10.0))
    return s


SCENES: dict[str, Callable[[], Scene]] = {
    "cornell-box": cornell_box,
    "living-room": living_room,
    "office": office,
    "museum": museum,
    "futuristic": futuristic,
    "turntable": turntable,
}


def builtin_scene(name: str) -> Scene:
    if name not in SCENES:
        raise InputError(f"no built-in scene {name!r}; choose one of {', '.join(SCENES)}")
    return SCENES[name]()
