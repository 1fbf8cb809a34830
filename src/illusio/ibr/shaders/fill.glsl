#version 430
// Hole filling in one draw (rings.glsl): an empty pixel takes the farthest of the nearest ring around
// it holding something, up to `radius` rings; others stay, so the cost is in the holes. Default: the
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
void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    float d = texelFetch(depth, p, 0).r;
    filled = d > 0.0 ? d : farthest_of_nearest_ring(depth, p, radius, 0).r;
}
#endif
#endif
