#version 430
// Depth pre-pass of the forward path: the scene's surfaces into the depth buffer only, so the
// shading pass that follows lights each pixel once (equal depth) instead of every overdrawn fragment.
#include "surface.glsl"

#if defined(FRAGMENT_SHADER)
void main() {}
#endif
