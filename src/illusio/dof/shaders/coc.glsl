#version 430
// Circle of confusion per pixel, in pixels, from linear view depth (dof.lens; NumPy reference
// dof.reference.coc): c = A |1/d − 1/d_f| · scale, scale = H / (2 tan(fov_y/2)); no surface
// (depth ≤ 0) counts as infinitely far. Clamped to max_coc.
#include "common/fullscreen.glsl"

#if defined(FRAGMENT_SHADER)
uniform sampler2D depth;       // .r: metres along the view axis, 0 = nothing
uniform float aperture;        // A, metres
uniform float focus_distance;  // d_f, metres
uniform float scale;           // H / (2 tan(fov_y / 2)), pixels
uniform float max_coc;         // pixels
out float coc;

void main() {
    float d = texelFetch(depth, ivec2(gl_FragCoord.xy), 0).r;
    float inverse = d > 0.0 ? 1.0 / d : 0.0;
    coc = min(aperture * abs(inverse - 1.0 / focus_distance) * scale, max_coc);
}
#endif
