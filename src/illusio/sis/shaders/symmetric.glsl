#version 430
// Thimbleby, Inglis & Witten (1994), one invocation per row (sis.reference.symmetric): link the pixels
// x - s/2 and x - s/2 + s of every point x that both eyes see, keeping each chain of links sorted left
// to right in same[], then colour right to left. Hidden-surface test: a point is hidden when a column
// t pixels to its side is nearer than the sight line there, sigma(t) = e_p - e_p (e_p - s)/(e_p - 2t).
#if defined(COMPUTE_SHADER)
layout(local_size_x = 64) in;
#include "sis_common.glsl"
uniform float near_separation;     // W_s: nothing is nearer
uniform float eye_separation_px;   // e_p
layout(rgba8, binding = 0) coherent uniform image2D stereogram;
layout(r32i, binding = 1) coherent uniform iimage2D same;

float sep_at(int x, int y) { return texelFetch(separation_map, ivec2(x, y), 0).r; }

void main() {
    ivec2 size = imageSize(stereogram);
    int y = int(gl_GlobalInvocationID.x);
    if (y >= size.y) return;
    int w = size.x;
    float e = eye_separation_px;
    for (int x = 0; x < w; ++x) imageStore(same, ivec2(x, y), ivec4(x));
    int r0 = row_start(y);
    for (int x = r0; x < w; ++x) {
        float sf = sep_at(x, y);
        int s = int(floor(sf + 0.5));
        int left = x - s / 2;
        int right = left + s;
        if (left < r0 || right >= w) continue;
        bool visible = true;
        for (int t = 1; ; ++t) {
            float sigma = e - e * (e - sf) / (e - float(2 * t));
            if (sigma <= near_separation) break;
            if ((x - t >= r0 && sep_at(x - t, y) < sigma) || (x + t < w && sep_at(x + t, y) < sigma)) {
                visible = false;
                break;
            }
        }
        if (!visible) continue;
        int k = imageLoad(same, ivec2(left, y)).r;
        while (k != left && k != right) {
            if (k < right) {
                left = k;
            } else {
                int old_right = right;
                right = k;
                left = old_right;
            }
            k = imageLoad(same, ivec2(left, y)).r;
        }
        imageStore(same, ivec2(left, y), ivec4(right));
    }
    for (int x = w - 1; x >= 0; --x) {
        int k = imageLoad(same, ivec2(x, y)).r;
        vec4 c = (k == x) ? pattern_texel(x, y, 0) : imageLoad(stereogram, ivec2(k, y));
        imageStore(stereogram, ivec2(x, y), c);
    }
}
#endif
