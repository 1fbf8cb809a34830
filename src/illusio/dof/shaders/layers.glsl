#version 430
// The improved planes method, first step: the sharp image split into one layer per plane slab (the
// pixels that take that plane in the paper's method: the nearest plane behind them; nothing there:
// the farthest), premultiplied: layer k holds (rgb, 1) on its slab and 0 elsewhere. NumPy
// reference: dof.reference.planes_improved.
#define MAX_PLANES 64

#if defined(COMPUTE_SHADER)
layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba16f, binding = 0) uniform writeonly image2DArray layers;
uniform sampler2D image;
uniform sampler2D linear_depth;   // metres, 0 = nothing
uniform float distances[MAX_PLANES];  // far to near
uniform int count;
layout(std430, binding = 1) buffer Present { uint present[]; };  // 1 for each slab with a pixel
shared uint seen[MAX_PLANES];

void main() {
    uint local = gl_LocalInvocationIndex;
    if (local < uint(MAX_PLANES)) seen[local] = 0u;
    barrier();
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = textureSize(image, 0);
    bool inside = p.x < size.x && p.y < size.y;
    if (inside) {
    float z = texelFetch(linear_depth, p, 0).r;
    int slab = 0;
    if (z > 0.0) {
        for (int k = count - 1; k >= 0; --k) {   // the nearest plane behind the surface
            if (distances[k] > z) { slab = k; break; }
        }
    }
    vec3 colour = texelFetch(image, p, 0).rgb;
    for (int k = 0; k < count; ++k) {
        imageStore(layers, ivec3(p, k), k == slab ? vec4(colour, 1.0) : vec4(0.0));
    }
    atomicOr(seen[slab], 1u);
    }
    barrier();
    if (local < uint(count) && seen[local] != 0u) atomicOr(present[local], 1u);  // one write a group
}
#endif
