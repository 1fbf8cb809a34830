#version 430
// Cube shadow map face: distance from the light to the nearest surface, one face of one light per
// draw, into a tile of the shadow atlas (the viewport selects the tile).
uniform mat4 model_matrix;
uniform mat4 face_matrix;   // projection * rotation of this cube face (light at the origin)
uniform vec3 light_position;

#if defined(VERTEX_SHADER)
in vec3 in_position;
out vec3 from_light;
void main() {
    vec3 world = (model_matrix * vec4(in_position, 1.0)).xyz;
    from_light = world - light_position;
    gl_Position = face_matrix * vec4(from_light, 1.0);
}
#endif

#if defined(FRAGMENT_SHADER)
in vec3 from_light;
out float distance_to_light;
void main() {
    distance_to_light = length(from_light);
}
#endif
