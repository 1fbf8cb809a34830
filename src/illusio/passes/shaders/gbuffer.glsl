#version 430
// G-buffer: one geometry pass writing every per-pixel attribute later passes need.
// Attachments: 0 colour (albedo rgb, specular k_s), 1 linear depth (metres along the view axis),
// 2 normal (world, unit, facing the viewer; a = Phong exponent), 3 world position (a = 1 where hit),
// 4 object id (node index + 1 as float; 0 = background), 5 emission (rgb).
#include "common/camera.glsl"

uniform mat4 model_matrix;
uniform mat3 normal_matrix;

#if defined(VERTEX_SHADER)
in vec3 in_position;
in vec3 in_normal;
in vec2 in_uv;
out vec3 world_position;
out vec3 world_normal;
out vec2 surface_uv;
out float view_depth;
void main() {
    vec4 world = model_matrix * vec4(in_position, 1.0);
    vec4 eye = view_matrix * world;
    world_position = world.xyz;
    world_normal = normal_matrix * in_normal;
    surface_uv = in_uv;
    view_depth = -eye.z;
    gl_Position = projection_matrix * eye;
}
#endif

#if defined(FRAGMENT_SHADER)
uniform vec3 albedo;
uniform float specular;
uniform float shininess;
uniform vec3 emission;
uniform float object_id;
uniform bool has_texture;
uniform sampler2D albedo_texture;

in vec3 world_position;
in vec3 world_normal;
in vec2 surface_uv;
in float view_depth;

layout(location = 0) out vec4 out_colour;
layout(location = 1) out float out_depth;
layout(location = 2) out vec4 out_normal;
layout(location = 3) out vec4 out_position;
layout(location = 4) out float out_id;
layout(location = 5) out vec4 out_emission;

void main() {
    vec3 n = normalize(world_normal);
    if (!gl_FrontFacing) n = -n;  // seen from behind (open shapes, inside a lamp shade)
    vec3 colour = albedo;
    if (has_texture) colour *= texture(albedo_texture, surface_uv).rgb;
    out_colour = vec4(colour, specular);
    out_depth = view_depth;
    out_normal = vec4(n, shininess);
    out_position = vec4(world_position, 1.0);
    out_id = object_id;
    out_emission = vec4(emission, 1.0);
}
#endif
