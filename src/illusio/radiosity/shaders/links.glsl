#version 430
// Links drawn as lines from the receiver's centre to each source's centre, coloured by type.
#if defined(VERTEX_SHADER)
uniform mat4 view_matrix;
uniform mat4 projection_matrix;
in vec3 in_position;
in vec3 in_colour;
out vec3 colour;
void main() {
    colour = in_colour;
    gl_Position = projection_matrix * view_matrix * vec4(in_position, 1.0);
}
#endif

#if defined(FRAGMENT_SHADER)
in vec3 colour;
layout(location = 0) out vec4 out_colour;
void main() { out_colour = vec4(colour, 1.0); }
#endif
