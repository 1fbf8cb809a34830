#version 430
// The second pass (section 4.2.3.2). SELECT, one full-screen draw per reference view: each pixel of
// the new view, at the reconstructed depth, is back-projected into the reference; the reference's own
// depth there (bilinear over the four texels around it, the fix of Figure 4.4, or the nearest; the
// four read in one gather) gives the point the reference saw; its distance to ours — in pixels on the
// new image plane ("2d") or in metres ("3d") — goes to gl_FragDepth, so with the depth test LESS over
// all the draws each pixel keeps the reference that sees its point best; the draw writes (uv, depth
// read, reference index + 1). A reference whose stored normal faces away from the new eye saw the
// other side of a thin surface: skipped. SINGLE_PASS=1: the text's one-pass variant, one draw looping
// over the references and keeping the smallest distance itself (no depth test; the text packs depth
// in the colour's alpha to fit three views in its texture units, texture arrays lift that limit).
// DISTANCE_3D and BILINEAR are compiled in, not uniform switches (llvmpipe runs both sides of a
// branch where the pixels of a group disagree). RESOLVE=1, once, after the disocclusions are filled
// (fill.glsl, HITS=1): the chosen reference's attributes at that point — bilinear where the four
// texels around it lie on one surface (depths within 1 %), else the nearest texel; a recorded colour
// (photographic) bilinear everywhere — into the G-buffer layout (albedo + k_s, corrected linear
// depth, normal + exponent, world position, source index + 1, emission), or with SHADE=1 lit at once
// by emitters.glsl as the deferred shading would (radiance + source index): no G-buffer written and
// read again. SINGLE_PASS=1 with SHADE=1: the selection and the lit resolve in one draw (radiance,
// source, and the hits for the fill; the four depths of the chosen texel, already gathered, decide
// its filtering), the pixels with reconstructed depth and no reference marked in the depth buffer
// (1; others 0); then RESOLVE=1 SHADE=1 FILL=1 draws with the depth test only over those, each
// filling its hit from the rings around it (rings.glsl, as fill.glsl) and lighting it. EMISSION=0:
// no reference emits and the output is not photographic, so the emission's fetch is left out. NumPy
// references: ibr.reference.select, ibr.renderer.fill_hits, passes.reference.shading.
#include "common/fullscreen.glsl"
#define MAX_REFERENCES 16

#ifndef RESOLVE
#define RESOLVE 0
#endif
#ifndef SHADE
#define SHADE 0
#endif
#define MAX_EMITTERS 64
#define SHADOW_MAPS 0
#ifndef DISTANCE_3D
#define DISTANCE_3D 0
#endif
#ifndef BILINEAR
#define BILINEAR 1
#endif
#ifndef SINGLE_PASS
#define SINGLE_PASS 0
#endif
#ifndef FILL
#define FILL 0
#endif
#ifndef EMISSION
#define EMISSION 1
#endif

#if defined(FRAGMENT_SHADER)
uniform sampler2DArray ref_albedo;     // linear filtering: one sample interpolates (the resolve)
uniform sampler2DArray ref_normal;
uniform sampler2DArray ref_emission;   // the recorded colour instead, photographic output (bound so)
uniform sampler2DArray ref_depth;       // metres, 0 = nothing; nearest
uniform mat4 ref_inverse_view[MAX_REFERENCES];
uniform vec4 ref_projection[MAX_REFERENCES];  // p00, p02, p11, p12
uniform mat4 new_view;

vec3 unproject(vec2 pixel, vec2 size, float z, vec4 proj, mat4 inverse_view) {
    // pixel: from the top-left corner, centres at +0.5; z: metres along the view axis
    vec2 ndc = vec2(pixel.x / size.x * 2.0 - 1.0, 1.0 - pixel.y / size.y * 2.0);
    vec3 camera = vec3((ndc.x * z + proj.y * z) / proj.x, (ndc.y * z + proj.w * z) / proj.z, -z);
    return (inverse_view * vec4(camera, 1.0)).xyz;
}

vec4 fetch(sampler2DArray s, ivec2 t, int k) { return texelFetch(s, ivec3(t, k), 0); }

// reference k's depth at the four texels around GL texel coordinate t, in one gather: (t0), (t1.x,
// t0.y), (t0.x, t1.y), (t1), t0 = floor(t) and t1 = t0 + 1 clamped to the image as GL_CLAMP_TO_EDGE
vec4 depth_corners(vec2 t, ivec2 ref_size, int k, out ivec2 t0) {
    t0 = clamp(ivec2(floor(t)), ivec2(0), ref_size - 1);
    return textureGather(ref_depth, vec3((vec2(t0) + 1.0) / vec2(ref_size), float(k)), 0).wzxy;
}

#if RESOLVE || SHADE
uniform bool photographic;             // the recorded colour as emission, no albedo

// the point reference k saw at the hit h (uv, depth read)
vec3 seen_at(vec4 h, int k) {
    ivec2 ref_size = textureSize(ref_depth, 0).xy;
    vec2 ref_pixel = vec2(h.x * float(ref_size.x), (1.0 - h.y) * float(ref_size.y));
    return unproject(ref_pixel, vec2(ref_size), h.z, ref_projection[k], ref_inverse_view[k]);
}

// reference k's attributes at the hit h (uv, depth read), `corners` its four depths around h.xy
// (depth_corners): bilinear where they lie on one surface (within 1 %), else the nearest texel —
// one linear-filtered sample either way (at the nearest texel's centre the filter returns that
// texel: cheaper on llvmpipe than fetching four and choosing)
void attributes_at(vec4 h, int k, vec4 corners, out vec4 albedo, out vec4 normal, out vec3 emission) {
    ivec2 ref_size = textureSize(ref_depth, 0).xy;
    vec2 t = h.xy * vec2(ref_size) - 0.5;
    ivec2 nearest = clamp(ivec2(floor(t + 0.5)), ivec2(0), ref_size - 1);
    vec4 c = corners;
    float lo = min(min(c.x, c.y), min(c.z, c.w)), hi = max(max(c.x, c.y), max(c.z, c.w));
    bool on_one_surface = lo > 0.0 && hi <= lo * 1.01;
    vec3 at = vec3(on_one_surface ? h.xy : (vec2(nearest) + 0.5) / vec2(ref_size), float(k));
    normal = texture(ref_normal, at);
    albedo = texture(ref_albedo, at) * (photographic ? 0.0 : 1.0);
    // a recorded colour is an image of the light, not an attribute of one surface: resampled
    // bilinearly everywhere, as a camera's pixels blend what they cover (silhouettes included)
#if EMISSION
    emission = texture(ref_emission, photographic ? vec3(h.xy, float(k)) : at).rgb;
#else
    emission = vec3(0.0);  // no reference emits, and the output is not photographic: nothing to read
#endif
}

// the same, its four depths gathered here
void attributes(vec4 h, int k, out vec4 albedo, out vec4 normal, out vec3 emission, out vec3 seen) {
    ivec2 ref_size = textureSize(ref_depth, 0).xy;
    ivec2 t0;
    vec4 corners = depth_corners(h.xy * vec2(ref_size) - 0.5, ref_size, k, t0);
    attributes_at(h, k, corners, albedo, normal, emission);
    seen = seen_at(h, k);
}

#if SHADE
#include "passes/shaders/emitters.glsl"
uniform vec3 camera_position;
uniform vec3 ambient;
uniform vec3 background;
uniform float exposure;
layout(location = 0) out vec4 out_radiance;
layout(location = 1) out float out_id;

// the radiance the deferred shading makes of reference k's attributes at the hit h, the point `seen`
vec4 lit(vec4 h, int k, vec4 corners, vec3 seen) {
    vec4 albedo, normal;
    vec3 emission;
    attributes_at(h, k, corners, albedo, normal, emission);
    vec3 total = direct_light(seen, normalize(normal.xyz), normalize(camera_position - seen), albedo.rgb, albedo.a, normal.a);
    return vec4((total + ambient * albedo.rgb + emission) * exposure, 1.0);
}
#endif
#endif

#if !RESOLVE
uniform sampler2D reconstructed;        // new view's linear depth, 0 = nothing
uniform mat4 new_inverse_view;
uniform vec4 new_projection;
uniform mat4 new_view_projection;
uniform vec3 new_eye;
uniform mat4 ref_view_projection[MAX_REFERENCES];
uniform vec4 ref_eye_clip[MAX_REFERENCES];  // each reference's eye in the new view's clip space
uniform int layer;                      // the reference of this draw (multi-pass)
uniform int count;                      // the references (single pass)
uniform float max_distance;
#if SHADE
layout(location = 2) out vec4 hit;      // as below, for the fill
#else
out vec4 hit;                           // uv in the reference, its depth there, reference index + 1
#endif

// reference `k` seeing the new view's `point` (at `pixel`): its distance to the point the reference
// saw there, what the draw writes, the four depths around it (depth_corners) and that point; false
// where the reference does not see it. Whether it saw the side facing us is faces_us's question
bool candidate(int k, vec3 point, vec4 point_clip, vec2 pixel, vec2 size, out float distance, out vec4 found, out vec4 corners, out vec3 seen) {
    vec4 clip = ref_view_projection[k] * vec4(point, 1.0);
    if (clip.w <= 0.0) return false;
    vec2 uv = clip.xy / clip.w * 0.5 + 0.5;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThanEqual(uv, vec2(1.0)))) return false;
    ivec2 ref_size = textureSize(ref_depth, 0).xy;
    vec2 t = uv * vec2(ref_size) - 0.5;                           // GL texel coordinates
    ivec2 t0;
    vec4 c = depth_corners(t, ref_size, k, t0);
    corners = c;
    vec2 f = clamp(t - vec2(t0), 0.0, 1.0);
    float d = f.y < 0.5 ? (f.x < 0.5 ? c.x : c.y) : (f.x < 0.5 ? c.z : c.w);
#if BILINEAR
    if (min(min(c.x, c.y), min(c.z, c.w)) > 0.0) d = mix(mix(c.x, c.y, f.x), mix(c.z, c.w, f.x), f.y);
#endif
    if (d <= 0.0) return false;
    // the point the reference saw: on its ray through ours (the texel's), at depth d along its
    // axis, where ours is at clip.w (unproject's result without its matrix product)
    vec3 eye = ref_inverse_view[k][3].xyz;
    float along = d / clip.w;
    seen = eye + (point - eye) * along;
#if DISTANCE_3D
    distance = length(seen - point);
#else
    vec4 s = mix(ref_eye_clip[k], point_clip, along);  // = new_view_projection * (seen, 1): linear
    if (s.w <= 0.0) return false;
    vec2 seen_pixel = vec2((s.x / s.w * 0.5 + 0.5) * size.x, (0.5 - s.y / s.w * 0.5) * size.y);
    distance = length(seen_pixel - pixel);
#endif
    if (distance > max_distance) return false;
    found = vec4(uv, d, float(k + 1));
    return true;
}

// whether the reference of hit `found` (candidate's), its normal at the nearest texel, faces the new
// eye from `seen`: a reference whose stored normal faces away saw the other side of a thin surface
bool faces_us(vec4 found, vec3 seen) {
    int k = int(found.w + 0.5) - 1;
    ivec2 ref_size = textureSize(ref_depth, 0).xy;
    ivec2 nearest = clamp(ivec2(floor(found.xy * vec2(ref_size))), ivec2(0), ref_size - 1);
    return dot(fetch(ref_normal, nearest, k).xyz, new_eye - seen) > 0.0;
}

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec2 size = vec2(textureSize(reconstructed, 0));
    float z = texelFetch(reconstructed, p, 0).r;
#if SHADE
    if (z <= 0.0) {  // nothing here: the background, as the deferred shading draws it; no fill
        out_radiance = vec4(background, 1.0);
        out_id = 0.0;
        hit = vec4(0.0);
        gl_FragDepth = 0.0;
        return;
    }
#else
    if (z <= 0.0) discard;
#endif
    vec2 pixel = vec2(gl_FragCoord.x, size.y - gl_FragCoord.y);   // top-left origin, centre
    vec3 point = unproject(pixel, size, z, new_projection, new_inverse_view);
    vec4 point_clip = new_view_projection * vec4(point, 1.0);
    float distance;
    vec4 found, corners;
    vec3 seen;
#if SINGLE_PASS
    // the nearest candidate that faces us: the nearest of all, its side tested; where that fails
    // (rare: thin surfaces), the nearest of the rest, and so on. The same choice as testing every
    // candidate's side, for one normal fetch a pixel instead of one a reference (on llvmpipe an if
    // around the fetch measured no cheaper than the fetch itself, the compiler flattening a small
    // branch, but a loop is left once none of a group's pixels goes round again)
    vec4 best_corners = vec4(0.0);
    vec3 best_seen = vec3(0.0);
    int away = 0;  // bit k: reference k saw the other side
    for (int round = 0; round < count; ++round) {
        float best = max_distance * 2.0;
        hit = vec4(0.0);
        for (int k = 0; k < count; ++k) {
            // strictly nearer, as the depth test LESS over draws in reference order
            if ((away & (1 << k)) == 0 && candidate(k, point, point_clip, pixel, size, distance, found, corners, seen)
                    && distance < best) {
                best = distance;
                hit = found;
                best_corners = corners;
                best_seen = seen;
            }
        }
        if (hit.w == 0.0 || faces_us(hit, best_seen)) break;
        away |= 1 << (int(hit.w + 0.5) - 1);
        hit = vec4(0.0);  // (the last round's other side: no reference)
    }
#if SHADE
    if (hit.w == 0.0) {  // seen by no reference: the fill's (the depth test lets only these through)
        out_radiance = vec4(background, 1.0);
        out_id = 0.0;
        gl_FragDepth = 1.0;
        return;
    }
    out_radiance = lit(hit, int(hit.w + 0.5) - 1, best_corners, best_seen);
    out_id = hit.w;
    gl_FragDepth = 0.0;
#else
    if (hit.w == 0.0) discard;
#endif
#else
    if (!candidate(layer, point, point_clip, pixel, size, distance, found, corners, seen) || !faces_us(found, seen)) discard;
    gl_FragDepth = distance / max_distance * 0.999;
    hit = found;
#endif
}
#else
uniform sampler2D hits;
#if FILL
#include "rings.glsl"
uniform int radius;
#endif
#if !SHADE
#include "common/gbuffer_outputs.glsl"
#endif

void main() {
#if FILL
    // only the pixels the selection left without a reference run (the depth test): the farthest hit
    // of the nearest ring around them (fill.glsl's, HITS=1)
    vec4 h = farthest_of_nearest_ring(hits, ivec2(gl_FragCoord.xy), radius, 2);
#else
    vec4 h = texelFetch(hits, ivec2(gl_FragCoord.xy), 0);
#endif
    int k = int(h.w + 0.5) - 1;
    out_id = max(h.w, 0.0);
#if SHADE
    if (k < 0) {  // a hole: the background, as the deferred shading draws it
        out_radiance = vec4(background, 1.0);
        return;
    }
    ivec2 ref_size = textureSize(ref_depth, 0).xy;
    ivec2 t0;
    out_radiance = lit(h, k, depth_corners(h.xy * vec2(ref_size) - 0.5, ref_size, k, t0), seen_at(h, k));
#else
    vec4 albedo, normal;
    vec3 emission, seen;
    if (k < 0) {  // a hole: nothing, as the G-buffer's background
        out_colour = vec4(0.0); out_depth = 0.0; out_normal = vec4(0.0); out_position = vec4(0.0);
        out_emission = vec4(0.0);
        return;
    }
    attributes(h, k, albedo, normal, emission, seen);
    out_colour = albedo;
    out_normal = normal;
    out_emission = vec4(emission, 1.0);
    out_depth = -(new_view * vec4(seen, 1.0)).z;
    out_position = vec4(seen, 1.0);
#endif
}
#endif
#endif
