// Vertex stage of the shared full-screen triangle: three vertices from gl_VertexID, no buffers.
// uv runs 0..1 over the viewport, (0, 0) at the bottom left (GL convention).
#if defined(VERTEX_SHADER)
out vec2 uv;
void main() {
    vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    uv = corner;
    gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
}
#endif
