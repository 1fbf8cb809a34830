#version 430
// The second pass (section 4.2.3.2), one reference view per draw: each pixel of the new view, at the
// reconstructed depth, is back-projected into the reference; the reference's own depth there
// (bilinear over the four texels around it, the fix of Figure 4.4, or the nearest) gives the point
// the reference saw; its distance to ours — in pixels on the new image plane ("2d") or in metres
// ("3d") — goes to gl_FragDepth, so with the depth test LESS over all the draws each pixel keeps
// the reference that sees its point best. Outputs the G-buffer layout (albedo + k_s, corrected
// linear depth, normal + exponent, world position, source view index + 1, emission). A reference
// whose stored normal faces away from the new eye saw the other side of a thin surface: skipped.
// Where the four texels around the point lie on one surface (within 1 % in depth), the attributes
// are interpolated bilinearly too (no resampling aliasing of textures); else the nearest texel.
// NumPy reference: ibr.reference.select.
#include "common/fullscreen.glsl"

#if defined(FRAGMENT_SHADER)
uniform sampler2D reconstructed;   // new view's linear depth, 0 = nothing
uniform sampler2D ref_albedo;
uniform sampler2D ref_normal;
uniform sampler2D ref_emission;
uniform sampler2D ref_depth;       // metres, 0 = nothing
uniform mat4 new_inverse_view;
uniform vec4 new_projection;       // p00, p02, p11, p12 of the new camera's projection
uniform mat4 new_view_projection;
uniform mat4 new_view;
uniform mat4 ref_view_projection;
uniform mat4 ref_inverse_view;
uniform vec4 ref_projection;
uniform bool use_3d;
uniform bool bilinear;
uniform float max_distance;
uniform float source;              // reference index + 1
uniform vec3 new_eye;

layout(location = 0) out vec4 out_colour;
layout(location = 1) out float out_depth;
layout(location = 2) out vec4 out_normal;
layout(location = 3) out vec4 out_position;
layout(location = 4) out float out_id;
layout(location = 5) out vec4 out_emission;

vec3 unproject(vec2 pixel, vec2 size, float z, vec4 proj, mat4 inverse_view) {
    // pixel: from the top-left corner, centres at +0.5; z: metres along the view axis
    vec2 ndc = vec2(pixel.x / size.x * 2.0 - 1.0, 1.0 - pixel.y / size.y * 2.0);
    vec3 camera = vec3((ndc.x * z + proj.y * z) / proj.x, (ndc.y * z + proj.w * z) / proj.z, -z);
    return (inverse_view * vec4(camera, 1.0)).xyz;
}

vec4 bilerp(sampler2D s, ivec2 t0, ivec2 t1, vec2 f) {
    return mix(mix(texelFetch(s, t0, 0), texelFetch(s, ivec2(t1.x, t0.y), 0), f.x),
               mix(texelFetch(s, ivec2(t0.x, t1.y), 0), texelFetch(s, t1, 0), f.x), f.y);
}

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec2 size = vec2(textureSize(reconstructed, 0));
    float z = texelFetch(reconstructed, p, 0).r;
    if (z <= 0.0) discard;
    vec2 pixel = vec2(gl_FragCoord.x, size.y - gl_FragCoord.y);   // top-left origin, centre
    vec3 point = unproject(pixel, size, z, new_projection, new_inverse_view);

    vec4 clip = ref_view_projection * vec4(point, 1.0);
    if (clip.w <= 0.0) discard;
    vec2 uv = clip.xy / clip.w * 0.5 + 0.5;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThanEqual(uv, vec2(1.0)))) discard;
    ivec2 ref_size = textureSize(ref_depth, 0);
    vec2 t = uv * vec2(ref_size) - 0.5;                           // GL texel coordinates
    ivec2 nearest = clamp(ivec2(floor(t + 0.5)), ivec2(0), ref_size - 1);
    float d = texelFetch(ref_depth, nearest, 0).r;
    ivec2 t0 = clamp(ivec2(floor(t)), ivec2(0), ref_size - 1);
    ivec2 t1 = min(t0 + 1, ref_size - 1);
    vec2 f = clamp(t - vec2(t0), 0.0, 1.0);
    float d00 = texelFetch(ref_depth, t0, 0).r, d10 = texelFetch(ref_depth, ivec2(t1.x, t0.y), 0).r;
    float d01 = texelFetch(ref_depth, ivec2(t0.x, t1.y), 0).r, d11 = texelFetch(ref_depth, t1, 0).r;
    float lo = min(min(d00, d10), min(d01, d11)), hi = max(max(d00, d10), max(d01, d11));
    // the four texels on one surface (no depth edge between them): attributes are interpolated too
    bool on_one_surface = lo > 0.0 && hi <= lo * 1.01;
    if (bilinear && lo > 0.0) {
        d = mix(mix(d00, d10, f.x), mix(d01, d11, f.x), f.y);
    }
    if (d <= 0.0) discard;
    vec2 ref_pixel = vec2(uv.x * float(ref_size.x), (1.0 - uv.y) * float(ref_size.y));
    vec3 seen = unproject(ref_pixel, vec2(ref_size), d, ref_projection, ref_inverse_view);
    vec4 normal = on_one_surface ? bilerp(ref_normal, t0, t1, f) : texelFetch(ref_normal, nearest, 0);
    if (dot(normal.xyz, new_eye - seen) <= 0.0) discard;  // the reference saw the other side

    float distance;
    if (use_3d) {
        distance = length(seen - point);
    } else {
        vec4 c = new_view_projection * vec4(seen, 1.0);
        if (c.w <= 0.0) discard;
        vec2 seen_pixel = vec2((c.x / c.w * 0.5 + 0.5) * size.x, (0.5 - c.y / c.w * 0.5) * size.y);
        distance = length(seen_pixel - pixel);
    }
    if (distance > max_distance) discard;
    gl_FragDepth = distance / max_distance * 0.999;

    out_colour = on_one_surface ? bilerp(ref_albedo, t0, t1, f) : texelFetch(ref_albedo, nearest, 0);
    out_depth = -(new_view * vec4(seen, 1.0)).z;
    out_normal = normal;
    out_position = vec4(seen, 1.0);
    out_id = source;
    out_emission = vec4((on_one_surface ? bilerp(ref_emission, t0, t1, f) : texelFetch(ref_emission, nearest, 0)).rgb, 1.0);
}
#endif
