#version 430
// Filling the selection's holes (disocclusions: the reconstructed depth has a point, no reference
// sees it), in one draw: an empty pixel looks at the rings of pixels around it, nearest first, and
// takes from the first ring holding hits the one whose reference saw the farthest point (the
// background goes on behind the occluder); up to `radius` rings. Pixels with a hit leave at once,
// so the cost is in the holes. NumPy reference: ibr.renderer.fill_hits.
#include "common/fullscreen.glsl"

#if defined(FRAGMENT_SHADER)
uniform sampler2D hits;          // uv, reference depth, reference index + 1 (0 = none)
uniform sampler2D reconstructed; // the new view's depth, 0 = nothing there
uniform int radius;
out vec4 filled;
void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    ivec2 size = textureSize(hits, 0);
    vec4 h = texelFetch(hits, p, 0);
    if (h.w == 0.0 && texelFetch(reconstructed, p, 0).r > 0.0) {
        for (int r = 1; r <= radius && h.w == 0.0; ++r)
            for (int dy = -r; dy <= r; ++dy)
                for (int dx = -r; dx <= r; dx += (abs(dy) == r ? 1 : 2 * r)) {  // the ring only
                    ivec2 q = p + ivec2(dx, dy);
                    if (q.x >= 0 && q.y >= 0 && q.x < size.x && q.y < size.y) {
                        vec4 n = texelFetch(hits, q, 0);
                        if (n.w > 0.0 && (h.w == 0.0 || n.z > h.z)) h = n;
                    }
                }
    }
    filled = h;
}
#endif
