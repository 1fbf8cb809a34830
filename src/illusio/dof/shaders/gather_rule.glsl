// What the gathers (gather.glsl, gather_taps.glsl) share: their common inputs, a pixel's depth and
// covering radius, and the depth rule. Included inside their FRAGMENT_SHADER sections.

uniform sampler2D image;       // linear colour (gather_taps: with mipmaps)
uniform sampler2D coc;         // .r: circle of confusion, pixels
uniform sampler2D depth;       // .r: metres, 0 = nothing (infinitely far)
uniform float depth_slack;     // relative depth within which a neighbour is level with a pixel
out vec4 colour;

const float PI = 3.14159265;

// metres, nothing there (0) infinitely far
float far_depth(ivec2 q) {
    float d = texelFetch(depth, q, 0).r;
    return d > 0.0 ? d : 1e30;
}

// r_q = max(c_q / 2, 1/2), pixels
float covering_radius(ivec2 q) { return max(texelFetch(coc, q, 0).r * 0.5, 0.5); }

// a q behind p (beyond the slack) outside p's own circle gives p nothing
bool hidden(float zq, float zp, float dist, float rp) { return zq > zp * (1.0 + depth_slack) && dist > rp; }
