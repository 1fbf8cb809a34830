#version 430
// The fast formulation: the whole stereogram in one dispatch, depth in, stereogram out. One
// invocation per row walks it left to right and computes each pixel's separation from the depth on
// the fly (no separation pass, no separation texture). The same image as the sequential algorithm
// (sis.reference.sequential). (A private ring buffer of recent colours instead of reading the image
// back measured no faster on llvmpipe.)
#define ROWS_PER_GROUP 64
#if defined(COMPUTE_SHADER)
layout(local_size_x = ROWS_PER_GROUP) in;
#include "depth_to_separation.glsl"
#include "sis_common.glsl"
layout(rgba8, binding = 0) coherent uniform image2D stereogram;


void main() {
    ivec2 size = imageSize(stereogram);
    int y = int(gl_GlobalInvocationID.x);
    if (y >= size.y) return;
    int start = row_start(y);
    for (int x = 0; x < size.x; ++x) {
        int s = int(floor(separation_at(x, y) + 0.5));
        vec4 c = (x - start < first_strip) ? pattern_texel(x, y, s - strip_width)
                                           : imageLoad(stereogram, ivec2(x - s, y));
        imageStore(stereogram, ivec2(x, y), c);
    }
}
#endif
