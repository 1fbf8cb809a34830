#version 430
// Each row's first host column (depth >= 0), times the oversampling factor: where that row's
// stereogram starts. Rows without host pixels start past the end. Only columns [first_column,
// end_column) are searched: where the host's bounding box projects (no host pixel lies outside).
#if defined(COMPUTE_SHADER)
layout(local_size_x = 64) in;
uniform sampler2D depth_map;
uniform int oversample;
uniform int first_column;
uniform int end_column;
layout(r32i, binding = 0) uniform writeonly iimage2D row_starts;

void main() {
    ivec2 size = textureSize(depth_map, 0);
    int y = int(gl_GlobalInvocationID.x);
    if (y >= size.y) return;
    int end = min(end_column, size.x);
    int x = max(first_column, 0);
    while (x < end && texelFetch(depth_map, ivec2(x, y), 0).r < 0.0) ++x;
    if (x >= end) x = size.x;
    imageStore(row_starts, ivec2(y, 0), ivec4(x * oversample));
}
#endif
