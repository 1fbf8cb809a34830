#version 430
// The first pass's points (the reference pixels no kept triangle covers), scattered into the new
// view's linear depth after the mesh: each a square of side max(1, footprint · f_x / z) pixels
// centred where it projects, every pixel whose centre lies inside taking its depth, the nearest
// winning — what GL_POINTS with that point size and the z-buffer draw, one invocation a point
// instead of a rasterised primitive (llvmpipe sets up a point as dearly as a triangle, and the points
// of references at twice the output's size land four to a pixel). The depth texture is R32F, bound
// as r32ui: positive floats order as their bits, 0 = nothing. NumPy reference: ibr.reference.point_depth.
#if defined(COMPUTE_SHADER)
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Points { vec4 points[]; };  // world xyz, footprint (m)
layout(r32ui, binding = 0) uniform coherent uimage2D depth;
uniform mat4 view_matrix;
uniform mat4 projection_matrix;
uniform float focal_px;    // the new view's f_x in pixels
uniform float near;        // metres: nearer points are clipped, as GL clips them
uniform int count;

void main() {
    int i = int(gl_GlobalInvocationID.x);
    if (i >= count) return;
    vec4 eye = view_matrix * vec4(points[i].xyz, 1.0);
    float z = -eye.z;
    if (z <= near) return;
    vec4 clip = projection_matrix * eye;
    ivec2 size = imageSize(depth);
    // pixel coordinates from the top-left corner, centres at +0.5 (the reference's)
    vec2 at = vec2((clip.x / clip.w * 0.5 + 0.5) * float(size.x), (0.5 - clip.y / clip.w * 0.5) * float(size.y));
    float half_side = max(1.0, points[i].w * focal_px / z) * 0.5;
    // the pixels c whose centres c + 0.5 lie in [at − half, at + half)
    ivec2 first = max(ivec2(ceil(at - half_side - 0.5)), ivec2(0));
    ivec2 end = min(ivec2(ceil(at + half_side - 0.5)), size);
    uint bits = floatBitsToUint(z);
    for (int row = first.y; row < end.y; ++row) {
        for (int column = first.x; column < end.x; ++column) {
            ivec2 texel = ivec2(column, size.y - 1 - row);
            uint old = imageLoad(depth, texel).r;
            while (old == 0u || bits < old) {  // nothing there, or farther: ours, unless another came first
                uint was = imageAtomicCompSwap(depth, texel, old, bits);
                if (was == old) break;
                old = was;
            }
        }
    }
}
#endif
