#version 430
// The first pass: the reconstruction mesh (world coordinates) into the new view's linear depth
// (metres along the view axis; cleared to 0 = nothing), with the z-buffer; the reference pixels no
// kept triangle covers follow as points (points.glsl). NumPy reference: passes.reference.gbuffer
// ray-casting the same mesh.
#include "common/camera.glsl"

#if defined(VERTEX_SHADER)
in vec3 in_position;
out float view_depth;
void main() {
    vec4 eye = view_matrix * vec4(in_position, 1.0);
    view_depth = -eye.z;
    gl_Position = projection_matrix * eye;
}
#endif

#if defined(FRAGMENT_SHADER)
in float view_depth;
out float depth;
void main() {
    depth = view_depth;
}
#endif
