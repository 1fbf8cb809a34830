// Shared by the stereogram passes: the separation map, the tiled pattern and each row's start.
// Coordinates are GL pixels (row 0 at the bottom); the pattern is indexed by image rows (row 0 at the
// top) so that it tiles the same way as sis/reference.py.
uniform sampler2D separation_map;   // R32F, pixels between the two pixels of a point
uniform sampler2D pattern;          // the tiled pattern, uploaded with the row flip
uniform isampler2D row_starts;      // (H, 1): first column of each GL row's stereogram; G: one past
                                    // the host's last (0: not given, the image width)
uniform bool use_row_starts;
uniform int image_height;
uniform int image_width;            // of the stereogram (oversampled)
uniform int strip_width;            // W_s, whole pixels
uniform int first_strip;            // W_s + β, whole pixels

int rounded_separation(ivec2 p) {
    return int(floor(texelFetch(separation_map, p, 0).r + 0.5));
}

int row_start(int y) {
    return use_row_starts ? texelFetch(row_starts, ivec2(y, 0), 0).r : 0;
}

int row_end(int y) {
    int end = use_row_starts ? texelFetch(row_starts, ivec2(y, 0), 0).g : 0;
    return end > 0 ? end : image_width;
}

// T[y mod H_T, (x - shift) mod W_T] with y counted from the top of the image. With row starts (a host
// surface in a scene) a column left of the row's start wraps into its first strip instead, and one
// past the row's end (a host row shorter than a strip) wraps back inside [start, end), so the first
// strip only ever shows the pattern projected on the host (sis.reference._texel).
vec4 pattern_texel(int x, int y, int shift) {
    ivec2 size = textureSize(pattern, 0);
    int y_top = image_height - 1 - y;
    int row = size.y - 1 - y_top % size.y;
    int v = x - shift;
    if (use_row_starts) {
        int start = row_start(y);
        if (v < start) v += first_strip;
        int end = row_end(y);
        if (v >= end) v = start + (v - start) % max(end - start, 1);
    }
    if (v < 0) v += size.x * (-v / size.x + 1);  // GLSL's % is undefined for negative operands
    int col = v % size.x;
    return texelFetch(pattern, ivec2(col, row), 0);
}
