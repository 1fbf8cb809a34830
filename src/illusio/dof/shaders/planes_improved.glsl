#version 430
// The improved planes method, second step: the slabs' layers composited far to near. At a pixel,
// its own slab's layer is read at the level of the pixel's own circle of confusion (no banding: the
// blur follows the depth, not the plane's), every other layer at its slab's largest circle (how far
// that slab's blur spills). A layer's blurred coverage (alpha) lays it over the layers behind, and
// its colour is normalised by its own coverage, searched up the levels until half covered (a hole
// left by a nearer object is filled from around it) — so a sharp foreground no longer leaks into a
// blurred background, which never held its colours. Composited front to back with an early stop.
// NumPy reference: dof.reference.planes_improved.
#include "common/fullscreen.glsl"
#define MAX_PLANES 64

#if defined(FRAGMENT_SHADER)
uniform sampler2DArray layers;   // premultiplied, mipmapped
uniform sampler2D coc;           // pixels
uniform sampler2D linear_depth;  // metres, 0 = nothing
uniform float distances[MAX_PLANES];  // far to near
uniform float lods[MAX_PLANES];  // each slab's spill level
uniform float present[MAX_PLANES];  // 1 for a slab with pixels (read from the top mipmap level)
uniform int count;
uniform float max_level;
in vec2 uv;
out vec4 colour;

vec3 filled(int k, float lod, vec4 first) {
    vec4 c = first;  // the lookup at lod itself, done by the caller
    if (c.a >= 0.5 || lod >= max_level) return c.rgb / max(c.a, 1e-6);
    for (int j = 1; j < 16; ++j) {
        float level = min(lod + float(j), max_level);
        c = textureLod(layers, vec3(uv, float(k)), level);
        if (c.a >= 0.5 || level >= max_level) break;
    }
    return c.rgb / max(c.a, 1e-6);
}

int slab_of(float z) {
    if (z <= 0.0) return 0;
    for (int k = count - 1; k >= 0; --k) {
        if (distances[k] > z) return k;
    }
    return 0;
}

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    int own = slab_of(texelFetch(linear_depth, p, 0).r);
    float own_lod = log2(max(texelFetch(coc, p, 0).r, 1.0));
    // front to back, each layer over what is behind by its coverage; stop once nothing shows
    // through; then divide by the coverage gathered, so that where neighbouring slabs' coverages at
    // their own levels leave a gap (a surface crossing from one slab to the next) no other colour
    // creeps in. Nothing at all (every coverage 0): the farthest layer with pixels, filled.
    int farthest = 0;
    while (farthest < count - 1 && present[farthest] <= 0.0) ++farthest;
    vec3 result = vec3(0.0);
    float through = 1.0;  // what still shows through the nearer layers
    for (int k = count - 1; k >= farthest && through > 1.0 / 1024.0; --k) {
        if (present[k] <= 0.0) continue;  // an empty slab
        float lod = k == own ? own_lod : lods[k];
        vec4 c = textureLod(layers, vec3(uv, float(k)), lod);
        float coverage = clamp(c.a, 0.0, 1.0);
        if (coverage <= 0.0) continue;  // lays nothing here: spare the colour lookups
        result += through * coverage * filled(k, lod, c);
        through *= 1.0 - coverage;
    }
    if (through >= 1.0) {
        float lod = farthest == own ? own_lod : lods[farthest];
        result = filled(farthest, lod, textureLod(layers, vec3(uv, float(farthest)), lod));
    } else {
        result /= 1.0 - through;
    }
    colour = vec4(result, 1.0);
}
#endif
