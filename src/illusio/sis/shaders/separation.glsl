#version 430
// The separation map of a depth map (see depth_to_separation.glsl), one pixel per fragment.
#include "common/fullscreen.glsl"

#if defined(FRAGMENT_SHADER)
#include "depth_to_separation.glsl"
out float separation;

void main() {
    separation = separation_at(int(gl_FragCoord.x), int(gl_FragCoord.y));
}
#endif
