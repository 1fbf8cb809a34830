// Direct light from point emitters (point lights, and area lamps split into samples), shared by the
// deferred shading pass and the forward pass. Per emitter k at L_k with weight W_k (RGB) and emitter
// normal m_k (zero: isotropic):
//   E_k = W_k · max(0, n·l) · (m_k = 0 ? 1 : max(0, -m_k·l)) / max(r², r_min²)
//   radiance += V_k · (ρ/π + k_s (s+2)/(2π) max(0, r_k·v)^s) · E_k
// The NumPy reference is passes.reference.shading.
// SHADOW_MAPS (defined by the including program): 1 compiles the shadow lookups in. A separate
// variant, not a uniform switch: on llvmpipe the lookup code costs even when skipped (~25 ms at
// 1080p with no emitter at all).
// GLOSSY 0 compiles the Phong lobe out, for matte surfaces (k_s = 0), for the same reason as
// surface.glsl's TEXTURED: a branch on k_s does not spare the pow on llvmpipe.
#define GLOSSY 1
#if SHADOW_MAPS
#include "common/shadow_lookup.glsl"
#endif
uniform float min_distance;
uniform int emitter_count;
uniform vec3 emitter_position[MAX_EMITTERS];
uniform vec3 emitter_normal[MAX_EMITTERS];
uniform vec3 emitter_weight[MAX_EMITTERS];
uniform int emitter_shadow_row[MAX_EMITTERS];   // -1: no shadow map
uniform vec3 emitter_shadow_origin[MAX_EMITTERS];  // where that light's shadow map was rendered

const float PI = 3.14159265358979;

// p: world position, n: unit normal facing the viewer, v: unit direction to the eye
vec3 direct_light(vec3 p, vec3 n, vec3 v, vec3 albedo, float ks, float shininess) {
    vec3 total = vec3(0.0);
    vec3 diffuse = albedo / PI;
    float phong_norm = ks * (shininess + 2.0) / (2.0 * PI);
    int cached_row = -1;  // emitters of one lamp share its shadow map: look it up once
    float cached_visibility = 1.0;
    for (int k = 0; k < emitter_count; ++k) {
        vec3 l = emitter_position[k] - p;
        float d2 = dot(l, l);
        l *= inversesqrt(d2);
        float cos_r = dot(n, l);
        if (cos_r <= 0.0) continue;
        vec3 m = emitter_normal[k];
        float cos_e = dot(m, m) > 0.0 ? max(-dot(m, l), 0.0) : 1.0;
        vec3 irradiance = emitter_weight[k] * (cos_r * cos_e / max(d2, min_distance * min_distance));
        float visibility = 1.0;
#if SHADOW_MAPS
        int row = emitter_shadow_row[k];
        if (row >= 0) {
            if (row != cached_row) {
                cached_visibility = light_visibility(p, n, emitter_shadow_origin[k], row);
                cached_row = row;
            }
            visibility = cached_visibility;
        }
#endif
        vec3 brdf = diffuse;
#if GLOSSY
        if (ks > 0.0) brdf += phong_norm * pow(max(dot(reflect(-l, n), v), 0.0), shininess);
#endif
        total += visibility * brdf * irradiance;
    }
    return total;
}
