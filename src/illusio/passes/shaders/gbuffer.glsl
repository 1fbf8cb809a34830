#version 430
// G-buffer: one geometry pass writing every per-pixel attribute later passes need.
// Attachments: 0 colour (albedo rgb, specular k_s), 1 linear depth (metres along the view axis),
// 2 normal (world, unit, facing the viewer; a = Phong exponent), 3 world position (a = 1 where hit),
// 4 object id (node index + 1 as float; 0 = background), 5 emission (rgb).
#include "surface.glsl"

#if defined(FRAGMENT_SHADER)
layout(location = 0) out vec4 out_colour;
layout(location = 1) out float out_depth;
layout(location = 2) out vec4 out_normal;
layout(location = 3) out vec4 out_position;
layout(location = 4) out float out_id;
layout(location = 5) out vec4 out_emission;

void main() {
    out_colour = vec4(surface_albedo(), specular);
    out_depth = view_depth;
    out_normal = vec4(surface_normal(), shininess);
    out_position = vec4(world_position, 1.0);
    out_id = object_id;
    out_emission = vec4(emission, 1.0);
}
#endif
