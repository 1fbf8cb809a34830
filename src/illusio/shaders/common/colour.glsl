// Colour helpers shared by passes. Values are linear unless a name says otherwise.
float luminance(vec3 linear_rgb) {
    return dot(linear_rgb, vec3(0.2126, 0.7152, 0.0722));
}
