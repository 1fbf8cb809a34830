// Visibility of a world point from a light through the cube shadow atlas written by shadow.glsl.
// Atlas layout: column = cube face (0..5: +x -x +y -y +z -z), row = shadow index of the light.
uniform sampler2D shadow_atlas;
uniform mat4 shadow_face_matrices[6];
uniform int shadow_rows;
uniform float shadow_tile_size;   // pixels per tile side

int cube_face(vec3 d) {
    vec3 a = abs(d);
    if (a.x >= a.y && a.x >= a.z) return d.x > 0.0 ? 0 : 1;
    if (a.y >= a.z) return d.y > 0.0 ? 2 : 3;
    return d.z > 0.0 ? 4 : 5;
}

// 1 = lit, 0 = shadowed; 3x3 percentage-closer filtering inside the tile.
float light_visibility(vec3 world, vec3 normal, vec3 light, int row) {
    vec3 d = world - light;
    float dist = length(d);
    int face = cube_face(d);
    vec4 clip = shadow_face_matrices[face] * vec4(d, 1.0);
    vec2 uv = clip.xy / clip.w * 0.5 + 0.5;
    float texel = 1.0 / shadow_tile_size;
    // bias grows with distance and with grazing angles
    float slope = 1.0 - abs(dot(normal, d / max(dist, 1e-6)));
    float bias = 0.01 + dist * (0.004 + 0.02 * slope) * 512.0 / shadow_tile_size;
    float lit = 0.0;
    for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
            vec2 t = clamp(uv + vec2(dx, dy) * texel, vec2(0.5 * texel), vec2(1.0 - 0.5 * texel));
            vec2 atlas = vec2((float(face) + t.x) / 6.0, (float(row) + t.y) / float(shadow_rows));
            lit += (texture(shadow_atlas, atlas).r + bias >= dist) ? 1.0 : 0.0;
        }
    }
    return lit / 9.0;
}
