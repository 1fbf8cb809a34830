// Camera uniforms shared by passes that draw geometry. Matrices are column-major, column vectors.
uniform mat4 view_matrix;        // world -> camera (camera looks down -z)
uniform mat4 projection_matrix;  // camera -> clip
uniform vec3 camera_position;    // world position of the eye, metres
