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
uniform sampler2D albedo_texture;  // rgb: albedo; alpha: opacity (1 without an alpha mask)
uniform float alpha_cutoff;        // glTF's alpha mask: texels less opaque are cut away (0: opaque)

in vec3 world_position;
in vec3 world_normal;
in vec2 surface_uv;
in float view_depth;

// unit normal facing the viewer (open shapes and the inside of a lamp shade are seen from behind)
vec3 surface_normal() {
    vec3 n = normalize(world_normal);
    return gl_FrontFacing ? n : -n;
}

// the albedo, discarding the fragment where the alpha mask cuts the surface away
vec3 surface_albedo() {
#if TEXTURED
    if (!has_texture) return albedo;
    vec4 texel = texture(albedo_texture, surface_uv);
    if (texel.a < alpha_cutoff) discard;
    return albedo * texel.rgb;
#else
    return albedo;
#endif
}
#endif
