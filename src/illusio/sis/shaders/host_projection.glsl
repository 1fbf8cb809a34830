#version 430
// Steps (2) and (4) of Figure 22: draw the host surface of the main scene textured with the hidden
// scene's depth image and with the pattern, over the whole host, whatever stands in front of it (an
// occluder must not cut the stereogram's rows: the image behind it continues). Outputs, in screen
// space: D (R32F; the target is cleared to -1 = not host) and the pattern (RGBA8, alpha 1 on the host).
// Layout "viewer" (issue 20, hosts seen at an angle): D is read across depth_box, a rectangle of the
// screen in pixels (x0, y0, x1, y1, GL rows), not through the uvs: the hidden scene keeps its shape
// in the viewer's image, however the host is turned; 1 (far) outside the box.
#include "common/camera.glsl"

uniform mat4 model_matrix;

#if defined(VERTEX_SHADER)
in vec3 in_position;
in vec2 in_uv;
out vec2 surface_uv;
void main() {
    surface_uv = in_uv;
    gl_Position = projection_matrix * view_matrix * model_matrix * vec4(in_position, 1.0);
}
#endif

#if defined(FRAGMENT_SHADER)
uniform sampler2D hidden_depth;   // D of the hidden scene, over the host's uv square
uniform sampler2D pattern;        // the pattern, repeated pattern_repeat times over the host
uniform vec2 pattern_repeat;
uniform vec2 uv_min;              // the host's uv bounds: D and the pattern span them once
uniform vec2 uv_max;
uniform int viewer_layout;        // 1: D across depth_box in screen pixels
uniform vec4 depth_box;
in vec2 surface_uv;
layout(location = 0) out float depth;
layout(location = 1) out vec4 colour;

void main() {
    vec2 uv = (surface_uv - uv_min) / max(uv_max - uv_min, vec2(1e-6));
    if (viewer_layout == 1) {
        vec2 st = (gl_FragCoord.xy - depth_box.xy) / max(depth_box.zw - depth_box.xy, vec2(1e-6));
        depth = all(greaterThanEqual(st, vec2(0.0))) && all(lessThanEqual(st, vec2(1.0))) ? texture(hidden_depth, st).r : 1.0;
    } else {
        depth = texture(hidden_depth, uv).r;
    }
    colour = vec4(texture(pattern, uv * pattern_repeat).rgb, 1.0);
}
#endif
