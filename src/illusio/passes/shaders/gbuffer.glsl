#version 430
// G-buffer: one geometry pass writing every per-pixel attribute later passes need.
// Attachments: shaders/common/gbuffer_outputs.glsl.
#include "surface.glsl"

#if defined(FRAGMENT_SHADER)
#include "common/gbuffer_outputs.glsl"

void main() {
    out_colour = vec4(surface_albedo(), specular);
    out_depth = view_depth;
    out_normal = vec4(surface_normal(), shininess);
    out_position = vec4(world_position, 1.0);
    out_id = object_id;
    out_emission = vec4(emission, 1.0);
}
#endif
