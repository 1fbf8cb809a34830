#version 430
// Object-space line segments drawn as screen-space quads of a given width in pixels (core profile
// has no wide lines), depth-tested against the surface so that hidden parts vanish.
#include "common/camera.glsl"

uniform mat4 model_matrix;
uniform vec2 viewport;       // pixels
uniform float width;         // pixels
uniform vec3 colour;

#if defined(VERTEX_SHADER)
in vec3 in_position;
void main() {
    gl_Position = projection_matrix * view_matrix * model_matrix * vec4(in_position, 1.0);
}
#endif

#if defined(GEOMETRY_SHADER)
layout(lines) in;
layout(triangle_strip, max_vertices = 4) out;
void main() {
    vec4 a = gl_in[0].gl_Position;
    vec4 b = gl_in[1].gl_Position;
    if (a.w <= 0.0 || b.w <= 0.0) return;  // behind the eye
    vec2 pa = a.xy / a.w * viewport * 0.5;
    vec2 pb = b.xy / b.w * viewport * 0.5;
    vec2 d = pb - pa;
    float len = length(d);
    vec2 dir = len > 1e-6 ? d / len : vec2(1.0, 0.0);
    vec2 side = vec2(-dir.y, dir.x) * 0.5 * width;
    vec2 along = dir * 0.5 * width;  // round-ish joins: extend each end by half the width
    vec2 offsets[4] = vec2[](-along + side, -along - side, along + side, along - side);
    for (int i = 0; i < 4; ++i) {
        vec4 p = i < 2 ? a : b;
        gl_Position = vec4(p.xy + offsets[i] / viewport * 2.0 * p.w, p.z, p.w);
        EmitVertex();
    }
    EndPrimitive();
}
#endif

#if defined(FRAGMENT_SHADER)
out vec4 out_colour;
void main() {
    out_colour = vec4(colour, 1.0);
}
#endif
