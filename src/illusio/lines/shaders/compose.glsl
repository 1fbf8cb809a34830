#version 430
// The drawing's base: white paper, the hybrid apparent ridges (ridge filter output) and the
// image-space silhouettes (covered pixels with an uncovered 4-neighbour or a depth jump larger than
// depth_jump × depth), each in its colour. Linear RGB out. NumPy reference: lines.reference.compose.
#include "common/fullscreen.glsl"

#if defined(FRAGMENT_SHADER)
uniform sampler2D q_t1;          // .a: view depth, 0 = background
uniform sampler2D ridges;        // .r: 1 on a ridge
uniform bool show_ridges;
uniform bool show_silhouettes;
uniform vec3 ridge_colour;
uniform vec3 silhouette_colour;
uniform float depth_jump;
out vec4 colour;

bool silhouette(ivec2 p) {
    ivec2 size = textureSize(q_t1, 0);
    float d = texelFetch(q_t1, p, 0).a;
    if (d <= 0.0) return false;
    ivec2 n[4] = ivec2[](ivec2(1, 0), ivec2(-1, 0), ivec2(0, 1), ivec2(0, -1));
    for (int i = 0; i < 4; ++i) {
        float e = texelFetch(q_t1, clamp(p + n[i], ivec2(0), size - 1), 0).a;
        if (e <= 0.0 || e - d > depth_jump * d) return true;  // the nearer side of a jump draws it
    }
    return false;
}

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec3 c = vec3(1.0);
    if (show_ridges && texelFetch(ridges, p, 0).r > 0.5) c = ridge_colour;
    if (show_silhouettes && silhouette(p)) c = silhouette_colour;
    colour = vec4(c, 1.0);
}
#endif
