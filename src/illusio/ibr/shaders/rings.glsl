// Hole filling by rings, shared by the first pass's depth and the second pass's hits: a pixel looks
// at the square rings around it, nearest first, up to `radius`, and takes from the first ring that
// holds anything the texel with the largest key (component `key` > 0 means "something there"): the
// farthest depth — where a cut triangle or an occluder uncovered the background, the background goes
// on behind it. Returns vec4(0) when no ring within `radius` holds anything. The first of equal keys
// in ring order wins. NumPy references: ibr.renderer.fill_holes, ibr.renderer.fill_hits.
vec4 farthest_of_nearest_ring(sampler2D s, ivec2 p, int radius, int key) {
    ivec2 size = textureSize(s, 0);
    vec4 best = vec4(0.0);
    for (int r = 1; r <= radius && best[key] <= 0.0; ++r)
        for (int dy = -r; dy <= r; ++dy)
            for (int dx = -r; dx <= r; dx += (abs(dy) == r ? 1 : 2 * r)) {  // the ring only
                ivec2 q = p + ivec2(dx, dy);
                if (q.x >= 0 && q.y >= 0 && q.x < size.x && q.y < size.y) {
                    vec4 n = texelFetch(s, q, 0);
                    if (n[key] > best[key]) best = n;
                }
            }
    return best;
}
