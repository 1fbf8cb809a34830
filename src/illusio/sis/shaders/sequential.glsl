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
#if FROM_DEPTH
// the RGBA8 stereogram bound as R32UI (same texel size): colours move as packed words, with no
// unorm conversion per pixel
layout(r32ui, binding = 0) coherent uniform uimage2D stereogram;
uniform int end_column;
#else
layout(rgba8, binding = 0) coherent uniform image2D stereogram;
#endif

void main() {
    ivec2 size = imageSize(stereogram);
    int y = int(gl_GlobalInvocationID.x);
    if (y >= size.y) return;
    int start = row_start(y);
#if FROM_DEPTH
    // two loops instead of a branch per pixel: the first strip from the pattern, then the links.
    // With row starts (a host surface) the columns left of the start are skipped: no chain reaches
    // them (no separation exceeds the first strip) and the host does not show them.
    // end_column: a host ends there, so nothing right of it is shown (chains only look left: the
    // columns before it are the same either way)
    int row_end = min(size.x, end_column);
    int first_end = min(row_end, start + first_strip);
    for (int x = use_row_starts ? max(start, 0) : 0; x < first_end; ++x) {
        int s = int(floor(separation_at(x, y) + 0.5));
        imageStore(stereogram, ivec2(x, y), uvec4(packUnorm4x8(pattern_texel(x, y, s - strip_width))));
    }
    for (int x = first_end; x < row_end; ++x) {
        int s = int(floor(separation_at(x, y) + 0.5));
        imageStore(stereogram, ivec2(x, y), imageLoad(stereogram, ivec2(x - s, y)));
    }
#else
    for (int x = 0; x < size.x; ++x) {
        int s = rounded_separation(ivec2(x, y));
        vec4 c = (x - start < first_strip) ? pattern_texel(x, y, s - strip_width)
                                           : imageLoad(stereogram, ivec2(x - s, y));
        imageStore(stereogram, ivec2(x, y), c);
    }
#endif
}
#endif
