#version 430
// Cube shadow map face: distance from the light to the nearest surface, one face of one light per
// draw, into a tile of the shadow atlas (the viewport selects the tile).
uniform mat4 model_matrix;
uniform mat4 face_matrix;   // projection * rotation of this cube face (light at the origin)
uniform vec3 light_position;
// ALPHA_MASK 1: for nodes with an alpha mask (their texture's alpha), texels below the cutoff cast
// no shadow, as surface.glsl cuts them from the image
#define ALPHA_MASK 0

#if defined(VERTEX_SHADER)
in vec3 in_position;
out vec3 from_light;
#if ALPHA_MASK
in vec2 in_uv;
out vec2 surface_uv;
#endif
void main() {
#if ALPHA_MASK
    surface_uv = in_uv;
#endif
    vec3 world = (model_matrix * vec4(in_position, 1.0)).xyz;
    from_light = world - light_position;
    gl_Position = face_matrix * vec4(from_light, 1.0);
}
#endif

#if defined(FRAGMENT_SHADER)
in vec3 from_light;
out float distance_to_light;
#if ALPHA_MASK
uniform sampler2D albedo_texture;
uniform float alpha_cutoff;
in vec2 surface_uv;
#endif
void main() {
#if ALPHA_MASK
    if (texture(albedo_texture, surface_uv).a < alpha_cutoff) discard;
#endif
    distance_to_light = length(from_light);
}
#endif
