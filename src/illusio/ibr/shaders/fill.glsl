#version 430
// Hole filling in one draw (rings.glsl): an empty pixel takes the farthest of the nearest ring around
// it holding something, up to `radius` rings; others stay, so the cost is in the holes (an empty
// pixel with no depth in its square reads it in gathers and stays empty: the background). Default: the
// first pass's depth (0 = empty; NumPy reference ibr.renderer.fill_holes). HITS=1: the selection's
// hits (uv, reference depth, reference index + 1; empty where the index is 0 and the reconstructed
// depth has a point: a disocclusion), between the selection and the resolve (NumPy reference
// ibr.renderer.fill_hits; inside the resolve draw the loop slowed every pixel on llvmpipe).
#include "common/fullscreen.glsl"
#ifndef HITS
#define HITS 0
#endif

#if defined(FRAGMENT_SHADER)
#include "rings.glsl"
uniform int radius;
#if HITS
uniform sampler2D hits;
uniform sampler2D reconstructed;
out vec4 filled;
void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 h = texelFetch(hits, p, 0);
    filled = h.w == 0.0 && texelFetch(reconstructed, p, 0).r > 0.0 ? farthest_of_nearest_ring(hits, p, radius, 2) : h;
}
#else
uniform sampler2D depth;
out float filled;

// whether any depth lies in the (2 radius + 1)² square around p: its texels four at a time, in
// gathers (a square of 2 radius + 2 texels, edges wrapped or clamped: a superset of those inside
// the image). Most empty pixels are the background, far from any depth: this answers them with
// about a third of the ring search's reads
bool depth_within(ivec2 p) {
    vec2 texel = 1.0 / vec2(textureSize(depth, 0));
    vec4 most = vec4(0.0);
    for (int dy = -radius; dy <= radius; dy += 2)
        for (int dx = -radius; dx <= radius; dx += 2)
            most = max(most, textureGather(depth, (vec2(p + ivec2(dx, dy)) + 1.0) * texel, 0));
    return max(max(most.x, most.y), max(most.z, most.w)) > 0.0;
}

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    float d = texelFetch(depth, p, 0).r;
    filled = d;
    if (d > 0.0) return;
    if (depth_within(p)) filled = farthest_of_nearest_ring(depth, p, radius, 0).r;
}
#endif
#endif
