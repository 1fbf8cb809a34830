#version 430
// Deferred Lambert + normalised Phong shading of the G-buffer by point emitters (point lights, and
// area lamps split into samples), with optional cube shadow maps, ambient term and emission.
// Per emitter k at L_k with weight W_k (RGB) and emitter normal m_k (zero: isotropic):
//   E_k = W_k · max(0, n·l) · (m_k = 0 ? 1 : max(0, -m_k·l)) / max(r², r_min²)
//   radiance += V_k · (ρ/π + k_s (s+2)/(2π) max(0, r_k·v)^s) · E_k
// then + ambient·ρ + emission. The NumPy reference is passes.reference.shading.
#define MAX_EMITTERS 64
#include "common/fullscreen.glsl"

#if defined(FRAGMENT_SHADER)
#include "common/shadow_lookup.glsl"
uniform sampler2D g_colour;
uniform sampler2D g_normal;
uniform sampler2D g_position;
uniform sampler2D g_emission;
uniform vec3 camera_position;
uniform vec3 ambient;
uniform vec3 background;
uniform float exposure;
uniform float min_distance;
uniform int emitter_count;
uniform vec3 emitter_position[MAX_EMITTERS];
uniform vec3 emitter_normal[MAX_EMITTERS];
uniform vec3 emitter_weight[MAX_EMITTERS];
uniform int emitter_shadow_row[MAX_EMITTERS];   // -1: no shadow map
uniform vec3 emitter_shadow_origin[MAX_EMITTERS];  // where that light's shadow map was rendered
uniform bool use_shadows;

in vec2 uv;
out vec4 radiance;

const float PI = 3.14159265358979;

void main() {
    // texelFetch: the output has the G-buffer's size, and llvmpipe fetches faster than it filters
    vec4 pos = texelFetch(g_position, ivec2(gl_FragCoord.xy), 0);
    if (pos.a < 0.5) {
        radiance = vec4(background, 1.0);
        return;
    }
    vec4 c = texelFetch(g_colour, ivec2(gl_FragCoord.xy), 0);
    vec4 nn = texelFetch(g_normal, ivec2(gl_FragCoord.xy), 0);
    vec3 albedo = c.rgb;
    float ks = c.a;
    float shininess = nn.a;
    vec3 n = normalize(nn.xyz);
    vec3 p = pos.xyz;
    vec3 v = normalize(camera_position - p);
    vec3 total = vec3(0.0);
    int cached_row = -1;  // emitters of one lamp share its shadow map: look it up once
    float cached_visibility = 1.0;
    for (int k = 0; k < emitter_count; ++k) {
        vec3 l = emitter_position[k] - p;
        float r2 = max(dot(l, l), min_distance * min_distance);
        l = normalize(l);
        float cos_r = max(dot(n, l), 0.0);
        if (cos_r <= 0.0) continue;
        vec3 m = emitter_normal[k];
        float cos_e = dot(m, m) > 0.0 ? max(-dot(m, l), 0.0) : 1.0;
        vec3 irradiance = emitter_weight[k] * cos_r * cos_e / r2;
        float visibility = 1.0;
        int row = emitter_shadow_row[k];
        if (use_shadows && row >= 0) {
            if (row != cached_row) {
                cached_visibility = light_visibility(p, n, emitter_shadow_origin[k], row);
                cached_row = row;
            }
            visibility = cached_visibility;
        }
        vec3 refl = reflect(-l, n);
        float phong = ks * (shininess + 2.0) / (2.0 * PI) * pow(max(dot(refl, v), 0.0), shininess);
        total += visibility * (albedo / PI + phong) * irradiance;
    }
    total += ambient * albedo + texelFetch(g_emission, ivec2(gl_FragCoord.xy), 0).rgb;
    radiance = vec4(total * exposure, 1.0);
}
#endif
