#version 430
// Second pass of the hybrid apparent-ridge method (report, section 3.3, Figure 3.8, annex B): a 3×3
// Laplacian of q whose weights follow t1, quantised to one of four directions (0°, 45°, 90°, 135°,
// each within 22.5°): the two neighbours along t1 weigh 1 + 2λ, the two across it 1, the four others
// 1 + λ; the centre 8 + 8λ. A pixel is on a ridge where the response exceeds the threshold.
// Output: (ridge 0/1, response, 0, 1) — the flag first, so a mask reads back as one 8-bit channel;
// background and t1 = 0 pixels respond 0.
// NumPy reference: lines.ridge_filter.adaptive_laplacian.
#include "common/fullscreen.glsl"

#if defined(FRAGMENT_SHADER)
uniform sampler2D q_t1;          // from view_curvature.glsl
uniform float lambda;            // λ: weight of the direction
uniform float threshold;         // 0.2 in the report
out vec4 result;

float q_at(ivec2 p, ivec2 size) {
    return texelFetch(q_t1, clamp(p, ivec2(0), size - 1), 0).r;
}

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    ivec2 size = textureSize(q_t1, 0);
    vec4 centre = texelFetch(q_t1, p, 0);
    vec2 t1 = centre.gb;
    float response = 0.0;
    if (dot(t1, t1) > 1e-12) {
        t1 = normalize(t1);  // interpolated across the triangle: no longer unit
        const float c = 0.92387953251080;  // cos(π/8)
        const float a = 0.70710678118655;
        // weights of the neighbours at (dx, dy), dy up; the case picks which pair weighs 1 + 2λ
        float l1 = 1.0 + lambda;
        float l2 = 1.0 + 2.0 * lambda;
        float w_h = l1, w_v = l1, w_d = l1, w_a = l1;  // horizontal, vertical, diagonal (1,1), anti (−1,1)
        if (abs(t1.x) > c)                        { w_h = l2; w_v = 1.0; }
        else if (abs(dot(t1, vec2(a, a))) > c)    { w_d = l2; w_a = 1.0; }
        else if (abs(t1.y) > c)                   { w_v = l2; w_h = 1.0; }
        else                                      { w_a = l2; w_d = 1.0; }
        float sum = w_h * (q_at(p + ivec2(1, 0), size) + q_at(p + ivec2(-1, 0), size))
                  + w_v * (q_at(p + ivec2(0, 1), size) + q_at(p + ivec2(0, -1), size))
                  + w_d * (q_at(p + ivec2(1, 1), size) + q_at(p + ivec2(-1, -1), size))
                  + w_a * (q_at(p + ivec2(-1, 1), size) + q_at(p + ivec2(1, -1), size));
        response = (8.0 + 8.0 * lambda) * centre.r - sum;
    }
    result = vec4(response > threshold ? 1.0 : 0.0, response, 0.0, 1.0);
}
#endif
