#version 430
// Depth-aware gather (the "convolution" method of section 2.2.2, scattering written as gathering;
// NumPy reference dof.reference.gather). Every pixel q within `radius` of p whose own circle of
// confusion covers p (r_q = max(c_q / 2, 1/2)) adds its colour with weight cover / (π r_q²), cover =
// clamp(r_q + ½ − |q − p|, 0, 1) (the circle's edge smoothed over a pixel: a hard edge aliases the
// rim of a bright, slightly blurred light, 1.4 dB of the living room's error),
// unless it lies behind p (z_q > z_p (1 + depth_slack)) outside p's own circle (|q − p| > r_p):
// a sharp foreground does not bleed over the blurred background behind it, and a blurred
// background does not bleed over a sharp foreground in front of it.
#include "common/fullscreen.glsl"

#if defined(FRAGMENT_SHADER)
#include "gather_rule.glsl"
uniform int radius;            // pixels: ceil(max_coc / 2)

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    ivec2 size = textureSize(image, 0);
    float zp = far_depth(p);
    float rp = covering_radius(p);
    vec3 sum = vec3(0.0);
    float total = 0.0;
    for (int dy = -radius; dy <= radius; ++dy) {
        for (int dx = -radius; dx <= radius; ++dx) {
            ivec2 q = p + ivec2(dx, dy);
            if (q.x < 0 || q.y < 0 || q.x >= size.x || q.y >= size.y) continue;
            float dist = length(vec2(dx, dy));
            float rq = covering_radius(q);
            float cover = clamp(rq + 0.5 - dist, 0.0, 1.0);
            if (cover <= 0.0) continue;
            if (hidden(far_depth(q), zp, dist, rp)) continue;
            float w = cover / (PI * rq * rq);
            sum += w * texelFetch(image, q, 0).rgb;
            total += w;
        }
    }
    colour = vec4(sum / total, 1.0);
}
#endif
