#version 430
// The radiosity solution drawn as its leaf elements: each vertex carries B/π (radiance, W/(m²·sr)),
// interpolated across the element (Gouraud, the chapter's display). With EDGES, a leaf's outline is
// drawn in `edge_colour` (the element mesh of Loscos Figure 4.6): `in_corner` holds the vertex's
// place in its element — (u, v, 0) on a quad, (u, v, 1) on a triangle — so the distance to the
// nearest edge is known in the fragment shader.
#define EDGES 0

#if defined(VERTEX_SHADER)
uniform mat4 view_matrix;
uniform mat4 projection_matrix;
in vec3 in_position;
in vec3 in_radiance;
in vec3 in_corner;
in float in_element;
in float in_two_sided;
out vec3 radiance;
out vec3 corner;
flat out int element;
flat out int two_sided;
void main() {
    two_sided = int(in_two_sided + 0.5);
    radiance = in_radiance;
    corner = in_corner;
    element = int(in_element);
    gl_Position = projection_matrix * view_matrix * vec4(in_position, 1.0);
}
#endif

#if defined(FRAGMENT_SHADER)
uniform float exposure;
uniform vec3 edge_colour;
in vec3 radiance;
in vec3 corner;
flat in int element;
flat in int two_sided;
layout(location = 0) out vec4 out_colour;
layout(location = 1) out float out_element;
void main() {
    // one side of a two-sided surface, seen from behind: its twin, facing the other way at the same
    // place, shows that side
    if (two_sided == 1 && !gl_FrontFacing) discard;
    vec3 colour = exposure * radiance;
#if EDGES
    vec2 uv = corner.xy;
    float d = corner.z > 0.5 ? min(min(uv.x, uv.y), 1.0 - uv.x - uv.y)
                             : min(min(uv.x, 1.0 - uv.x), min(uv.y, 1.0 - uv.y));
    float width = fwidth(d);
    colour = mix(edge_colour, colour, smoothstep(0.5 * width, 1.5 * width, d));
#endif
    out_colour = vec4(colour, 1.0);
    out_element = float(element);
}
#endif
