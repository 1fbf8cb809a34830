#version 430
// The viewer's display pass: one image into the bound viewport, as colour (RGB as it is) or as a
// depth map (D in .r, 0 = near shown white, 1 = far black, negative = no surface, black), and sRGB
// encoded for the window when `encode_srgb` is set (offscreen frames stay linear: files encode).
#include "common/fullscreen.glsl"

#if defined(FRAGMENT_SHADER)
uniform sampler2D image;
uniform bool as_depth;
uniform float grey_scale;       // > 0: show .r × grey_scale in grey (a circle-of-confusion map)
uniform bool encode_srgb;
in vec2 uv;
out vec4 colour;

vec3 linear_to_srgb(vec3 c) {
    c = clamp(c, 0.0, 1.0);
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}

void main() {
    vec4 texel = texture(image, uv);
    vec3 c = as_depth ? vec3(texel.r < 0.0 ? 0.0 : 1.0 - clamp(texel.r, 0.0, 1.0)) : texel.rgb;
    if (grey_scale > 0.0) c = vec3(clamp(texel.r * grey_scale, 0.0, 1.0));
    colour = vec4(encode_srgb ? linear_to_srgb(c) : clamp(c, 0.0, 1.0), 1.0);
}
#endif
