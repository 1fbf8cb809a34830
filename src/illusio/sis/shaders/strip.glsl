#version 430
// Algorithm 1 as render passes (Figure 21): pass 0 fills the first strip (W_s + β columns) from the
// pattern shifted by βD; pass k >= 1 computes the strip [lo, lo + W_s) from the previous pass's image,
// S[x] <- S[x - W_s - βD], and copies every other pixel, ping-ponging between two textures.
#include "common/fullscreen.glsl"

#if defined(FRAGMENT_SHADER)
#include "sis_common.glsl"
uniform sampler2D previous;
uniform int pass_index;
uniform int strip_lo;   // relative to the row start
out vec4 colour;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    int rel = p.x - row_start(p.y);
    int s = rounded_separation(p);
    if (pass_index == 0) {
        colour = rel < first_strip ? pattern_texel(p.x, p.y, s - strip_width) : vec4(0.0);
    } else if (rel >= strip_lo && rel < strip_lo + strip_width) {
        colour = texelFetch(previous, ivec2(p.x - s, p.y), 0);
    } else {
        colour = texelFetch(previous, p, 0);
    }
}
#endif
