#version 430
// One ring of hole filling: an empty pixel (0) takes the largest (farthest) depth of its 3×3
// neighbourhood, others stay. Run fill_radius times. NumPy reference: ibr.renderer.fill_holes.
#include "common/fullscreen.glsl"

#if defined(FRAGMENT_SHADER)
uniform sampler2D depth;
out float filled;
void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    ivec2 size = textureSize(depth, 0);
    float d = texelFetch(depth, p, 0).r;
    if (d <= 0.0) {
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                ivec2 q = p + ivec2(dx, dy);
                if (q.x >= 0 && q.y >= 0 && q.x < size.x && q.y < size.y) d = max(d, texelFetch(depth, q, 0).r);
            }
    }
    filled = d;
}
#endif
