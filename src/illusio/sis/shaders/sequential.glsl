#version 430
// Section 3.3: each row left to right, S[x] <- S[x - s(x)] past the first strip, the pattern shifted
// by s - W_s inside it. One invocation per row, all rows in one dispatch (sis.reference.sequential).
// FROM_DEPTH 1 is the fast formulation: the separation is computed from the depth on the fly, so the
// whole stereogram takes one dispatch with no separation pass. (A private ring buffer of recent
// colours instead of reading the image back measured no faster on llvmpipe.)
#define FROM_DEPTH 0
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
#if FROM_DEPTH
        int s = int(floor(separation_at(x, y) + 0.5));
#else
        int s = rounded_separation(ivec2(x, y));
#endif
        vec4 c = (x - start < first_strip) ? pattern_texel(x, y, s - strip_width)
                                           : imageLoad(stereogram, ivec2(x - s, y));
        imageStore(stereogram, ivec2(x, y), c);
    }
}
#endif
