#version 430
// Depth pre-pass of the forward path: the scene's surfaces into the depth buffer only, so the
// shading pass that follows lights each pixel once (equal depth) instead of every overdrawn fragment.
#include "surface.glsl"

// ALPHA_MASK 1: for nodes with an alpha mask, cut where the shading pass will (surface_albedo)
#define ALPHA_MASK 0

#if defined(FRAGMENT_SHADER)
void main() {
#if ALPHA_MASK
    surface_albedo();
#endif
}
#endif
