#version 430
// The largest covering radius near each tile (the sampled gather's disk): for the tile of `tile` ×
// `tile` pixels at this fragment, the largest r_q = max(c_q / 2, 1/2) over that tile and its eight
// neighbours. With tile ≥ max_coc / 2, every pixel q whose circle covers a pixel p of the tile lies
// there, so the value bounds how far p must look. NumPy reference: dof.reference.coc_tiles.
#include "common/fullscreen.glsl"

#if defined(FRAGMENT_SHADER)
uniform sampler2D coc;   // .r: pixels
uniform int tile;        // pixels per tile side
out vec4 colour;

void main() {
    ivec2 size = textureSize(coc, 0);
    ivec2 t = ivec2(gl_FragCoord.xy);
    ivec2 lo = max((t - 1) * tile, ivec2(0));
    ivec2 hi = min((t + 2) * tile, size) - 1;
    float largest = 0.0;
    for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x)
            largest = max(largest, texelFetch(coc, ivec2(x, y), 0).r);
    colour = vec4(max(largest * 0.5, 0.5), 0.0, 0.0, 1.0);
}
#endif
