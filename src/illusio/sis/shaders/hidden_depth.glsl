#version 430
// G-buffer depth of the hidden scene -> the stereogram's D in [0, 1] (0 = near): hits map linearly
// from the front to the back of the scene's bounding sphere onto [0, object_range]; the background
// is the far plane, D = 1.
#include "common/fullscreen.glsl"

#if defined(FRAGMENT_SHADER)
uniform sampler2D g_depth;
uniform sampler2D g_object_id;
uniform float front;          // metres along the view axis
uniform float back;
uniform float object_range;
out float depth;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    if (texelFetch(g_object_id, p, 0).r < 0.5) {
        depth = 1.0;
        return;
    }
    float z = texelFetch(g_depth, p, 0).r;
    depth = clamp((z - front) / (back - front), 0.0, 1.0) * object_range;
}
#endif
