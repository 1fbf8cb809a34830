#version 430
// The first pass: the reconstruction mesh (world coordinates), then the reference pixels no kept
// triangle covers as points of their footprint, into the new view's linear depth (metres along the
// view axis; cleared to 0 = nothing), with the z-buffer. NumPy reference:
// passes.reference.gbuffer ray-casting the same mesh.
#include "common/camera.glsl"

#if defined(VERTEX_SHADER)
in vec3 in_position;
// points only: the reference pixel's width at its depth (metres), drawn as a square that wide
in float in_footprint;
uniform float focal_px;    // the new view's f_x in pixels
out float view_depth;
void main() {
    vec4 eye = view_matrix * vec4(in_position, 1.0);
    view_depth = -eye.z;
    gl_PointSize = max(1.0, in_footprint * focal_px / max(view_depth, 1e-6));
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
