#version 430
// The paper's method (sections 3.1–3.2), second pass: one screen-filling plane at view depth z_i,
// textured with the sharp image's mipmap at the level of the plane's circle of confusion. Drawn far
// to near with depth writes off and the depth test GREATER against the scene's depth, so each
// pixel keeps the nearest plane still behind its surface. With DEPTH_FROM_LINEAR, the first pass's
// helper instead: write the scene's linear depth (0 = nothing: the far plane) as window depth.
#include "common/fullscreen.glsl"

#ifndef DEPTH_FROM_LINEAR
#define DEPTH_FROM_LINEAR 0
#endif

#if defined(FRAGMENT_SHADER)
uniform sampler2D image;        // mipmapped sharp colour
uniform sampler2D linear_depth; // DEPTH_FROM_LINEAR: metres, 0 = nothing
uniform float plane_depth;      // window depth of this plane, [0, 1]
uniform float lod;              // log2(max(c_i, 1))
uniform vec2 depth_map;         // window depth of z: a + b / z (from the projection)
in vec2 uv;
out vec4 colour;

void main() {
#if DEPTH_FROM_LINEAR
    float z = texelFetch(linear_depth, ivec2(gl_FragCoord.xy), 0).r;
    // nothing there: just short of the far plane, so the farthest plane (at the far plane) covers it
    gl_FragDepth = z > 0.0 ? depth_map.x + depth_map.y / z : 0.99999;
    colour = vec4(0.0);
#else
    gl_FragDepth = plane_depth;
    colour = vec4(textureLod(image, uv, lod).rgb, 1.0);
#endif
}
#endif
