#version 430
// The displayed radiosity modulated by the surfaces' textures (as Loscos's chapter modulates by the
// photograph's): each pixel's radiance times albedo / flat, where albedo is the G-buffer's textured
// colour there and flat the colour × texture mean its node's polygons were solved with. Untextured
// nodes have albedo = flat: unchanged. NumPy reference: radiosity.texture_modulation.modulate.
#include "common/fullscreen.glsl"

#if defined(FRAGMENT_SHADER)
uniform sampler2D radiance;
uniform sampler2D albedo;     // G-buffer colour: material colour × texture, rgb
uniform sampler2D object_id;  // G-buffer object id: node index + 1, 0 = nothing
uniform sampler2D flat_albedo; // (nodes + 1) × 1: each node's colour × its texture's mean
out vec4 colour;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 c = texelFetch(radiance, p, 0);
    int id = int(texelFetch(object_id, p, 0).r + 0.5);
    vec3 flat_colour = texelFetch(flat_albedo, ivec2(id, 0), 0).rgb;
    vec3 textured = texelFetch(albedo, p, 0).rgb;
    vec3 ratio = vec3(1.0);
    for (int k = 0; k < 3; ++k) {
        if (id > 0 && flat_colour[k] > 1e-6) ratio[k] = textured[k] / flat_colour[k];
    }
    colour = vec4(c.rgb * ratio, c.a);
}
#endif
