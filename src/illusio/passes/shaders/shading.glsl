#version 430
// Deferred Lambert + normalised Phong shading of the G-buffer by point emitters (emitters.glsl),
// with optional cube shadow maps, ambient term and emission. Reference: passes.reference.shading.
#define MAX_EMITTERS 64
#define SHADOW_MAPS 0
#include "common/fullscreen.glsl"

#if defined(FRAGMENT_SHADER)
#include "emitters.glsl"
uniform sampler2D g_colour;
uniform sampler2D g_normal;
uniform sampler2D g_position;
uniform sampler2D g_emission;
uniform vec3 camera_position;
uniform vec3 ambient;
uniform vec3 background;
uniform float exposure;

in vec2 uv;
out vec4 radiance;

void main() {
    // texelFetch: the output has the G-buffer's size, and llvmpipe fetches faster than it filters
    vec4 pos = texelFetch(g_position, ivec2(gl_FragCoord.xy), 0);
    if (pos.a < 0.5) {
        radiance = vec4(background, 1.0);
        return;
    }
    vec4 c = texelFetch(g_colour, ivec2(gl_FragCoord.xy), 0);
    vec4 nn = texelFetch(g_normal, ivec2(gl_FragCoord.xy), 0);
    vec3 p = pos.xyz;
    vec3 total = direct_light(p, normalize(nn.xyz), normalize(camera_position - p), c.rgb, c.a, nn.a);
    total += ambient * c.rgb + texelFetch(g_emission, ivec2(gl_FragCoord.xy), 0).rgb;
    radiance = vec4(total * exposure, 1.0);
}
#endif
