// Scene surfaces as the G-buffer and forward passes draw them: the vertex stage, and for the fragment
// stage the node's material (passes.gpu_scene.bind_surface sets these uniforms per node).
// TEXTURED 0 compiles the albedo texture fetch out, for nodes without a texture: llvmpipe runs both
// sides of a branch on a uniform, so a fetch skipped by `has_texture` still costs its full price.
#define TEXTURED 1
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

// unit normal facing the viewer (open shapes and the inside of a lamp shade are seen from behind)
vec3 surface_normal() {
    vec3 n = normalize(world_normal);
    return gl_FrontFacing ? n : -n;
}

vec3 surface_albedo() {
#if TEXTURED
    return has_texture ? albedo * texture(albedo_texture, surface_uv).rgb : albedo;
#else
    return albedo;
#endif
}
#endif
