#version 430
// Section 3.3: each row left to right, S[x] <- S[x - s(x)] past the first strip, the pattern shifted
// by s - W_s inside it. One invocation per row, all rows in one dispatch (sis.reference.sequential).
#if defined(COMPUTE_SHADER)
layout(local_size_x = 64) in;
#include "sis_common.glsl"
layout(rgba8, binding = 0) coherent uniform image2D stereogram;

void main() {
    ivec2 size = imageSize(stereogram);
    int y = int(gl_GlobalInvocationID.x);
    if (y >= size.y) return;
    int start = row_start(y);
    for (int x = 0; x < size.x; ++x) {
        int s = rounded_separation(ivec2(x, y));
        vec4 c = (x - start < first_strip) ? pattern_texel(x, y, s - strip_width)
                                           : imageLoad(stereogram, ivec2(x - s, y));
        imageStore(stereogram, ivec2(x, y), c);
    }
}
#endif
