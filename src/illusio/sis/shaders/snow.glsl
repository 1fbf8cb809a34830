#version 430
// TV "snow": grey dots from a hash of (x, y, frame, seed), the same as sis.patterns.snow.
#include "common/fullscreen.glsl"

#if defined(FRAGMENT_SHADER)
uniform uint seed;
uniform uint frame;
uniform int dot_size;
uniform int image_height;
uniform int oversample;
out vec4 colour;

uint hash32(uint x) {  // Wellons' lowbias32
    x ^= x >> 16; x *= 0x7feb352du; x ^= x >> 15; x *= 0x846ca68bu; x ^= x >> 16;
    return x;
}

void main() {
    int x = int(gl_FragCoord.x) / oversample;
    int y = image_height - 1 - int(gl_FragCoord.y);
    uint key = hash32(uint(x / dot_size));
    key = hash32(key ^ uint(y / dot_size));
    key = hash32(key ^ frame);
    key = hash32(key ^ seed);
    float v = float(key >> 8) / 16777216.0;
    colour = vec4(v, v, v, 1.0);
}
#endif
