#version 430
// Stereo composites of a left and a right image of the same size W×H (NumPy reference:
// passes.reference.stereo_composite). Layouts place the images side by side (2W×H; cross-eyed puts
// the right image on the left), or top (left) over bottom (right) (W×2H). Anaglyphs (W×H) mix the
// two per pixel with 3×3 matrices on linear RGB: Dubois's least-squares red-cyan matrices, or the
// colour / half-colour / grey schemes expressed as matrices; the result is clamped to [0, 1].
#include "common/fullscreen.glsl"

#if defined(FRAGMENT_SHADER)
uniform sampler2D left_image;
uniform sampler2D right_image;
uniform int layout_mode;      // 0 anaglyph, 1 side by side, 2 cross-eyed, 3 top-bottom
uniform mat3 left_matrix;     // anaglyph: out = L·left + R·right
uniform mat3 right_matrix;
out vec4 colour;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    ivec2 size = textureSize(left_image, 0);
    if (layout_mode == 0) {
        vec3 l = texelFetch(left_image, p, 0).rgb;
        vec3 r = texelFetch(right_image, p, 0).rgb;
        colour = vec4(clamp(left_matrix * l + right_matrix * r, 0.0, 1.0), 1.0);
        return;
    }
    if (layout_mode == 3) {  // GL rows count from the bottom: the left image is the top half
        bool top = p.y >= size.y;
        ivec2 q = ivec2(p.x, top ? p.y - size.y : p.y);
        colour = vec4(top ? texelFetch(left_image, q, 0).rgb : texelFetch(right_image, q, 0).rgb, 1.0);
        return;
    }
    bool first = p.x < size.x;
    ivec2 q = ivec2(first ? p.x : p.x - size.x, p.y);
    bool show_left = (layout_mode == 1) == first;
    colour = vec4(show_left ? texelFetch(left_image, q, 0).rgb : texelFetch(right_image, q, 0).rgb, 1.0);
}
#endif
