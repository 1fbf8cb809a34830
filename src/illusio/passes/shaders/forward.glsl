#version 430
// Forward shading: the scene's surfaces lit in the pass that draws them (emitters.glsl), no G-buffer.
// The same equations as the deferred shading.glsl (tested equal); cheaper where writing and reading
// the G-buffer dominates (a CPU rasteriser at high resolution). Optional screen-space material: on
// the nodes flagged, albedo and emission come from a screen-space texture (a stereogram shown on a
// surface, Dehos et al. Figure 22 step 6). Outputs: 0 radiance; 1 object id (if attached).
// SCREEN_MATERIAL 1: the nodes drawn take their colour from screen_albedo (the variant for the flagged
// nodes; variants rather than branches, see surface.glsl); passes/forward.py picks one per node.
#define MAX_EMITTERS 64
#define SHADOW_MAPS 0
#define SCREEN_MATERIAL 0
#include "surface.glsl"

#if defined(FRAGMENT_SHADER)
#include "emitters.glsl"
uniform vec3 ambient;
uniform float exposure;
uniform sampler2D screen_albedo;   // sampled at the pixel's screen position (any resolution)
uniform vec2 screen_size;          // pixels of this pass's target
uniform vec3 screen_tint;
uniform float screen_emission;

layout(location = 0) out vec4 radiance;
layout(location = 1) out float out_id;

void main() {
    vec3 colour = surface_albedo();
    vec3 emitted = emission;
#if SCREEN_MATERIAL
    vec3 s = texture(screen_albedo, gl_FragCoord.xy / screen_size).rgb;
    colour = s * screen_tint;
    emitted = s * screen_emission;
#endif
    vec3 p = world_position;
    vec3 total = direct_light(p, surface_normal(), normalize(camera_position - p), colour, specular, shininess);
    radiance = vec4((total + ambient * colour + emitted) * exposure, 1.0);
    out_id = object_id;
}
#endif
