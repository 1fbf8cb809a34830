#version 430
// Adds weight × a view into the accumulation target (additive blending is set by the pass): the
// accumulation method's average of the views through N points of the lens.
#include "common/fullscreen.glsl"

#if defined(FRAGMENT_SHADER)
uniform sampler2D image;
uniform float weight;
out vec4 colour;

void main() {
    colour = vec4(texelFetch(image, ivec2(gl_FragCoord.xy), 0).rgb * weight, weight);
}
#endif
