#version 430
// The hidden scene drawn straight into the stereogram's D in [0, 1] (0 = near): surfaces map linearly
// from the front to the back of the scene's bounding sphere onto [0, object_range]; the target is
// cleared to 1, the far background.
#include "passes/shaders/surface.glsl"

#if defined(FRAGMENT_SHADER)
uniform float front;          // metres along the view axis
uniform float back;
uniform float object_range;
out float depth;

void main() {
    depth = clamp((view_depth - front) / (back - front), 0.0, 1.0) * object_range;
}
#endif
