"""A toy technique outside illusio's source tree, registered by tests/core/test_adding_a_technique.py:
everything "Adding a technique" (docs/architecture.md) asks of a package, in its own package only."""

from illusio.core.technique import Technique

TOY = Technique(
    name="toy",
    title="A gradient scaled by one knob (a test's toy)",
    renderer="tests.core.toy.renderer:ToyRenderer",
    params="tests.core.toy.params:ToyParams",
    subject="tests.core.toy.renderer:toy_subject",
    source_kind="number",
    default_source="0.5",
    viewer_mode="tests.core.toy.renderer:ToyMode",
    commands=("toy=tests.core.toy.command:toy",),
)
