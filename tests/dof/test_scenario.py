"""The scenario language (section 4.1): the paper's script parses in French and in English, with or
without accents; mistakes name their line and column; the player moves objects, shows and hides
them, fires actions, loops and moves the focus smoothly."""

import numpy as np
import pytest

from illusio.dof.scenario import ScenarioError, parse_scenario, shipped_scenario
from illusio.dof.timeline import ScenarioPlayer
from illusio.scene.builtin import shapes
from illusio.scene.camera import Camera, Pose, View
from illusio.scene.scene import Action, Curve, Node, Scene
from illusio.scene.transforms import translate

FRENCH = """temps 0 // définition des paramètres du robot
positionne objet 1 vecteur [30.0,30.0, -30.0] affiche objet 1 nettete objet 1 stoppe objet 1
trajectoire objet 0 courbe 0 vitesse objet 0 réel 100.0 bouge objet 0 affiche objet 0
temps 20000 démarré action 1 objet 0 affiche objet 2 bouge objet 2
temps 30000 nettete objet 2 temps 100000 redémarré
"""
ENGLISH = """TIME 0
position object 1 vector [30, 30, -30] show object 1 focus object 1 stop object 1
trajectory object 0 curve 0 speed object 0 real 100 move object 0 show object 0
time 20000 start action 1 object 0 show object 2 move object 2
time 30000 focus object 2 time 100000 restart
"""


def strip(commands):
    return [(c.kind, c.time, c.object, c.ref, c.value) for c in commands]


def test_the_papers_script_reads_the_same_in_french_english_and_without_accents():
    french = parse_scenario(FRENCH)
    assert strip(french.commands) == strip(parse_scenario(ENGLISH).commands)
    plain = FRENCH.replace("é", "e")
    assert strip(parse_scenario(plain).commands) == strip(french.commands)
    kinds = [c.kind for c in french.commands]
    assert kinds.count("time") == 4 and kinds[-1] == "restart" and french.duration_ms == 100000
    start = next(c for c in french.commands if c.kind == "start_action")
    assert (start.time, start.ref, start.object, start.line, start.column) == (20000, 1, 0, 4, 13)


@pytest.mark.parametrize(
    "text, where, message",
    [
        ("temps 0\nnettete objet\n", "2:", "expected a name or a number"),
        ("temps 0\npositionne objet 1 vecteur [1, 2]\n", "2:33", "expected ','"),
        ("time 5\ntime 3", "2:1", "goes back before 5 ms"),
        ("show object 1\n  flyaway object 2", "2:3", "unknown command 'flyaway'"),
        ("speed object 0 real fast", "1:21", "expected a number"),
        ("temps 0 # comment", "1:9", "unexpected character '#'"),
    ],
)
def test_mistakes_name_their_line_and_column(text, where, message):
    with pytest.raises(ScenarioError) as err:
        parse_scenario(text, "my.txt")
    assert str(err.value).startswith(f"my.txt:{where}") and message in str(err.value), str(err.value)


def scene():
    s = Scene("test")
    for name in ("ship", "robot", "shell"):
        s.add(Node(name, shapes.box((0.2, 0.2, 0.2))))
    s.curves["line"] = Curve("line", [[0, 0, 0], [10, 0, 0]])
    s.curves["up"] = Curve("up", [[0, 0, 0], [0, 4, 0]])
    s.actions["fire"] = Action("fire", "shell", "up")
    s.cameras["main"] = View(Pose((0, 0, 10), (0, 0, 0)), Camera(50, 0.1, 100))
    return s


def test_unknown_objects_curves_and_actions_are_named_with_their_place():
    for text, message in (
        ("temps 0\naffiche objet 7", "my.txt:2:1: no object 7"),
        ("trajectoire objet 0 courbe wiggle", "my.txt:1:1: no curve 'wiggle'"),
        ("demarre action 3 objet ship", "my.txt:1:1: no action 3"),
    ):
        with pytest.raises(ScenarioError, match=message):
            ScenarioPlayer(parse_scenario(text, "my.txt"), scene())


def test_the_player_moves_shows_fires_and_loops():
    script = """time 0 trajectory object ship curve line speed object ship real 2 move object ship
    hide object shell
    time 2000 stop object ship
    time 3000 move object ship start action fire object robot show object shell move object shell
    speed object shell real 1
    time 6000 restart"""
    s = scene()
    s.nodes[1].transform = translate((5, 1, 0))
    player = ScenarioPlayer(parse_scenario(script), s)
    assert player.state(1.0)["ship"].position[0] == pytest.approx(2.0)  # 2 units/s along the line
    assert player.state(2.5)["ship"].position[0] == pytest.approx(4.0)  # stopped at 2 s
    at = player.state(4.0)
    assert at["ship"].position[0] == pytest.approx(6.0)
    np.testing.assert_allclose(at["shell"].position, (5, 2, 0), atol=1e-6)  # fired from the robot, 1 unit up
    assert at["shell"].visible and not player.state(1.0)["shell"].visible
    np.testing.assert_allclose(player.state(7.0)["ship"].position, player.state(1.0)["ship"].position)  # looped
    player.apply(s, 4.0)
    np.testing.assert_allclose(s.node("shell").transform[:3, 3], (5, 2, 0), atol=1e-6)


def test_the_focus_moves_smoothly_to_the_next_object():
    s = scene()
    s.nodes[0].transform = translate((0, 0, 6))  # 4 m from the camera
    s.nodes[1].transform = translate((0, 0, -10))  # 20 m
    player = ScenarioPlayer(parse_scenario("time 0 focus object ship time 1000 focus object robot"), s, transition=0.5)
    view = s.camera()
    assert player.focus_distance(view, 0.5) == pytest.approx(4.0, rel=1e-6)
    assert player.focus_distance(view, 1.0) == pytest.approx(4.0, rel=1e-6)  # the change starts where it was
    assert player.focus_distance(view, 1.5) == pytest.approx(20.0, rel=1e-6)
    between = [player.focus_distance(view, 1.0 + k * 0.05) for k in range(11)]
    assert all(a < b for a, b in zip(between, between[1:]))
    assert ScenarioPlayer(parse_scenario("time 0 show object ship"), s).focus_distance(view, 1.0) is None


def test_the_shipped_scenario_plays_on_the_futuristic_scene():
    from illusio.dof.scenario import load_scenario
    from illusio.scene import load_scene

    futuristic = load_scene("futuristic")
    player = ScenarioPlayer(load_scenario(shipped_scenario("futuristic")), futuristic)
    assert player.loop == 8.0
    view = futuristic.camera()
    assert player.state(2.0)["ship"].travelled == pytest.approx(18.0)  # 9 units/s along the flight curve
    assert np.linalg.norm(player.state(2.0)["ship"].position - player.state(0.0)["ship"].position) > 10
    assert not player.state(2.0)["projectile"].visible and player.state(3.0)["projectile"].visible
    assert player.focus_distance(view, 3.4) == pytest.approx(
        float(-(view.view_matrix().astype(float) @ np.append(player.state(3.4)["robot"].position, 1))[2]), rel=0.05
    )


def test_an_incomplete_line_is_reported_at_its_own_line():
    """A statement ends with its line: 'temps' alone on line 3 is line 3's mistake, not line 4's
    (statements used to run across line ends); several statements may still share a line."""
    with pytest.raises(ScenarioError) as err:
        parse_scenario("temps 0\naffiche objet 1\ntemps\naffiche objet 2\n", "my.txt")
    assert str(err.value).startswith("my.txt:3:") and "the end of the line" in str(err.value), str(err.value)
    with pytest.raises(ScenarioError) as err:
        parse_scenario("temps 0 affiche objet 1\npositionne objet 1\nvecteur [1, 2, 3]\n", "my.txt")
    assert str(err.value).startswith("my.txt:2:"), str(err.value)
    assert len(parse_scenario("temps 0 affiche objet 1 nettete objet 1\n").commands) == 3
