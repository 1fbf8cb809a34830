"""Playing a scenario on a scene: where every object is, whether it shows, and where the focus is at
any time. The state at a time is computed from the start (deterministic, whatever the frame rate).

Objects are the scene's nodes (a number is the node's index, a name its name), curves the scene's
curves and actions its actions (by index in their order, or by name). Speeds are scene units per
second; motion follows a curve at constant speed along its length and stops at its end. A change of
focus is a smooth transition of ``transition`` seconds, blended in dioptres (1/distance), as an
eye accommodates.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..scene.camera import View
from ..scene.scene import Scene
from .scenario import Command, Scenario, ScenarioError

__all__ = ["ScenarioPlayer", "ObjectState", "TRANSITION"]

#: seconds a change of focus takes
TRANSITION = 0.75


@dataclass
class ObjectState:
    position: np.ndarray
    visible: bool
    speed: float = 0.0
    moving: bool = False
    curve: str | None = None
    offset: np.ndarray = field(default_factory=lambda: np.zeros(3))
    travelled: float = 0.0


class _Path:
    """A curve by arc length."""

    def __init__(self, curve, samples: int = 1024):
        self.points = curve.evaluate(np.linspace(0.0, 1.0, samples))
        self.lengths = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(self.points, axis=0), axis=1))])

    @property
    def length(self) -> float:
        return float(self.lengths[-1])

    def at(self, s: float) -> np.ndarray:
        s = float(np.clip(s, 0.0, self.length))
        return np.array([np.interp(s, self.lengths, self.points[:, k]) for k in range(3)])


class ScenarioPlayer:
    """``state(t)``: every object's state at ``t`` seconds; ``apply(scene, t)`` moves and shows the
    scene's nodes accordingly; ``focus_distance(view, t)``: metres along the view axis to the focus,
    or None before the first focus command. The scenario is checked against the scene here: an
    unknown object, curve or action is a ScenarioError with its line and column."""

    def __init__(self, scenario: Scenario, scene: Scene, transition: float = TRANSITION):
        self.scenario = scenario
        self.scene = scene
        self.transition = transition
        self._nodes = {n.name: i for i, n in enumerate(scene.nodes)}
        self._curves = list(scene.curves)
        self._actions = list(scene.actions)
        self._paths = {name: _Path(c) for name, c in scene.curves.items()}
        self._commands = [self._bind(c) for c in scenario.commands]
        restarts = [c.time for c in scenario.commands if c.kind == "restart"]
        self.loop = restarts[0] / 1000.0 if restarts else None
        self.focus_changes = [(c.time / 1000.0, c.object) for c in self._commands if c.kind == "focus"]

    # -- checks ----------------------------------------------------------------------------------
    def _where(self, c: Command) -> str:
        return f"{self.scenario.name}:{c.line}:{c.column}"

    def _lookup(self, c: Command, ref, names: list[str], what: str) -> str:
        if isinstance(ref, int):
            if 0 <= ref < len(names):
                return names[ref]
        elif ref in names:
            return ref
        listed = ", ".join(f"{i} {n}" for i, n in enumerate(names[:12])) + (" ..." if len(names) > 12 else "")
        raise ScenarioError(
            f"{self._where(c)}: no {what} {ref!r} in scene {self.scene.name!r} ({what}s: {listed or 'none'})"
        )

    def _bind(self, c: Command) -> Command:
        """The command with its references as names (checked)."""
        from dataclasses import replace

        obj = self._lookup(c, c.object, [n.name for n in self.scene.nodes], "object") if c.object is not None else None
        ref = c.ref
        if c.kind == "trajectory":
            ref = self._lookup(c, c.ref, self._curves, "curve")
        elif c.kind == "start_action":
            ref = self._lookup(c, c.ref, self._actions, "action")
        if c.kind == "speed" and c.value < 0:
            raise ScenarioError(f"{self._where(c)}: a speed must be ≥ 0, got {c.value:g}")
        return replace(c, object=obj, ref=ref)

    # -- state -----------------------------------------------------------------------------------
    def _initial(self) -> dict[str, ObjectState]:
        return {
            n.name: ObjectState(np.asarray(n.transform[:3, 3], np.float64).copy(), n.visible) for n in self.scene.nodes
        }

    def _advance(self, states: dict[str, ObjectState], dt: float) -> None:
        if dt <= 0:
            return
        for st in states.values():
            if st.moving and st.curve is not None and st.speed > 0:
                path = self._paths[st.curve]
                st.travelled = min(st.travelled + st.speed * dt, path.length)
                st.position = path.at(st.travelled) + st.offset

    def _run(self, states: dict[str, ObjectState], c: Command) -> None:
        st = states.get(c.object) if c.object is not None else None
        if c.kind == "position":
            st.position, st.curve, st.offset = np.asarray(c.value, np.float64), None, np.zeros(3)
        elif c.kind in ("show", "hide"):
            st.visible = c.kind == "show"
        elif c.kind in ("move", "stop"):
            st.moving = c.kind == "move"
        elif c.kind == "speed":
            st.speed = float(c.value)
        elif c.kind == "trajectory":
            st.curve, st.offset, st.travelled = c.ref, np.zeros(3), 0.0
            st.position = self._paths[c.ref].at(0.0)
        elif c.kind == "start_action":
            action = self.scene.actions[c.ref]
            thrown = states[action.object]
            path = self._paths[action.curve]
            thrown.curve, thrown.travelled = action.curve, 0.0
            thrown.offset = st.position - path.at(0.0)
            thrown.position = st.position.copy()

    def state(self, t: float) -> dict[str, ObjectState]:
        """Every object's state at ``t`` seconds (looping at a restart)."""
        if self.loop is not None and self.loop > 0:
            t = t % self.loop
        states = self._initial()
        now = 0.0
        for c in self._commands:
            at = c.time / 1000.0
            if at > t:
                break
            self._advance(states, at - now)
            now = at
            self._run(states, c)
        self._advance(states, t - now)
        return states

    def apply(self, scene: Scene, t: float) -> None:
        """Move and show ``scene``'s nodes (the scene the player was made for, or a copy) as at ``t``."""
        for name, st in self.state(t).items():
            node = scene.node(name)
            node.transform = node.transform.copy()
            node.transform[:3, 3] = st.position
            node.visible = st.visible

    def focus_distance(self, view: View, t: float) -> float | None:
        """Metres along ``view``'s axis to the focus at ``t``, or None before any focus command."""
        if self.loop is not None and self.loop > 0:
            t = t % self.loop
        changes = [(at, name) for at, name in self.focus_changes if at <= t]
        if not changes:
            return None
        states = self.state(t)
        current_at, current = changes[-1]
        near = view.camera.near

        def distance(name: str) -> float:
            node = self.scene.node(name)
            lo, hi = node.mesh.bounds
            centre = (
                node.transform[:3, :3].astype(np.float64) @ ((np.asarray(lo, np.float64) + hi) / 2)
                + states[name].position
            )
            eye = view.view_matrix().astype(np.float64) @ np.append(centre, 1.0)
            return max(float(-eye[2]), near)

        target = distance(current)
        if len(changes) == 1 or self.transition <= 0:
            return target
        x = np.clip((t - current_at) / self.transition, 0.0, 1.0)
        w = x * x * (3 - 2 * x)  # smoothstep
        previous = distance(changes[-2][1])
        return 1.0 / ((1 - w) / previous + w / target)
