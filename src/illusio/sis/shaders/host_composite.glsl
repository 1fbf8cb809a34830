#version 430
// Step (6) of Figure 22, before shading: where the host is visible, its albedo becomes the
// stereogram (times the host's tint) and, for a glowing host such as a TV, its emission too.
#include "common/fullscreen.glsl"

#if defined(FRAGMENT_SHADER)
in vec2 uv;
uniform sampler2D g_colour;
uniform sampler2D g_emission;
uniform sampler2D host_pattern;   // alpha 1 where the host is visible
uniform sampler2D stereogram;     // at oversample times the width: sampled with linear filtering
uniform vec3 tint;
uniform float emission;
layout(location = 0) out vec4 colour;
layout(location = 1) out vec4 emitted;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 c = texelFetch(g_colour, p, 0);
    vec4 e = texelFetch(g_emission, p, 0);
    if (texelFetch(host_pattern, p, 0).a > 0.5) {
        vec3 s = texture(stereogram, uv).rgb;
        c.rgb = s * tint;
        e.rgb = s * emission;
    }
    colour = c;
    emitted = e;
}
#endif
