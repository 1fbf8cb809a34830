#version 430
// Each row's first host column (depth >= 0) and one past its last, times the oversampling factor:
// where that row's stereogram starts (R) and where its first strip's pattern wraps (G). Rows without
// host pixels start past the end. Only columns [first_column, end_column) are searched: where the
// host's bounding box projects (no host pixel lies outside).
#if defined(COMPUTE_SHADER)
layout(local_size_x = 64) in;
uniform sampler2D depth_map;
uniform int oversample;
uniform int first_column;
uniform int end_column;
layout(rg32i, binding = 0) uniform writeonly iimage2D row_starts;

void main() {
    ivec2 size = textureSize(depth_map, 0);
    int y = int(gl_GlobalInvocationID.x);
    if (y >= size.y) return;
    int end = min(end_column, size.x);
    int x = max(first_column, 0);
    while (x < end && texelFetch(depth_map, ivec2(x, y), 0).r < 0.0) ++x;
    if (x >= end) {
        imageStore(row_starts, ivec2(y, 0), ivec4(size.x * oversample, size.x * oversample, 0, 0));
        return;
    }
    int last = end - 1;
    while (last > x && texelFetch(depth_map, ivec2(last, y), 0).r < 0.0) --last;
    imageStore(row_starts, ivec2(y, 0), ivec4(x * oversample, (last + 1) * oversample, 0, 0));
}
#endif
