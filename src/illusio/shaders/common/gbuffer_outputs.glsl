// The G-buffer's attachments, written by the rasteriser's geometry pass (passes/shaders/gbuffer.glsl)
// and by image-based rendering's selection pass (ibr/shaders/select.glsl) in the same layout:
// 0 colour (albedo rgb, specular k_s), 1 linear depth (metres along the view axis),
// 2 normal (world, unit, facing the viewer; a = Phong exponent), 3 world position (a = 1 where hit),
// 4 object id (node index + 1 as float; 0 = background), 5 emission (rgb).
layout(location = 0) out vec4 out_colour;
layout(location = 1) out float out_depth;
layout(location = 2) out vec4 out_normal;
layout(location = 3) out vec4 out_position;
layout(location = 4) out float out_id;
layout(location = 5) out vec4 out_emission;
