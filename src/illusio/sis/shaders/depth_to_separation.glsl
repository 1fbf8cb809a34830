// Depth -> separation, pixels (sis.reference.separation), shared by the separation pass and the fused
// fast pass. Linear: s = W_s + β·D. Exact: f' linear in D between f'_min and f'_max, then equation (3)
// s = e_p·f' / (f + f'). With oversampling the depth is interpolated between pixel centres and the
// separation scaled by the factor. Negative depth marks pixels off the host: the far separation.
uniform sampler2D depth_map;     // R32F, D in [0, 1], 0 = near; < 0 = not on the host
uniform float strip_width_px;    // W_s
uniform float depth_factor;      // β
uniform bool invert;
uniform bool exact;
uniform float near_cm;           // f'_min
uniform float far_cm;            // f'_max
uniform float eye_separation_px; // e_p
uniform float viewing_distance_cm;  // f
uniform int oversample;

float separation_from_depth(float d, float n) {
    if (d < 0.0) return (strip_width_px + depth_factor) * n;
    if (invert) d = 1.0 - d;
    if (exact) {
        float f_prime = near_cm + d * (far_cm - near_cm);
        return eye_separation_px * f_prime / (viewing_distance_cm + f_prime) * n;
    }
    return (strip_width_px + depth_factor * d) * n;
}

float separation_at(int x, int y) {
    if (oversample == 1) return separation_from_depth(texelFetch(depth_map, ivec2(x, y), 0).r, 1.0);
    int width = textureSize(depth_map, 0).x;
    float n = float(oversample);
    float pos = clamp((float(x) + 0.5) / n - 0.5, 0.0, float(width - 1));
    int i0 = int(floor(pos));
    int i1 = min(i0 + 1, width - 1);
    float t = pos - float(i0);
    float d0 = texelFetch(depth_map, ivec2(i0, y), 0).r;
    float d1 = texelFetch(depth_map, ivec2(i1, y), 0).r;
    if (d0 < 0.0 || d1 < 0.0) return separation_from_depth(-1.0, n);
    return separation_from_depth(d0 * (1.0 - t) + d1 * t, n);
}
