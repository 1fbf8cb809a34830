#version 430
// The per-pixel layout of the fast pass: every pixel on its own: follow x -> x - s(x) until the first strip, then take the pattern
// there. The same image as the sequential algorithm (sis.reference.fast), with no order between pixels.
#include "common/fullscreen.glsl"

#if defined(FRAGMENT_SHADER)
#include "sis_common.glsl"
out vec4 colour;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    int start = row_start(p.y);
    int s = rounded_separation(p);
    while (p.x - start >= first_strip) {
        p.x -= s;
        s = rounded_separation(p);
    }
    colour = pattern_texel(p.x, p.y, s - strip_width);
}
#endif
