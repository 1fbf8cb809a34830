#version 430
// The sampled gather: the depth-aware gather of gather.glsl estimated from `taps` points instead of
// every pixel of the square. The points fill a disk of radius R (the tile's largest covering radius,
// coc_tiles.glsl) on Vogel's golden-angle spiral (the same pattern at every pixel), each standing
// for an area a = π R² / taps, spacing s = √max(a, 1). A point q adds its colour with weight
// cover · a / (π r_q²), cover = clamp((r_q − |q − p|) / s + ½, 0, 1) (q's circle over the point's
// share of the disk), under the gather's depth rule; p itself adds its own with weight 1 / (π r_p²).
// A point's colour is the texel under it at the mipmap level round(log2 s) (at most the last), the mean of the pixels
// it stands for, so the sparse points do not alias. NumPy reference: dof.reference.gather_taps.
#include "common/fullscreen.glsl"

#if defined(FRAGMENT_SHADER)
#include "gather_rule.glsl"
uniform sampler2D tiles;       // .r: the covering radius R of each tile, pixels
uniform int tile;              // pixels per tile side
uniform int taps;
uniform vec2 spiral[128];      // the unit disk's points (reference.disk_spiral)

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    ivec2 size = textureSize(image, 0);
    float zp = far_depth(p);
    float rp = covering_radius(p);
    float w = 1.0 / (PI * rp * rp);
    vec3 sum = w * texelFetch(image, p, 0).rgb;
    float total = w;
    float radius = texelFetch(tiles, p / tile, 0).r;
    float area = PI * radius * radius / float(taps);
    float spacing = sqrt(max(area, 1.0));
    int level = min(int(floor(log2(spacing) + 0.5)), textureQueryLevels(image) - 1);
    ivec2 last = textureSize(image, level) - 1;
    for (int k = 0; k < taps; ++k) {
        vec2 offset = radius * spiral[k];
        vec2 q = gl_FragCoord.xy + offset;
        if (q.x < 0.0 || q.y < 0.0 || q.x >= float(size.x) || q.y >= float(size.y)) continue;
        ivec2 qi = ivec2(q);
        float dist = length(offset);
        float rq = covering_radius(qi);
        float cover = clamp((rq - dist) / spacing + 0.5, 0.0, 1.0);
        if (cover <= 0.0) continue;
        if (hidden(far_depth(qi), zp, dist, rp)) continue;
        float wq = cover * area / (PI * rq * rq);
        sum += wq * texelFetch(image, min(qi >> level, last), level).rgb;
        total += wq;
    }
    colour = vec4(sum / total, 1.0);
}
#endif
