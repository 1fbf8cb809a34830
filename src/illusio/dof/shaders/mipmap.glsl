#version 430
// The mipmap method (section 2.2.3): each pixel reads the sharp image's mipmap at the level of its
// circle of confusion, lod = log2(max(c, 1)) (level L averages 2^L × 2^L pixels), trilinear.
// NumPy reference: dof.reference.mipmap.
#include "common/fullscreen.glsl"

#if defined(FRAGMENT_SHADER)
uniform sampler2D image;   // with mipmaps, LINEAR_MIPMAP_LINEAR
uniform sampler2D coc;     // .r: pixels
in vec2 uv;
out vec4 colour;

void main() {
    float c = texelFetch(coc, ivec2(gl_FragCoord.xy), 0).r;
    colour = vec4(textureLod(image, uv, log2(max(c, 1.0))).rgb, 1.0);
}
#endif
