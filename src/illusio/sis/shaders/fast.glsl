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
uniform sampler2D pattern;
uniform isampler2D row_starts;
uniform bool use_row_starts;
uniform int image_height;
uniform int strip_width;            // W_s, whole pixels
uniform int first_strip;            // W_s + β, whole pixels
layout(rgba8, binding = 0) coherent uniform image2D stereogram;

vec4 pattern_texel(int x, int y, int shift) {
    ivec2 size = textureSize(pattern, 0);
    int y_top = image_height - 1 - y;
    int row = size.y - 1 - y_top % size.y;
    int v = x - shift;
    if (v < 0) v += size.x * (-v / size.x + 1);
    return texelFetch(pattern, ivec2(v % size.x, row), 0);
}

void main() {
    ivec2 size = imageSize(stereogram);
    int y = int(gl_GlobalInvocationID.x);
    if (y >= size.y) return;
    int start = use_row_starts ? texelFetch(row_starts, ivec2(y, 0), 0).r : 0;
    for (int x = 0; x < size.x; ++x) {
        int s = int(floor(separation_at(x, y) + 0.5));
        vec4 c = (x - start < first_strip) ? pattern_texel(x, y, s - strip_width)
                                           : imageLoad(stereogram, ivec2(x - s, y));
        imageStore(stereogram, ivec2(x, y), c);
    }
}
#endif
