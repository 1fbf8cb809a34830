#version 430
// First pass of the hybrid apparent-ridge method (report, section 3.2 and annex B): per vertex, the
// view-dependent curvature operator Q (Judd et al. 2007) from k1 ≤ k2, e1, e2, the normal and the
// view direction; q1 = its largest singular value, scaled by 2^tau / curvature_scale and clamped to
// [0, 1] (the report stores it in an 8-bit colour); t1 = the screen direction of the singular
// vector. Rasterised into a float target (q, t1.x, t1.y, view depth > 0); background (0, 0, 0, 0).
// Differences from annex B, on purpose: q1 is the singular value, not the eigenvalue of QᵀQ the
// report's shader keeps (Judd's definition and the issue's); degenerate directions (view along the
// normal, isotropic points) give t1 = 0 instead of a NaN; the principal directions go through the
// model-view matrix (tangent vectors), the normal through its inverse transpose — annex B sends all
// three through the normal matrix, the same for a rigid camera but not under a scaled model matrix.
// NumPy reference: lines.view_curvature.
#include "common/camera.glsl"

uniform mat4 model_matrix;
uniform float tau;               // τ: scale 2^τ on q1
uniform float curvature_scale;   // 1 for the report's raw q1; the mesh's curvature scale otherwise

#if defined(VERTEX_SHADER)
in vec3 in_position;
in vec3 in_normal;
in vec3 in_e_min;
in vec3 in_e_max;
in vec2 in_k;                    // (k_min, k_max)
out vec4 q_t1;

void main() {
    mat4 model_view = view_matrix * model_matrix;
    vec4 eye = model_view * vec4(in_position, 1.0);
    gl_Position = projection_matrix * eye;
    mat3 normal_matrix = transpose(inverse(mat3(model_view)));
    vec3 n = normalize(normal_matrix * in_normal);
    vec3 e1 = mat3(model_view) * in_e_min;
    vec3 e2 = mat3(model_view) * in_e_max;
    float k1 = in_k.x;
    float k2 = in_k.y;
    vec3 view_dir = normalize(-eye.xyz);
    float ndotv = dot(view_dir, n);
    float u = dot(view_dir, e1);
    float v = dot(view_dir, e2);
    float w2 = u * u + v * v;
    float csc2theta = w2 > 1e-12 ? 1.0 / w2 : 0.0;
    float u2 = u * u * csc2theta;
    float v2 = v * v * csc2theta;
    float uv = u * v * csc2theta;
    float sec_minus_1 = 1.0 / max(abs(ndotv), 1e-4) - 1.0;
    float Q11 = k1 * (1.0 + sec_minus_1 * u2);
    float Q12 = k1 * (sec_minus_1 * uv);
    float Q21 = k2 * (sec_minus_1 * uv);
    float Q22 = k2 * (1.0 + sec_minus_1 * v2);
    float QTQ1 = Q11 * Q11 + Q21 * Q21;
    float QTQ12 = Q11 * Q12 + Q21 * Q22;
    float QTQ2 = Q12 * Q12 + Q22 * Q22;
    float half_diff = 0.5 * (QTQ2 - QTQ1);
    float lambda1 = 0.5 * (QTQ1 + QTQ2) + sqrt(QTQ12 * QTQ12 + half_diff * half_diff);
    // eigenvector of QᵀQ for lambda1: the better conditioned of its two row solutions
    vec2 a = vec2(QTQ2 - lambda1, -QTQ12);
    vec2 b = vec2(-QTQ12, QTQ1 - lambda1);
    vec2 s1 = dot(a, a) >= dot(b, b) ? a : b;
    s1 = dot(s1, s1) > 1e-30 ? normalize(s1) : vec2(QTQ1 >= QTQ2 ? 1.0 : 0.0, QTQ1 >= QTQ2 ? 0.0 : 1.0);
    vec3 w1 = s1.x * e1 + s1.y * e2;
    vec2 t1 = w1.z >= 0.0 ? -w1.xy : w1.xy;
    t1 = dot(t1, t1) > 1e-16 ? normalize(t1) : vec2(0.0);
    float q = clamp(exp2(tau) * sqrt(lambda1) / curvature_scale, 0.0, 1.0);
    q_t1 = vec4(q, t1, -eye.z);
}
#endif

#if defined(FRAGMENT_SHADER)
in vec4 q_t1;
out vec4 out_q_t1;
void main() {
    out_q_t1 = q_t1;
}
#endif
